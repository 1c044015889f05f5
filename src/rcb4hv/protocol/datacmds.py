"""The data commands of spec section 4: MOVE, the binary operations AND..MOD, NOT and SHIFT.

Each class owns its codec: ``encode()`` builds the frame, the ``from_frame`` classmethod
parses one (raising :class:`~rcb4hv.errors.ProtocolError` or ``ValueError``; the caller,
:func:`~rcb4hv.protocol.commands.decode_command`, checks framing and maps errors).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Final

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.frame import build_frame
from rcb4hv.protocol.operands import (
    KIND_COM,
    KIND_RAM,
    KIND_ROM,
    MAX_READ,
    RAM_SIZE,
    ROM_SIZE,
    Com,
    Data,
    Destination,
    Ics,
    Op,
    Ram,
    Rom,
    Source,
    check_int,
    decode_dst,
    dst_bytes,
    operand_text,
    src_bytes,
)

__all__ = [
    "Add",
    "And",
    "BinaryOp",
    "Div",
    "Mod",
    "Move",
    "Mul",
    "Not",
    "Or",
    "Shift",
    "Sub",
    "UnaryOp",
    "Xor",
]


def _validate_operands(
    name: str,
    dst: Destination,
    src: Source | None,
    size: int,
    max_size: int,
    allowed_dst: tuple[type, ...],
) -> None:
    if not isinstance(dst, allowed_dst):
        raise ValueError(f"{name}: destination {type(dst).__name__} is not allowed")
    if src is not None and not isinstance(src, (Ram, Ics, Rom, Data)):
        raise ValueError(f"{name}: source must be Ram, Ics, Rom or Data")
    check_int(f"{name} size", size, 1, max_size)
    for role, op in (("destination", dst), ("source", src)):
        if op is not None and not op.span_ok(size):
            end = (
                f"RAM ({RAM_SIZE - 1:04X}h)"
                if isinstance(op, Ram)
                else f"ROM ({ROM_SIZE - 1:06X}h)"
            )
            raise ValueError(
                f"{name}: {role} {operand_text(op)} + {size} bytes runs past the end of {end}"
            )


def _resolve_size(src: Source, size: int | None) -> int:
    if isinstance(src, Data):
        if size is not None and size != len(src.data):
            raise ValueError(f"size {size} does not match the {len(src.data)}-byte literal")
        return len(src.data)
    if size is None:
        raise ValueError("size is required unless the source is a Data literal")
    return size


def _data_header(frame: bytes) -> tuple[bool, Destination, int]:
    """(no-write flag, destination, source kind) of a data command frame."""
    n = len(frame)
    if n < 8:
        raise ProtocolError(f"data command frame of {n} bytes is too short")
    t = frame[2]
    if t & 0x4C:
        raise ProtocolError(f"type byte {t:02X}: bits 6, 3 and 2 must be 0")
    return bool(t & 0x80), decode_dst((t >> 4) & 3, frame[3:6]), t & 3


def _data_operands(frame: bytes) -> tuple[bool, Destination, Source, int | None]:
    """(no-write flag, destination, source, size) of a MOVE or binary operation frame."""
    nw, dst, src_kind = _data_header(frame)
    n = len(frame)
    src: Source
    size: int | None
    if src_kind == KIND_COM:
        src, size = Data(frame[6:-1]), None
    elif src_kind == KIND_ROM:
        if n != 11:
            raise ProtocolError("ROM source needs an 11-byte frame")
        src, size = Rom(frame[6] | frame[7] << 8 | frame[8] << 16), frame[9]
    else:
        if n != 10:
            raise ProtocolError("RAM/ICS source needs a 10-byte frame")
        src = Ram(frame[6] | frame[7] << 8) if src_kind == KIND_RAM else Ics(frame[6], frame[7])
        size = frame[8]
    return nw, dst, src, size


@dataclass(frozen=True, slots=True)
class Move:
    """00h MOVE: ``dst <- src`` over ``size`` bytes. ``dst=Com()`` reads data to the host."""

    dst: Destination
    src: Source
    size: int | None = None
    cmd: ClassVar[int] = Op.MOVE

    def __post_init__(self) -> None:
        size = _resolve_size(self.src, self.size)
        object.__setattr__(self, "size", size)
        _validate_operands("MOVE", self.dst, self.src, size, MAX_READ, (Ram, Ics, Com, Rom))

    @property
    def nbytes(self) -> int:
        """The operation size in bytes."""
        assert self.size is not None
        return self.size

    def encode(self) -> bytes:
        t = (self.dst.kind << 4) | self.src.kind
        return build_frame(
            self.cmd, bytes((t,)) + dst_bytes(self.dst) + src_bytes(self.src, self.nbytes)
        )

    @classmethod
    def from_frame(cls, frame: bytes) -> Move:
        nw, dst, src, size = _data_operands(frame)
        if nw:
            raise ProtocolError("MOVE does not take the no-write-back flag")
        return cls(dst, src, size)

    @property
    def reply_data_size(self) -> int | None:
        """Bytes of data in the reply (None: the reply is an ACK)."""
        return self.nbytes if isinstance(self.dst, Com) else None


@dataclass(frozen=True, slots=True)
class BinaryOp:
    dst: Destination
    src: Source
    size: int | None = None
    no_write: bool = False
    cmd: ClassVar[int] = -1
    max_size: ClassVar[int] = MAX_READ
    allowed_dst: ClassVar[tuple[type, ...]] = (Ram, Ics, Rom)

    def __post_init__(self) -> None:
        size = _resolve_size(self.src, self.size)
        object.__setattr__(self, "size", size)
        if not isinstance(self.no_write, bool):
            raise ValueError("no_write must be a bool")
        _validate_operands(
            type(self).__name__.upper(), self.dst, self.src, size, self.max_size, self.allowed_dst
        )

    @property
    def nbytes(self) -> int:
        assert self.size is not None
        return self.size

    def encode(self) -> bytes:
        t = (0x80 if self.no_write else 0) | (self.dst.kind << 4) | self.src.kind
        return build_frame(
            self.cmd, bytes((t,)) + dst_bytes(self.dst) + src_bytes(self.src, self.nbytes)
        )

    @classmethod
    def from_frame(cls, frame: bytes) -> BinaryOp:
        nw, dst, src, size = _data_operands(frame)
        return cls(dst, src, size, nw)

    @property
    def reply_data_size(self) -> int | None:
        return self.nbytes


@dataclass(frozen=True, slots=True)
class And(BinaryOp):
    """01h AND: ``dst &= src``; Z = result is zero."""

    cmd: ClassVar[int] = Op.AND


@dataclass(frozen=True, slots=True)
class Or(BinaryOp):
    """02h OR: ``dst |= src``; Z = result is zero."""

    cmd: ClassVar[int] = Op.OR


@dataclass(frozen=True, slots=True)
class Xor(BinaryOp):
    """03h XOR: ``dst ^= src``; Z = result is zero."""

    cmd: ClassVar[int] = Op.XOR


_ARITH_DST: Final = (Ram, Ics, Com, Rom)


@dataclass(frozen=True, slots=True)
class Add(BinaryOp):
    """06h ADD (1 or 2 bytes): C = carry out of the width."""

    cmd: ClassVar[int] = Op.ADD
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Sub(BinaryOp):
    """07h SUB (1 or 2 bytes): C = 1 unless it borrowed (C = dst >= src)."""

    cmd: ClassVar[int] = Op.SUB
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Mul(BinaryOp):
    """08h MUL (1 or 2 bytes, low bytes kept): C = the product overflowed."""

    cmd: ClassVar[int] = Op.MUL
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Div(BinaryOp):
    """09h DIV (1 or 2 bytes, unsigned integer division)."""

    cmd: ClassVar[int] = Op.DIV
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Mod(BinaryOp):
    """0Ah MOD (1 or 2 bytes, unsigned remainder)."""

    cmd: ClassVar[int] = Op.MOD
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class UnaryOp:
    dst: Destination
    size: int
    no_write: bool = False
    cmd: ClassVar[int] = -1

    def __post_init__(self) -> None:
        if not isinstance(self.no_write, bool):
            raise ValueError("no_write must be a bool")
        _validate_operands(
            type(self).__name__.upper(), self.dst, None, self.size, MAX_READ, (Ram, Ics, Rom)
        )

    @property
    def nbytes(self) -> int:
        return self.size

    def _operand_byte(self) -> int:
        return 0

    def encode(self) -> bytes:
        t = (0x80 if self.no_write else 0) | (self.dst.kind << 4)
        return build_frame(
            self.cmd,
            bytes((t,)) + dst_bytes(self.dst) + bytes((0, self._operand_byte(), self.size)),
        )

    @classmethod
    def _unary_header(cls, frame: bytes, operand_free: bool) -> tuple[bool, Destination]:
        nw, dst, src_kind = _data_header(frame)
        if len(frame) != 10 or src_kind != KIND_RAM or frame[6] != 0 or (operand_free and frame[7]):
            raise ProtocolError(f"malformed {cls.__name__.upper()} frame")
        return nw, dst

    @classmethod
    def from_frame(cls, frame: bytes) -> UnaryOp:
        nw, dst = cls._unary_header(frame, True)
        return cls(dst, frame[8], nw)

    @property
    def reply_data_size(self) -> int | None:
        return self.size


@dataclass(frozen=True, slots=True)
class Not(UnaryOp):
    """04h NOT: ``dst = ~dst`` (frame ``0A 04 TYPE D0 D1 D2 00 00 SIZE SUM``)."""

    cmd: ClassVar[int] = Op.NOT


@dataclass(frozen=True, slots=True)
class Shift(UnaryOp):
    """05h SHIFT: count 1-127 shifts right by count, 128-255 left by 256 - count; 0 no shift.

    Frame ``0A 05 TYPE D0 D1 D2 00 COUNT SIZE SUM``. The whole ``size``-byte value shifts
    as one little-endian integer; C = the last bit shifted out.
    """

    count: int = 0
    cmd: ClassVar[int] = Op.SHIFT

    def __post_init__(self) -> None:
        check_int("SHIFT count", self.count, 0, 0xFF)
        UnaryOp.__post_init__(self)

    def _operand_byte(self) -> int:
        return self.count

    @classmethod
    def from_frame(cls, frame: bytes) -> Shift:
        nw, dst = cls._unary_header(frame, False)
        return cls(dst, frame[8], nw, frame[7])

    @property
    def right_bits(self) -> int:
        """Signed shift: positive = right by that many bits, negative = left."""
        return self.count if self.count < 128 else self.count - 256

    @classmethod
    def right(cls, dst: Destination, bits: int, size: int, no_write: bool = False) -> Shift:
        """Shift right by 0..127 bits."""
        check_int("right shift", bits, 0, 127)
        return cls(dst, size, no_write, bits)

    @classmethod
    def left(cls, dst: Destination, bits: int, size: int, no_write: bool = False) -> Shift:
        """Shift left by 1..128 bits (count byte 256 - bits)."""
        check_int("left shift", bits, 1, 128)
        return cls(dst, size, no_write, 256 - bits)
