"""The client's transaction helpers: prebuilt read frames and the careful reply hunt.

:meth:`Rcb4Client._roundtrip` takes the fast path when the first read brings exactly the
reply frame it expects; anything else (a NAK, a reply in pieces, stray bytes before it, a
damaged reply) goes through :class:`ReplyMatcher`, which hunts for the reply among the bytes.
The hunt is sans-I/O (bytes in, the reply frame out): both faces of the client (blocking and
asyncio) feed it, each with its own waiting.
"""

from __future__ import annotations

import logging
import math
from numbers import Real
from typing import Final, NoReturn

from rcb4hv.errors import (
    ArgumentError,
    ArgumentTypeError,
    ChecksumError,
    FrameError,
    NakError,
    Rcb4TimeoutError,
)
from rcb4hv.protocol import NEED_DATA, Com, FrameDecoder, Move, Ram
from rcb4hv.protocol.replies import NAK_BYTE

__all__ = ["RAM_READS", "ReplyMatcher", "check_timeout", "data_reply_error", "ram_read_frame"]

log = logging.getLogger("rcb4hv.client.core")

RAM_READS: dict[tuple[int, int], bytes] = {}
"""RAM read frames already built, by (address, size): a control loop reads the same ones."""
RAM_READS_KEPT: Final = 512
STRAY_SHOWN: Final = 32
"""How many discarded stray bytes the warning shows (it counts them all)."""


def check_timeout(timeout: object) -> None:
    """ArgumentError (a ValueError) unless ``timeout`` is a number of seconds > 0 and finite:
    no call may hang (None and inf would), and 0 or less could never see a reply."""
    if isinstance(timeout, bool) or not isinstance(timeout, Real):
        raise ArgumentTypeError(f"a timeout is a number of seconds, not {timeout!r}")
    if not 0 < float(timeout) < math.inf:
        raise ArgumentError(f"a timeout is a number of seconds > 0 and finite, not {timeout!r}")


def data_reply_error(raw: bytes, cmd: int, size: int, name: str) -> NoReturn:
    """Raise what a reply ``raw`` other than the ``size`` data bytes asked for means."""
    if len(raw) == 4 and raw[2] == NAK_BYTE:
        raise NakError(f"board answered NAK to {name}", cmd)
    raise FrameError(f"bad reply to {name}: expected {size} data bytes, got {raw.hex(' ')}")


def ram_read_frame(address: int, size: int) -> bytes:
    """The frame of ``Move(Com(), Ram(address), size)`` (a RAM read), remembered in
    :data:`RAM_READS`."""
    frame = Move(Com(), Ram(address), size).encode()
    if len(RAM_READS) >= RAM_READS_KEPT:
        RAM_READS.clear()
    RAM_READS[address, size] = frame
    return frame


class ReplyMatcher:
    """Finds the reply frame to one command in the bytes that arrive after it was sent.

    Bytes that cannot start it (a SIZE other than ``expected`` or 4, a CMD other than
    ``cmd``) are discarded, and :meth:`report` logs them once for the exchange (a late reply
    of 131 bytes is one warning, not one per chunk read). A damaged candidate is remembered
    and sets :attr:`grace_deadline` to ``now + corrupt_grace`` (a good copy may still follow).
    """

    def __init__(
        self, decoder: FrameDecoder, cmd: int, expected: int, name: str, corrupt_grace: float
    ) -> None:
        self.decoder = decoder
        self.cmd = cmd
        self.expected = expected
        self.name = name
        self.corrupt_grace = corrupt_grace
        self.corrupt: ChecksumError | None = None
        self.grace_deadline: float | None = None
        self.need = 4
        """How many more bytes to ask the link for."""
        self.discarded = 0
        """Stray bytes discarded so far in this exchange."""
        self._shown = bytearray()  # the first of them, for the log
        decoder.reset()

    def feed(self, chunk: bytes, now: float) -> bytes | None:
        """Take ``chunk``; return the reply frame once it is complete (checksum checked)."""
        decoder, cmd, expected = self.decoder, self.cmd, self.expected
        decoder.receive_data(chunk)
        while True:
            pending = decoder.pending
            skip, n = 0, len(pending)
            while skip < n and not (
                (pending[skip] == expected or pending[skip] == 4)
                and (skip + 1 >= n or pending[skip + 1] == cmd)
            ):
                skip += 1
            if skip:
                self.discarded += skip
                self._shown += pending[: max(0, min(skip, STRAY_SHOWN - len(self._shown)))]
                decoder.reset()
                decoder.receive_data(pending[skip:])
                pending = pending[skip:]
            if not pending:
                self.need = 4
                return None
            try:
                frame = decoder.next_frame()
            except ChecksumError as exc:
                log.warning("reply to %s with a bad checksum: %s", self.name, exc)
                self.corrupt = ChecksumError(
                    f"reply to {self.name} has a bad checksum: {exc.frame.hex(' ')}", exc.frame
                )
                limit = now + self.corrupt_grace
                if self.grace_deadline is None or limit < self.grace_deadline:
                    self.grace_deadline = limit
                continue
            if frame is NEED_DATA:
                self.need = max(pending[0] - len(pending), 1)
                return None
            assert isinstance(frame, bytes)
            if len(frame) == 4 and expected != 4 and frame[2] != NAK_BYTE:
                # an ACK where data is expected: a late reply to an earlier command, not this
                # one's (only a NAK is a 4-byte answer to a data command)
                self.discarded += 4
                self._shown += frame[: max(0, min(4, STRAY_SHOWN - len(self._shown)))]
                continue
            return frame

    def report(self) -> None:
        """Log the stray bytes discarded in this exchange, once (the client calls it when the
        exchange ends, however it ends); a no-op when there were none or after the first
        call."""
        if not self.discarded:
            return
        shown = self._shown.hex(" ")
        if self.discarded > len(self._shown):
            shown += " ..."
        log.warning(
            "discarded %d stray byte(s) before the reply to %s: %s",
            self.discarded,
            self.name,
            shown,
        )
        self.discarded = 0
        self._shown.clear()

    def until(self, deadline: float) -> float:
        """``deadline``, cut to the grace period after a damaged reply."""
        grace = self.grace_deadline
        return deadline if grace is None or grace > deadline else grace

    def timeout_error(self, timeout: float) -> Exception:
        """What to raise at the deadline: the checksum error seen, else a timeout."""
        partial = self.decoder.reset()
        if self.corrupt is not None:
            return self.corrupt
        got = f" (incomplete: {partial.hex(' ')})" if partial else ""
        return Rcb4TimeoutError(f"no reply to {self.name} within {timeout:g} s{got}")
