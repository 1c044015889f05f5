"""Serve a :class:`~rcb4hv.emulator.Board` on a pseudo-terminal or a TCP socket.

Both servers run one background thread that waits in ``select`` (never spins): the timeout is
the board's :meth:`~rcb4hv.emulator.Board.poll_timeout` (an output period while the program
runs or servos move, the frame timeout of a partial frame, a pending ROM flush), the time of
the next queued reply, or nothing at all. Replies leave no sooner than
``config.min_reply_latency_s`` after the request arrived (some clients flush their input right
after writing) and, with ``config.pace_replies``, not before the request's bytes and then the
reply's would have crossed the wire at the configured COM baud (11 bits a byte): a pty or a
socket delivers the request at once, so its wire time is charged when the reply is queued.
A queued reply is waited for to its due time (no 1 ms floor), so pacing holds for short
frames too.

The pty server keeps its own slave fd open (raw mode), so a client can close and reopen the
slave path any number of times, with any termios settings (even parity, any supported baud).
A pty cannot store PARENB (the kernel's ``pty_set_termios`` drops it, and the ioctl succeeds);
glibc's ``tcsetattr`` reads the termios back and fails with EINVAL when PARENB was not applied
and ``c_cflag`` did not change either - a reopen, or pyserial's ``timeout`` setter. So the
server keeps the slave *armed*: CSTOPB (pyserial clears it in every reconfigure; its
custom-baud ``TCSETS2`` keeps it) and a sentinel speed, so the client's next ``tcsetattr``
changes ``c_cflag``. Each arming writes the other of two sentinel speeds: one that lands inside
a client's call (after its ioctl, before glibc's read-back) still leaves ``c_cflag`` changed.
It re-arms as soon as a client has set the slave up (the master runs in packet mode and the
slave carries EXTPROC, so the kernel reports each ``tcsetattr``: a client that opens, closes
and reopens without sending finds it armed, as does a second client), before answering, and
every :data:`PTY_REARM` seconds. An open that comes within the server's wake-up time of the
previous set-up can still be refused (rcb4hv's own transports close a pty armed, so their
reopen never is). Clients that reconfigure around every read need more:
:mod:`rcb4hv.emulator.ptywatch`.
The TCP server serves one connection at a time; a new connection replaces the old one.

Both serve any :class:`Served` device, not only a :class:`~rcb4hv.emulator.Board`: the ICS bus
emulator (:class:`~rcb4hv.ics.EmulatedBus`, ``rcb4hv emulate-ics``) is served the same way.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import logging
import os
import pty
import select
import socket
import struct
import sys
import termios
import threading
import time
import tty
from collections import deque
from typing import Any, Final, Protocol

from rcb4hv.emulator.board import Board
from rcb4hv.protocol.memory import SystemRegister, read_system

__all__ = ["PtyServer", "Served", "TcpServer"]

log = logging.getLogger(__name__)

MIN_WAIT: Final = 0.001
MAX_WAIT: Final = 1.0
MAX_UNSENT: Final = 1 << 16
PTY_REARM: Final = 0.2
# Two speeds no client asks for (a pty ignores speed), written in turn: see the module docs.
SENTINEL_SPEEDS: Final = (termios.B50, termios.B75)
# One stop bit: every pyserial reconfigure clears CSTOPB (ICS and RCB-4 are 8E1), a pty keeps it.
ARM_CFLAG: Final = termios.CSTOPB
# Packet mode (TIOCPKT) with EXTPROC on the slave: the kernel reports every termios change.
EXTPROC: Final = 0o200000  # <asm-generic/termbits.h>; not exported by Python's termios
TIOCPKT_DATA: Final = 0x00
TIOCPKT_IOCTL: Final = 0x40
PR_SET_TIMERSLACK: Final = 29
# start() waits this long at most for the thread to serve (as long as stop() waits for it)
START_TIMEOUT_S: Final = 10.0


def fine_timer_slack() -> None:
    """Ask Linux to fire this thread's timers on time (``PR_SET_TIMERSLACK`` 1 ns instead of
    the default 50 µs): a paced reply is due a few hundred µs after its request, so the
    default slack alone would add a fifth to it. Anywhere else (or if it fails) nothing
    changes but that precision."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(PR_SET_TIMERSLACK, 1, 0, 0, 0) != 0:
            log.debug("prctl(PR_SET_TIMERSLACK) failed: errno %d", ctypes.get_errno())
    except (OSError, AttributeError) as exc:
        log.debug("no fine timer slack: %s", exc)


class ServeConfig(Protocol):
    """The serving fields of a device's configuration."""

    @property
    def min_reply_latency_s(self) -> float: ...

    @property
    def pace_replies(self) -> bool: ...


class Served(Protocol):
    """What the servers drive: bytes in, bytes out, on the device's own clock."""

    @property
    def config(self) -> ServeConfig: ...

    def feed(self, data: bytes) -> bytes: ...

    def tick(self) -> None: ...

    def take_output(self) -> bytes: ...

    def poll_timeout(self) -> float | None: ...

    def reset_input(self) -> None: ...


def _wire_baud(device: Served) -> int:
    """The baud rate replies are paced at: the board's COM rate, or the device's own."""
    if isinstance(device, Board):
        return SystemRegister.from_word(read_system(device.ram)).baud_rate
    return int(getattr(device, "wire_baud", 115200))


class _Server:
    """Common loop: the device, the reply queue and the stop pipe."""

    name = "rcb4hv-emulator"
    _max_wait = MAX_WAIT

    def __init__(self, board: Served) -> None:
        self.board = board
        self._queue: deque[tuple[float, bytes]] = deque()
        self._unsent = bytearray()
        self._rx_unanswered = 0  # request bytes received since the last reply was queued
        self._stop_r, self._stop_w = os.pipe()
        self._thread: threading.Thread | None = None
        self._serving = threading.Event()
        self._lock = threading.Lock()
        self._closed = False
        self.error: BaseException | None = None

    @property
    def lock(self) -> threading.Lock:
        """Held by the server thread while it touches the board; hold it to inspect the board."""
        return self._lock

    # --------------------------------------------------------------- lifecycle

    def start(self) -> None:
        if self._thread is not None:
            raise RuntimeError("server already started")
        self._thread = threading.Thread(target=self._main, name=self.name, daemon=True)
        self._thread.start()
        # return once the thread serves: a client told the path/address may act at once
        self._serving.wait(timeout=START_TIMEOUT_S)

    def stop(self) -> None:
        """Stop the thread, join it and close every fd this server opened."""
        if self._closed:
            return
        self._closed = True
        with contextlib.suppress(OSError):
            os.write(self._stop_w, b"x")
        if self._thread is not None:
            self._thread.join(timeout=START_TIMEOUT_S)
        self._close_fds()
        for fd in (self._stop_r, self._stop_w):
            with contextlib.suppress(OSError):
                os.close(fd)

    def __enter__(self) -> _Server:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # --------------------------------------------------------------- to override

    def _close_fds(self) -> None:
        raise NotImplementedError

    def _read_fds(self) -> list[int]:
        raise NotImplementedError

    def _on_readable(self, fd: int) -> bool:
        """Handle a readable fd; True if bytes were fed to the board."""
        raise NotImplementedError

    def _out_fd(self) -> int | None:
        raise NotImplementedError

    # --------------------------------------------------------------- loop

    def _schedule(self, data: bytes, received: float) -> None:
        if not data:
            return
        cfg = self.board.config
        at = received + cfg.min_reply_latency_s
        if cfg.pace_replies:
            baud = _wire_baud(self.board)
            at += (self._rx_unanswered + len(data)) * 11 / baud
        self._rx_unanswered = 0
        self._queue.append((at, data))

    def _flush_due(self, now: float) -> None:
        while self._queue and self._queue[0][0] <= now:
            self._unsent += self._queue.popleft()[1]
        fd = self._out_fd()
        if fd is None:
            self._unsent.clear()
            return
        while self._unsent:
            try:
                n = os.write(fd, self._unsent)
            except BlockingIOError:
                break
            except OSError as exc:
                log.debug("write failed: %s", exc)
                self._unsent.clear()
                self._on_write_error()
                break
            del self._unsent[:n]
        if len(self._unsent) > MAX_UNSENT:
            del self._unsent[: len(self._unsent) - MAX_UNSENT]

    def _on_write_error(self) -> None:
        pass

    def _prepare_thread(self) -> None:
        pass

    def _housekeeping(self) -> None:
        pass

    def _timeout(self, now: float) -> float | None:
        wait = self._max_wait
        t = self.board.poll_timeout()
        if t is not None:
            wait = min(wait, max(MIN_WAIT, t))
        if self._queue:  # due replies leave on time: _flush_due moves them out each pass
            wait = min(wait, max(0.0, self._queue[0][0] - now))
        return wait

    def _main(self) -> None:
        if self.board.config.pace_replies:
            fine_timer_slack()
        self._prepare_thread()
        self._serving.set()
        try:
            self._loop()
        except BaseException as exc:  # pragma: no cover - logged, the thread ends
            self.error = exc
            log.exception("emulator server crashed")

    def _loop(self) -> None:
        board = self.board
        while True:
            now = time.monotonic()
            fds = [self._stop_r, *self._read_fds()]
            wfd = self._out_fd() if self._unsent else None
            try:
                readable, _w, _x = select.select(
                    fds, [wfd] if wfd is not None else [], [], self._timeout(now)
                )
            except (OSError, ValueError) as exc:
                log.debug("select: %s", exc)
                time.sleep(MIN_WAIT)
                continue
            if self._stop_r in readable:
                return
            with self._lock:
                if self._queue:  # replies now due leave before the board runs on
                    self._flush_due(time.monotonic())
                fed = False
                for fd in readable:
                    fed = self._on_readable(fd) or fed
                self._housekeeping()
                if not fed:
                    board.tick()  # feed() has just ticked otherwise
                now = time.monotonic()
                self._schedule(board.take_output(), now)
                self._flush_due(now)

    def _feed(self, data: bytes) -> None:
        received = time.monotonic()
        self._rx_unanswered += len(data)
        reply = self.board.feed(data)
        self._schedule(reply, received)


class PtyServer(_Server):
    """Serve the board on a new pseudo-terminal; clients open :attr:`path`."""

    name = "rcb4hv-emulator-pty"
    _max_wait = PTY_REARM

    def __init__(self, board: Served) -> None:
        super().__init__(board)
        self._master, self._slave = pty.openpty()
        tty.setraw(self._slave)
        os.set_blocking(self._master, False)
        self.path = os.ttyname(self._slave)
        self._last_rearm = 0.0
        self._sentinel = 0  # index of the sentinel speed written last
        self._written: tuple[int, int] = (0, 0)  # c_cflag, c_lflag of the last arming
        self._arm_lflag = 0  # local flags an armed slave carries too
        self._packet = self._packet_mode()
        self._rearm()

    def _packet_mode(self) -> bool:
        """Have the kernel report each termios change of the slave (a client's open, close
        and reopen with nothing sent included): packet mode on the master, EXTPROC on the
        slave (armed with it, so a client that clears it is re-armed too). False where the
        pty has no packet mode: the periodic re-arm alone then."""
        try:
            fcntl.ioctl(self._master, termios.TIOCPKT, struct.pack("i", 1))
        except (OSError, AttributeError) as exc:
            log.debug("no packet mode on the pty: %s", exc)
            return False
        self._arm_lflag = EXTPROC
        return True

    def _armed(self) -> bool:
        """Whether the slave is armed (no client open or reconfigure since the last arming)."""
        try:
            attrs = termios.tcgetattr(self._slave)
        except (termios.error, OSError):
            return False
        return self._is_armed(attrs)

    def _touched(self) -> bool:
        """Whether someone else set the slave's termios since the last arming."""
        try:
            attrs = termios.tcgetattr(self._slave)
        except (termios.error, OSError):
            return False
        return (attrs[2], attrs[3]) != self._written

    def _is_armed(self, attrs: list[Any]) -> bool:
        return bool(attrs[2] & ARM_CFLAG) and (attrs[3] & self._arm_lflag) == self._arm_lflag

    def _rearm(self) -> None:
        """Arm the slave so the next client ``tcsetattr`` changes ``c_cflag`` (module docs)."""
        self._last_rearm = time.monotonic()
        try:
            attrs = termios.tcgetattr(self._slave)
            if self._is_armed(attrs):
                return
            self._sentinel = 1 - self._sentinel
            speed = SENTINEL_SPEEDS[self._sentinel]
            attrs[4] = attrs[5] = speed
            attrs[2] = (attrs[2] & ~termios.CBAUD) | speed | ARM_CFLAG
            attrs[3] |= self._arm_lflag
            termios.tcsetattr(self._slave, termios.TCSANOW, attrs)
            self._written = (attrs[2], attrs[3])
        except (termios.error, OSError) as exc:
            log.debug("could not arm the pty: %s", exc)

    def _housekeeping(self) -> None:
        now = time.monotonic()
        if now - self._last_rearm >= PTY_REARM:
            self._rearm()

    def _close_fds(self) -> None:
        for fd in (self._master, self._slave):
            with contextlib.suppress(OSError):
                os.close(fd)

    def _read_fds(self) -> list[int]:
        return [self._master]

    def _out_fd(self) -> int | None:
        return self._master

    def _read_master(self) -> bytes:
        try:
            return os.read(self._master, 4096)
        except BlockingIOError:
            return b""
        except OSError as exc:
            if exc.errno == errno.EIO:  # no one has the slave open (cannot happen: we hold it)
                time.sleep(MIN_WAIT)
                return b""
            raise

    def _on_readable(self, fd: int) -> bool:
        data = self._read_master()
        if self._packet and data:
            if data[0] != TIOCPKT_DATA:  # a status packet: one byte, no data
                if data[0] & TIOCPKT_IOCTL and self._touched():  # a client's, not our own
                    self._rearm()
                return False
            data = data[1:]
        if not data:
            return False
        self._rearm()
        self._feed(data)
        return True

    def __enter__(self) -> PtyServer:
        self.start()
        return self


class TcpServer(_Server):
    """Serve the board on a TCP socket (127.0.0.1 by default); see :attr:`address`."""

    name = "rcb4hv-emulator-tcp"

    def __init__(self, board: Served, host: str = "127.0.0.1", port: int = 0) -> None:
        super().__init__(board)
        self._listener = socket.create_server((host, port))
        self._listener.setblocking(False)
        self._conn: socket.socket | None = None
        addr = self._listener.getsockname()
        self.address: tuple[str, int] = (addr[0], addr[1])

    def _close_fds(self) -> None:
        self._drop_conn()
        self._listener.close()

    def _drop_conn(self) -> None:
        if self._conn is not None:
            with contextlib.suppress(OSError):
                self._conn.close()
            self._conn = None
            self._queue.clear()
            self._rx_unanswered = 0
            self._unsent.clear()
            self.board.reset_input()

    def _read_fds(self) -> list[int]:
        fds = [self._listener.fileno()]
        if self._conn is not None:
            fds.append(self._conn.fileno())
        return fds

    def _out_fd(self) -> int | None:
        return None if self._conn is None else self._conn.fileno()

    def _on_write_error(self) -> None:
        self._drop_conn()

    def _on_readable(self, fd: int) -> bool:
        if fd == self._listener.fileno():
            try:
                conn, peer = self._listener.accept()
            except BlockingIOError:
                return False
            if self._conn is not None:  # one board, one link: as a serial port has
                log.warning("TCP client %s replaces the one connected before (disconnected)", peer)
            self._drop_conn()
            conn.setblocking(False)
            conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
            self._conn = conn
            log.info("TCP client %s connected", peer)
            return False
        if self._conn is None or fd != self._conn.fileno():
            return False
        try:
            data = self._conn.recv(4096)
        except BlockingIOError:
            return False
        except OSError:
            data = b""
        if not data:
            log.info("TCP client disconnected")
            self._drop_conn()
            return False
        self._feed(data)
        return True

    def __enter__(self) -> TcpServer:
        self.start()
        return self
