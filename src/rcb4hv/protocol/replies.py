"""Replies of the board: ACK, NAK, data and version (spec sections 3 and 12).

A reply cannot always be decoded without knowing the command it answers: a one-byte data
reply holding 06 is byte-for-byte an ACK. :func:`decode_reply` therefore takes the command.
When a command expects exactly one data byte, a 4-byte reply is read as data, even if that
byte is 15h (which would otherwise be a NAK): the protocol gives no way to tell them apart.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, Protocol

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.frame import build_frame, check_frame
from rcb4hv.protocol.operands import MAX_READ

__all__ = [
    "ACK_BYTE",
    "MAX_REPLY_SIZE",
    "NAK_BYTE",
    "Ack",
    "DataReply",
    "Nak",
    "Reply",
    "VersionReply",
    "decode_reply",
    "encode_reply",
    "reply_length",
]

ACK_BYTE: Final = 0x06
NAK_BYTE: Final = 0x15
VERSION_LENGTH: Final = 32
MAX_REPLY_SIZE: Final = MAX_READ + 3
"""A MOVE may read 128 bytes to COM, whose reply frame is 131 bytes long."""


class _Expects(Protocol):
    @property
    def cmd(self) -> int: ...

    @property
    def reply_data_size(self) -> int | None: ...


@dataclass(frozen=True, slots=True)
class Ack:
    """``04 CMD 06 SUM``."""

    cmd: int


@dataclass(frozen=True, slots=True)
class Nak:
    """``04 CMD 15 SUM``."""

    cmd: int


@dataclass(frozen=True, slots=True)
class DataReply:
    """``(N+3) CMD d1..dN SUM``."""

    cmd: int
    data: bytes

    def __post_init__(self) -> None:
        if not 1 <= len(self.data) <= MAX_REPLY_SIZE - 3:
            raise ValueError(f"data reply of {len(self.data)} bytes")

    def as_int(self) -> int:
        """The data as an unsigned little-endian integer."""
        return int.from_bytes(self.data, "little")


@dataclass(frozen=True, slots=True)
class VersionReply:
    """``23 FD <32 bytes> SUM``."""

    version: bytes

    cmd = 0xFD

    def __post_init__(self) -> None:
        if len(self.version) != VERSION_LENGTH:
            raise ValueError("a version string is 32 bytes")

    @property
    def text(self) -> str:
        """The printable part of the version string."""
        return "".join(chr(b) if 0x20 <= b < 0x7F else "" for b in self.version).rstrip()


Reply = Ack | Nak | DataReply | VersionReply

# Replies are frozen: the decoder hands out these instead of building one per ACK.
_ACKS: Final = tuple(Ack(c) for c in range(256))
_NAKS: Final = tuple(Nak(c) for c in range(256))


def encode_reply(reply: Reply) -> bytes:
    """The frame of ``reply``."""
    if isinstance(reply, Ack):
        return build_frame(reply.cmd, b"\x06")
    if isinstance(reply, Nak):
        return build_frame(reply.cmd, b"\x15")
    if isinstance(reply, DataReply):
        return build_frame(reply.cmd, reply.data)
    return build_frame(0xFD, reply.version)


_ACK_FRAMES: Final = tuple(encode_reply(a) for a in _ACKS)
_NAK_FRAMES: Final = tuple(encode_reply(n) for n in _NAKS)


def reply_length(command: _Expects) -> int:
    """Length in bytes of the successful reply frame to ``command`` (a NAK is always 4)."""
    n = command.reply_data_size
    return 4 if n is None else n + 3


def decode_reply(frame: bytes | bytearray, command: _Expects) -> Reply:
    """Decode the reply frame to ``command``; raise ProtocolError if it cannot be one."""
    n = len(frame)
    cmd = command.cmd
    expected = command.reply_data_size
    if n == 4 and expected is None:  # fast path: the whole ACK / NAK frame, prebuilt
        if frame == _ACK_FRAMES[cmd]:
            return _ACKS[cmd]
        if frame == _NAK_FRAMES[cmd]:
            return _NAKS[cmd]
    frame = bytes(frame)
    check_frame(frame, MAX_REPLY_SIZE)
    if frame[1] != cmd:
        raise ProtocolError(f"reply for command {frame[1]:02X}h while waiting for {cmd:02X}h")
    if expected is None:
        raise ProtocolError(f"expected ACK or NAK for {cmd:02X}h, got {frame.hex(' ')}")
    if n == expected + 3:
        if cmd == 0xFD:
            return VersionReply(frame[2:-1])
        return DataReply(cmd, frame[2:-1])
    if n == 4 and frame[2] == NAK_BYTE:
        return Nak(cmd)
    raise ProtocolError(f"expected {expected} data bytes for {cmd:02X}h, got {frame.hex(' ')}")
