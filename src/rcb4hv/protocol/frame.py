"""Frames, checksums and the incremental frame decoder.

Every frame, in both directions, is ``[SIZE] [CMD] [payload ...] [SUM]`` where SIZE is the
total length (SIZE and SUM included) and SUM is the low byte of the sum of every byte before it.

:class:`FrameDecoder` is sans-I/O (after h11): feed it bytes with
:meth:`~FrameDecoder.receive_data`, then call :meth:`~FrameDecoder.next_frame` until it
returns :data:`NEED_DATA`.

Resynchronisation rules (the decoder's contract):

* A SIZE byte below 3 or above ``max_size`` cannot start a frame: that one byte is dropped and
  :class:`~rcb4hv.errors.FrameError` is raised. The decoder has already resynchronised when the
  exception reaches the caller, who simply calls ``next_frame()`` again.
* Fewer than SIZE bytes buffered: :data:`NEED_DATA`.
* SIZE bytes buffered but the checksum is wrong: :class:`~rcb4hv.errors.ChecksumError` carrying
  the candidate frame. With ``resync="byte"`` (the host default: hunt for the reply among stray
  bytes) only the first byte is dropped, so a valid frame that starts inside the candidate is
  still found; with ``resync="frame"`` (the board's behaviour: a bad frame is judged whole and
  NAKed) the whole candidate is dropped.
* End of input / a frame timeout: :meth:`~FrameDecoder.reset` returns the partial bytes and
  empties the buffer; the caller decides (the emulator NAKs, the client reports a timeout).

The buffer never holds more than ``max_size - 1`` bytes that do not yet form a frame, plus
whatever the caller fed since the last ``next_frame()`` call.
"""

from __future__ import annotations

from typing import Final, Literal
from zlib import adler32

from rcb4hv.errors import ChecksumError, FrameError

__all__ = [
    "MAX_FRAME_SIZE",
    "MIN_FRAME_SIZE",
    "NEED_DATA",
    "FrameDecoder",
    "NeedData",
    "build_frame",
    "check_frame",
    "checksum",
    "frame_at",
    "seal",
    "split_frames",
    "sum_ok",
]

MIN_FRAME_SIZE: Final = 3
MAX_FRAME_SIZE: Final = 128


class NeedData:
    """Type of the :data:`NEED_DATA` marker."""

    _instance: NeedData | None = None

    def __new__(cls) -> NeedData:
        if cls._instance is None:
            cls._instance = super().__new__(cls)
        return cls._instance

    def __repr__(self) -> str:
        return "NEED_DATA"


NEED_DATA: Final = NeedData()
"""Returned by :meth:`FrameDecoder.next_frame` when no complete frame is buffered yet."""


def checksum(data: bytes | bytearray | memoryview) -> int:
    """Low byte of the sum of ``data``."""
    if len(data) <= 256:
        return ((adler32(data) & 0xFFFF) - 1) & 0xFF
    return sum(data) & 0xFF


def sum_ok(frame: bytes | bytearray) -> bool:
    """True if the last byte of ``frame`` (at most 256 bytes) is the checksum of the others.

    Adler-32's first half is 1 + the sum of the bytes modulo 65521; for at most 256 bytes
    the sum is below 65521, so that half is the exact sum, computed in C (the checksum of a
    131-byte reply in a tenth of the time of ``sum()``).
    """
    return not ((adler32(frame) & 0xFFFF) - 1 - 2 * frame[-1]) & 0xFF


def build_frame(cmd: int, payload: bytes | bytearray = b"") -> bytes:
    """Build ``SIZE CMD payload SUM``; raises ValueError if it would exceed 255 bytes."""
    size = len(payload) + 3
    if size > 255:
        raise ValueError(f"frame of {size} bytes does not fit a size byte")
    if not 0 <= cmd <= 0xFF:
        raise ValueError(f"command byte {cmd} out of range 0..255")
    return seal(bytes((size, cmd)) + bytes(payload))


def seal(body: bytes) -> bytes:
    """``body`` (SIZE CMD payload, at most 255 bytes) with its checksum byte appended: how
    every frame gets its checksum (the sum by Adler-32, as in :func:`checksum`)."""
    return body + _BYTES[((adler32(body) & 0xFFFF) - 1) & 0xFF]


_BYTES: Final = tuple(bytes((b,)) for b in range(256))


def check_frame(frame: bytes, max_size: int = MAX_FRAME_SIZE) -> None:
    """Raise FrameError / ChecksumError unless ``frame`` is one whole, valid frame."""
    n = len(frame)
    if n < MIN_FRAME_SIZE:
        raise FrameError(f"frame of {n} bytes is shorter than 3")
    if frame[0] != n:
        raise FrameError(f"size byte says {frame[0]} but the frame has {n} bytes")
    if n > max_size:
        raise FrameError(f"frame of {n} bytes exceeds the maximum of {max_size}")
    if not sum_ok(frame):
        raise ChecksumError(
            f"checksum {frame[-1]:02X} does not match {checksum(frame[:-1]):02X}", bytes(frame)
        )


def frame_at(
    data: bytes | bytearray | memoryview, offset: int, max_size: int = MAX_FRAME_SIZE
) -> bytes:
    """The whole, checked frame that starts at ``data[offset]`` (a ROM image, a motion's bytes).

    Raises FrameError for an offset outside ``data``, a SIZE byte below 3 or above
    ``max_size`` (erased ROM reads FF) or a frame running past the end, and ChecksumError for a
    damaged frame.
    """
    if not 0 <= offset < len(data):
        raise FrameError(f"offset {offset} is outside the {len(data)} bytes")
    size = data[offset]
    if size < MIN_FRAME_SIZE or size > max_size:
        raise FrameError(f"size byte {size:#04x} at offset {offset} cannot start a frame")
    if offset + size > len(data):
        raise FrameError(f"the {size}-byte frame at offset {offset} runs past the end")
    frame = bytes(data[offset : offset + size])
    check_frame(frame, max_size)
    return frame


class FrameDecoder:
    """Incremental decoder: bytes in, whole checked frames out."""

    __slots__ = ("_buf", "max_size", "resync")

    def __init__(
        self, max_size: int = MAX_FRAME_SIZE, resync: Literal["byte", "frame"] = "byte"
    ) -> None:
        if not MIN_FRAME_SIZE <= max_size <= 255:
            raise ValueError("max_size must be within 3..255")
        if resync not in ("byte", "frame"):
            raise ValueError("resync must be 'byte' or 'frame'")
        self.max_size = max_size
        self.resync = resync
        self._buf = bytearray()

    def receive_data(self, data: bytes | bytearray | memoryview) -> None:
        """Append received bytes."""
        self._buf += data

    @property
    def pending(self) -> bytes:
        """The bytes buffered that have not formed a frame yet."""
        return bytes(self._buf)

    def reset(self) -> bytes:
        """Drop and return the buffered partial input (end of input or frame timeout)."""
        rest = bytes(self._buf)
        self._buf.clear()
        return rest

    def next_frame(self) -> bytes | NeedData:
        """Return the next whole frame, or NEED_DATA; raise a ProtocolError on bad input."""
        buf = self._buf
        if not buf:
            return NEED_DATA
        size = buf[0]
        if size < MIN_FRAME_SIZE or size > self.max_size:
            del buf[0]
            raise FrameError(f"size byte {size:#04x} cannot start a frame; dropped")
        if len(buf) < size:
            return NEED_DATA
        frame = bytes(buf[:size])
        if not sum_ok(frame):
            if self.resync == "byte":
                del buf[0]
            else:
                del buf[:size]
            raise ChecksumError(f"bad checksum in frame {frame.hex(' ')}", frame)
        del buf[:size]
        return frame


def split_frames(data: bytes) -> tuple[list[bytes], bytes]:
    """Cut ``data`` into frames by their SIZE bytes; return (frames, trailing bytes).

    Stops at an erased byte (FF), a SIZE below 3 or a frame that runs past the end; what is
    left (HeartToHeart4's FF end marker, erased space) is returned as the tail. Checksums are
    checked (:class:`~rcb4hv.errors.ChecksumError` for a damaged frame).
    """
    frames: list[bytes] = []
    i = 0
    while i < len(data):
        try:
            frame = frame_at(data, i)
        except FrameError:  # erased (FF), a SIZE below 3 or a frame past the end: the tail
            break
        frames.append(frame)
        i += len(frame)
    return frames, bytes(data[i:])
