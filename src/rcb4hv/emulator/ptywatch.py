"""A pty server for clients that reconfigure the port around every read (``emulate-ics``).

Every ``tcsetattr`` that asks for even parity on a pty must change ``c_cflag`` or glibc fails
it with EINVAL (see :mod:`rcb4hv.emulator.server`), so :class:`~rcb4hv.emulator.server.PtyServer`
keeps its slave *armed*. iory/rcb4's ``ics.py`` sets ``timeout`` before and after every read:
two ``tcsetattr`` calls per command, about 2 ms apart (the command's wire time + 2 ms), and the
slave must be armed again before each. An arming done only when the command's bytes arrive is
too late for the first (a pty hands bytes to the master through a kernel work queue, which a
busy machine delays), and nothing arms it between the two.

:class:`WatchingPtyServer` is told of every ``tcsetattr`` on the slave as it happens: the
master runs in packet mode (``TIOCPKT``) and the slave carries ``EXTPROC``, with which the
kernel's pty driver reports each termios change to the master as a ``TIOCPKT_IOCTL`` status
packet. The server re-arms at once (safe even inside the client's call: each arming writes the
other sentinel speed), and holds each reply until the client has reconfigured after sending its
command (or for ``reply_gate_s``, for clients that never do), so the reconfigure that follows
the read finds the slave armed; and it stops the slave's output from the reply until the
reconfigure after the read has been re-armed, so the client's next command (and the
reconfigure after it) waits for that. Its thread asks for the lowest real-time priority where
that is allowed, so re-arming does not wait for a CPU.
"""

from __future__ import annotations

import logging
import os
import termios
import time
from typing import Final

from rcb4hv.emulator.server import (
    TIOCPKT_DATA,
    TIOCPKT_IOCTL,
    PtyServer,
    Served,
    fine_timer_slack,
)

__all__ = ["WatchingPtyServer"]

log = logging.getLogger(__name__)

# A client seen reconfiguring between command and reply always does (rcb4's synchronize):
# hold its replies until it has, however long a busy machine makes it take.
LEARNED_GATE_S: Final = 1.0
# After this many gates in a row ran out with no reconfigure, the client is taken not to
# reconfigure (our own client; pyserial with the timeout set once): its answers go at once.
PLAIN_AFTER: Final = 2
# Mid-command the slave's output is never stopped longer than this (a client that went away).
FLOW_SAFETY_S: Final = 2.0


class WatchingPtyServer(PtyServer):
    """A :class:`PtyServer` that re-arms on every client ``tcsetattr`` and gates replies."""

    name = "rcb4hv-emulator-pty-watch"

    def __init__(self, board: Served, *, reply_gate_s: float) -> None:
        super().__init__(board)  # the master in packet mode, EXTPROC armed on the slave
        if not self._packet:
            self.stop()
            raise OSError("the ICS pty server needs the pty's packet mode (Linux)")
        self.reply_gate_s = reply_gate_s
        self._gate_until: float | None = None
        self._reconfigures = 0  # client tcsetattr calls seen
        self._at_read = 0  # ... when the last command's bytes were read
        self._at_flush = 0  # ... when the last reply left
        self.reconfiguring_client = False  # learned: the client reconfigures before reading
        self._plain_streak = 0  # gates that ran out with no reconfigure, in a row
        self._held = bytearray()  # the servo's answer, waiting for the gate
        self._stopped_until: float | None = None  # the slave's output is stopped until then
        # Until the first client sets the port up (its open's tcsetattr) and that is re-armed,
        # its first command waits: the first timeout change follows it by 2 ms only.
        self._before_first = True  # no client has set the port up yet
        self._flow(on=False, safety=False)

    def _prepare_thread(self) -> None:
        fine_timer_slack()
        try:
            os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(1))
        except (OSError, AttributeError) as exc:  # not root, no CAP_SYS_NICE, not Linux
            log.debug("no real-time priority for the pty server: %s", exc)

    def _on_readable(self, fd: int) -> bool:
        packet = self._read_master()
        if not packet:
            return False
        if packet[0] != TIOCPKT_DATA:  # a status packet: one byte, no data
            if packet[0] & TIOCPKT_IOCTL and self._touched():  # not our own arming
                first = self._before_first
                self._before_first = False
                if not self._armed():
                    self._reconfigures += 1
                    self.reconfiguring_client |= self._gate_until is not None
                    self._rearm()
                elif not first:
                    return False  # still armed (a custom-baud TCSETS2 keeps CSTOPB)
                if self._gate_until is None:
                    self._flow(on=True)
            return False
        data = packet[1:]
        if not data:
            return False
        now = time.monotonic()
        if self._held:  # an answer still held belongs to the command before: it goes first
            self._release(now)
        self._rearm()
        if self.reconfiguring_client:
            gate = LEARNED_GATE_S
        elif self._plain_streak >= PLAIN_AFTER:
            gate = 0.0  # a client that does not reconfigure: nothing to wait for
        else:
            gate = self.reply_gate_s
        self._gate_until = now + gate
        self._at_read = self._reconfigures
        self._feed(data)
        return True

    def _feed(self, data: bytes) -> None:
        """The echo leaves at once (a pyserial writer may wait for the port to turn writable,
        which on a pty can take the master writing something back); the servo's answer is
        held until the gate opens."""
        received = time.monotonic()
        self._rx_unanswered += len(data)
        out = self.board.feed(data)
        self._schedule(out[: len(data)], received)
        self._held += out[len(data) :]

    def _flow(self, *, on: bool, safety: bool = True) -> None:
        """Start or stop the slave's output (what the client writes): stopped, a client's
        write waits, so its next command (and the tcsetattr after that) cannot overtake a
        re-arm that a busy machine delays."""
        if on:
            self._stopped_until = None
        elif safety:
            self._stopped_until = time.monotonic() + FLOW_SAFETY_S
        try:
            termios.tcflow(self._slave, termios.TCOON if on else termios.TCOOFF)
        except (termios.error, OSError) as exc:
            log.debug("tcflow: %s", exc)

    def _housekeeping(self) -> None:
        """No periodic re-arm: every client ``tcsetattr`` is reported. Let a client that went
        away mid-command write again."""
        if self._stopped_until is not None and time.monotonic() >= self._stopped_until:
            self._flow(on=True)

    def _flush_due(self, now: float) -> None:
        if self._gate_until is not None:
            reconfigured = self._reconfigures > self._at_read
            # a reconfiguring client whose command reached us after its first reconfigure
            # (the pty's work queue was late): twice since the last reply, after reading it
            # and after sending this command
            late = self.reconfiguring_client and self._reconfigures - self._at_flush >= 2
            if now >= self._gate_until or reconfigured or late:
                self._plain_streak = 0 if reconfigured or late else self._plain_streak + 1
                self._release(now)
        super()._flush_due(now)

    def _release(self, now: float) -> None:
        """Let the held answer go (after re-arming, so the client's next call finds it so)."""
        self._gate_until = None
        self._rearm()
        self._at_flush = self._reconfigures
        if self._held:
            self._schedule(bytes(self._held), now)
            self._held.clear()
        if self.reconfiguring_client:
            # its next command waits (its write cannot complete) until the tcsetattr that
            # follows its read has been re-armed after
            self._flow(on=False)

    def _timeout(self, now: float) -> float | None:
        wait = super()._timeout(now)
        for t in (self._gate_until, self._stopped_until):
            if t is not None:
                left = max(0.0, t - now)
                wait = left if wait is None else min(wait, left)
        return wait
