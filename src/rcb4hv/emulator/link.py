"""The board's serial link: framing, oversize swallowing, NAK timeouts and queued output.

Frames are cut by the protocol core's :class:`~rcb4hv.protocol.FrameDecoder`
(``resync="frame"``); each complete frame goes to the handler the board passes in. See
:mod:`rcb4hv.emulator` for the exact bad-input rules this unit implements.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from rcb4hv.emulator.clock import Clock
from rcb4hv.emulator.config import EmulatorConfig
from rcb4hv.errors import ArgumentTypeError, ChecksumError, FrameError
from rcb4hv.protocol import NEED_DATA, FrameDecoder, Nak, encode_reply

__all__ = ["Link", "nak", "received"]

log = logging.getLogger(__name__)

MAX_FRAME = 128


def nak(cmd: int) -> bytes:
    return encode_reply(Nak(cmd))


def received(data: object) -> bytes:
    """``data`` as the bytes the link receives: bytes, bytearray or memoryview. Anything else
    (an int: ``bytes(5)`` would be five zero bytes; a str, a list) is the caller's mistake, not
    line noise: :class:`~rcb4hv.errors.ArgumentTypeError` (a TypeError)."""
    if not isinstance(data, bytes | bytearray | memoryview):
        raise ArgumentTypeError(
            f"data must be bytes, bytearray or memoryview, not {type(data).__name__}"
        )
    return bytes(data)


class Link:
    """Receive side and queued output of the board's serial port."""

    def __init__(self, config: EmulatorConfig, clock: Clock) -> None:
        self.config = config
        self.clock = clock
        self.decoder = FrameDecoder(resync="frame")
        self.discard_left = 0  # bytes of an oversize frame still to swallow
        self._discard_cmd: int | None = None
        self.last_rx = 0.0
        self._output = bytearray()

    @property
    def pending(self) -> bool:
        """True while a partial frame (or an oversize frame being swallowed) is held."""
        return bool(self.discard_left or self.decoder.pending)

    def reset(self) -> bytes:
        """Drop partial input silently; return the bytes the decoder held."""
        self.discard_left = 0
        self._discard_cmd = None
        return self.decoder.reset()

    def take_output(self) -> bytes:
        out = bytes(self._output)
        self._output.clear()
        return out

    def queue(self, data: bytes) -> None:
        self._output += data
        excess = len(self._output) - self.config.max_pending_output
        if excess > 0:
            del self._output[:excess]

    def receive(self, data: bytes, handle: Callable[[bytes], bytes]) -> bytes:
        """Cut ``data`` into frames; return the replies (``handle(frame)`` for each frame)."""
        out = bytearray()
        self.last_rx = self.clock.now()
        dec = self.decoder
        while data:
            if self.discard_left:
                take = data[: self.discard_left]
                if self._discard_cmd is None:
                    self._discard_cmd = take[0]
                self.discard_left -= len(take)
                data = data[len(take) :]
                if not self.discard_left:
                    if self.config.oversize_frame == "nak":
                        out += nak(self._discard_cmd)
                    self._discard_cmd = None
                continue
            dec.receive_data(data)
            data = b""
            while True:
                head = dec.pending[:1]
                try:
                    frame = dec.next_frame()
                except ChecksumError as exc:
                    log.debug("checksum error in %s", exc.frame.hex(" "))
                    out += nak(exc.frame[1])
                    continue
                except FrameError:
                    size = head[0]
                    if size > MAX_FRAME:
                        log.debug("oversize frame (SIZE %d): swallowed", size)
                        data = dec.reset()
                        self.discard_left = size - 1
                        self._discard_cmd = None
                        break
                    log.debug("dropped byte %02X that cannot start a frame", size)
                    continue
                if frame is NEED_DATA:
                    break
                assert isinstance(frame, bytes)
                out += handle(frame)
        return bytes(out)

    def timeout_due(self) -> float | None:
        """Board time at which the held partial frame times out (None: nothing held)."""
        if not self.pending:
            return None
        return self.last_rx + self.clock.board_seconds(self.config.frame_timeout_s)

    def check_timeout(self, now: float) -> None:
        """Drop a partial frame after ``frame_timeout_s`` of silence; queue its NAK."""
        if not self.pending:
            return
        if now - self.last_rx < self.clock.board_seconds(self.config.frame_timeout_s):
            return
        partial = self.decoder.reset()
        cmd = partial[1] if len(partial) >= 2 else self._discard_cmd
        self.discard_left = 0
        self._discard_cmd = None
        log.debug("frame timeout with %d partial bytes", len(partial))
        if cmd is not None and self.config.partial_frame_reply == "nak":
            self.queue(nak(cmd))
