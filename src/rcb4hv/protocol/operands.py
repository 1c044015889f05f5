"""Command bytes, board sizes and the operands of the data commands (spec section 4).

:class:`Ram`, :class:`Ics`, :class:`Rom` and :class:`Com` are destinations; :class:`Ram`,
:class:`Ics`, :class:`Rom` and :class:`Data` (literal bytes carried in the frame) are sources.
Each operand knows its kind code of the type byte and its address bytes on the wire.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Final

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.frame import MAX_FRAME_SIZE

__all__ = [
    "ICS_COUNT",
    "KIND_COM",
    "KIND_ICS",
    "KIND_RAM",
    "KIND_ROM",
    "MAX_LITERAL",
    "MAX_READ",
    "POSITION_FREE",
    "POSITION_HOLD",
    "POSITION_MAX",
    "POSITION_MIN",
    "RAM_SIZE",
    "ROM_SIZE",
    "Com",
    "Data",
    "Destination",
    "Ics",
    "Op",
    "Ram",
    "Rom",
    "Source",
    "check_ics",
    "check_int",
    "check_position",
    "decode_dst",
    "dst_bytes",
    "is_valid_position",
    "operand_text",
    "src_bytes",
]


class Op:
    """Command bytes (the CMD field of a frame)."""

    MOVE: Final = 0x00
    AND: Final = 0x01
    OR: Final = 0x02
    XOR: Final = 0x03
    NOT: Final = 0x04
    SHIFT: Final = 0x05
    ADD: Final = 0x06
    SUB: Final = 0x07
    MUL: Final = 0x08
    DIV: Final = 0x09
    MOD: Final = 0x0A
    JUMP: Final = 0x0B
    CALL: Final = 0x0C
    RETURN: Final = 0x0D
    ICS_COMM: Final = 0x0E
    SINGLE_SERVO: Final = 0x0F
    CONST_FRAME_SERVO: Final = 0x10
    SERIES_SERVO: Final = 0x11
    SPEED_STRETCH: Final = 0x12
    VERSION: Final = 0xFD
    ACK_CHECK: Final = 0xFE


RAM_SIZE: Final = 0x0490
"""Bytes of RAM: 0000h-048Fh (spec section 10)."""
ROM_SIZE: Final = 0x40000
"""Bytes of ROM (EEPROM): 256 KB, 00000h-3FFFFh (spec section 10)."""
ICS_COUNT: Final = 36
"""ICS numbers 0-35: the entries of the allocation table at 0044h and the bits of a 10h
bitmap (spec 10.1 and the RunConstFrameServo section)."""
MAX_READ: Final = 128
"""The most bytes one data command moves (its size byte, 1-128; a MOVE to COM of 128 bytes
has a 131-byte reply frame)."""
MAX_LITERAL: Final = MAX_FRAME_SIZE - 7
POSITION_MIN: Final = 3500
POSITION_MAX: Final = 11500
"""The documented servo positions, POSITION_MIN..POSITION_MAX (about -135..+135 degrees)."""
POSITION_HOLD: Final = 0x7FFF
POSITION_FREE: Final = 0x8000

# operand kind codes of the type byte
KIND_RAM: Final = 0
KIND_ICS: Final = 1
KIND_COM: Final = 2
KIND_ROM: Final = 3
_KIND_NAMES: Final = ("RAM", "ICS", "COM", "ROM")


def check_int(name: str, value: int, lo: int, hi: int) -> None:
    if not isinstance(value, int) or isinstance(value, bool):
        raise ValueError(f"{name} must be an int, not {type(value).__name__}")
    if not lo <= value <= hi:
        raise ValueError(f"{name} {value!r} out of range {lo}..{hi}")


def check_ics(ics: int) -> None:
    check_int("ICS number", ics, 0, ICS_COUNT - 1)


def is_valid_position(position: int) -> bool:
    """True for 3500..11500 and the special values 0x7FFF (hold) and 0x8000 (free)."""
    return POSITION_MIN <= position <= POSITION_MAX or position in (POSITION_HOLD, POSITION_FREE)


def check_position(position: int) -> None:
    # The wire carries any 16-bit value and real HeartToHeart4 projects use values outside the
    # documented 3500..11500 (e.g. 2100, 12700), so the command layer accepts the full range;
    # the robot-level client applies the documented range (see is_valid_position).
    check_int("position", position, 0, 0xFFFF)


# --------------------------------------------------------------------------- operands


@dataclass(frozen=True, slots=True)
class Ram:
    """RAM address 0000h-048Fh."""

    address: int
    kind: ClassVar[int] = KIND_RAM

    def __post_init__(self) -> None:
        check_int("RAM address", self.address, 0, RAM_SIZE - 1)

    def span_ok(self, size: int) -> bool:
        return self.address + size <= RAM_SIZE


@dataclass(frozen=True, slots=True)
class Ics:
    """Byte ``offset`` inside the device block of ICS number ``ics`` (RAM alloc[ics] + offset)."""

    offset: int
    ics: int
    kind: ClassVar[int] = KIND_ICS

    def __post_init__(self) -> None:
        check_int("ICS offset", self.offset, 0, 0xFF)
        check_ics(self.ics)

    def span_ok(self, size: int) -> bool:
        return True


@dataclass(frozen=True, slots=True)
class Rom:
    """ROM (EEPROM) address 000000h-03FFFFh."""

    address: int
    kind: ClassVar[int] = KIND_ROM

    def __post_init__(self) -> None:
        check_int("ROM address", self.address, 0, ROM_SIZE - 1)

    def span_ok(self, size: int) -> bool:
        return self.address + size <= ROM_SIZE


@dataclass(frozen=True, slots=True)
class Com:
    """The host: as a destination, the result is sent back in the reply."""

    kind: ClassVar[int] = KIND_COM

    def span_ok(self, size: int) -> bool:
        return True


@dataclass(frozen=True, slots=True)
class Data:
    """Literal bytes carried in the frame (source kind COM)."""

    data: bytes
    kind: ClassVar[int] = KIND_COM

    def __post_init__(self) -> None:
        if not isinstance(self.data, bytes):
            object.__setattr__(self, "data", bytes(self.data))
        if not 1 <= len(self.data) <= MAX_LITERAL:
            raise ValueError(f"literal of {len(self.data)} bytes; must be 1..{MAX_LITERAL}")

    def span_ok(self, size: int) -> bool:
        return True


Destination = Ram | Ics | Com | Rom
Source = Ram | Ics | Rom | Data


def operand_text(op: Destination | Source) -> str:
    """``RAM[0462h]``, ``ICS5[+04h]``, ``ROM[000B80h]``, ``COM`` or ``#02 80``."""
    if isinstance(op, Ram):
        return f"RAM[{op.address:04X}h]"
    if isinstance(op, Ics):
        return f"ICS{op.ics}[+{op.offset:02X}h]"
    if isinstance(op, Rom):
        return f"ROM[{op.address:06X}h]"
    if isinstance(op, Data):
        return "#" + op.data.hex(" ").upper()
    return "COM"


def dst_bytes(dst: Destination) -> bytes:
    if isinstance(dst, Ram):
        return bytes((dst.address & 0xFF, dst.address >> 8, 0))
    if isinstance(dst, Ics):
        return bytes((dst.offset, dst.ics, 0))
    if isinstance(dst, Rom):
        a = dst.address
        return bytes((a & 0xFF, (a >> 8) & 0xFF, a >> 16))
    return b"\x00\x00\x00"


def src_bytes(src: Source, size: int) -> bytes:
    if isinstance(src, Data):
        return src.data
    if isinstance(src, Ram):
        return bytes((src.address & 0xFF, src.address >> 8, size))
    if isinstance(src, Ics):
        return bytes((src.offset, src.ics, size))
    a = src.address
    return bytes((a & 0xFF, (a >> 8) & 0xFF, a >> 16, size))


def decode_dst(kind: int, b: bytes) -> Destination:
    if kind == KIND_RAM:
        if b[2]:
            raise ProtocolError("RAM destination: third address byte must be 00")
        return Ram(b[0] | b[1] << 8)
    if kind == KIND_ICS:
        if b[2]:
            raise ProtocolError("ICS destination: third address byte must be 00")
        return Ics(b[0], b[1])
    if kind == KIND_COM:
        if b != b"\x00\x00\x00":
            raise ProtocolError("COM destination: address bytes must be 00 00 00")
        return Com()
    return Rom(b[0] | b[1] << 8 | b[2] << 16)
