"""Struct views of the board's structures: servo block (spec 9), ICS allocation table (10.1),
vector package (11.3) and the KRI-3 receiver block.

Each structure has a precompiled :class:`struct.Struct`, named offsets / :class:`Field` s for
one field at a block address, and whole-structure ``unpack`` / ``pack`` over any buffer at any
address (RAM, or a data image inside a ROM image).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from struct import Struct
from typing import Final

from rcb4hv.protocol.branches import Condition
from rcb4hv.protocol.memory.fields import Field, ReadBuffer, WriteBuffer, read_u16, s16
from rcb4hv.protocol.memory.map import ADDR, Button
from rcb4hv.protocol.operands import ICS_COUNT, POSITION_FREE

__all__ = [
    "ALLOC_TABLE",
    "KRI3",
    "NO_BLOCK",
    "SERVO",
    "SERVO_BLOCK",
    "VEC",
    "VECTOR_PACKAGE",
    "Kri3Block",
    "ServoBlock",
    "VectorPackage",
    "button_operand",
    "mix_method",
    "mix_rate",
    "mix_source",
    "operand_ics",
    "pack_alloc",
    "read_alloc",
    "unpack_alloc",
]


# ----------------------------------------------------------------------------- servo block


class SERVO:
    """Offsets inside the 20-byte servo block (spec 9) and a :class:`Field` for each.

    ``SERVO.OUTPUT`` is the offset (an int, as the assembler's symbols use it);
    ``SERVO.F_OUTPUT.get(ram, blk)`` reads the field of the block at ``blk``.
    """

    SIZE: Final = 20
    TYPE: Final = 0
    ID: Final = 1
    BASE: Final = 2
    MEASURED: Final = 4
    OUTPUT: Final = 6
    SPEED: Final = 8
    END: Final = 9
    REMAINING: Final = 11
    WIDTH: Final = 12
    MIX1_SOURCE: Final = 14
    MIX1_METHOD: Final = 16
    MIX2_SOURCE: Final = 17
    MIX2_METHOD: Final = 19

    F_TYPE: Final = Field("type", TYPE, "B")
    F_ID: Final = Field("ics_id", ID, "B")
    F_BASE: Final = Field("base", BASE, "h")
    F_MEASURED: Final = Field("measured", MEASURED, "H")
    F_OUTPUT: Final = Field("output", OUTPUT, "H")
    F_SPEED: Final = Field("speed", SPEED, "B")
    F_END: Final = Field("end", END, "H")
    F_REMAINING: Final = Field("remaining", REMAINING, "B")
    F_WIDTH: Final = Field("width", WIDTH, "h")
    F_MIX1_SOURCE: Final = Field("mix1_source", MIX1_SOURCE, "H")
    F_MIX1_METHOD: Final = Field("mix1_method", MIX1_METHOD, "B")
    F_MIX2_SOURCE: Final = Field("mix2_source", MIX2_SOURCE, "H")
    F_MIX2_METHOD: Final = Field("mix2_method", MIX2_METHOD, "B")
    MIXES: Final = ((MIX1_SOURCE, MIX1_METHOD), (MIX2_SOURCE, MIX2_METHOD))
    """(source offset, method offset) of the two mixing entries."""


SERVO_BLOCK: Final = Struct("<BBhHHBHBhHBHB")
"""The whole servo block, field order as :class:`ServoBlock` (base and width signed)."""
_SERVO_BLOCK_W: Final = Struct("<BBHHHBHBHHBHB")  # the same bytes, every field unsigned
assert SERVO_BLOCK.size == SERVO.SIZE == _SERVO_BLOCK_W.size


@dataclass(frozen=True, slots=True)
class ServoBlock:
    """The 20-byte servo block HeartToHeart4 puts at 0090h + 20n (spec section 9)."""

    type: int = 0
    ics_id: int = 0
    base: int = 0
    measured: int = 0
    output: int = POSITION_FREE
    speed: int = 0
    end: int = 0
    remaining: int = 0
    width: int = 0
    mix1_source: int = 0xFFFF
    mix1_method: int = 0
    mix2_source: int = 0xFFFF
    mix2_method: int = 0

    SIZE = 20

    @classmethod
    def unpack(cls, buf: ReadBuffer, at: int = 0) -> ServoBlock:
        """The block at ``at`` in ``buf`` (RAM, or a servo block image in a ROM image)."""
        return cls(*SERVO_BLOCK.unpack_from(buf, at))

    @classmethod
    def from_bytes(cls, data: bytes | bytearray | memoryview) -> ServoBlock:
        if len(data) < SERVO.SIZE:
            raise ValueError("a servo block is 20 bytes")
        return cls.unpack(data)

    def pack(self, buf: WriteBuffer, at: int = 0) -> None:
        """Store this block at ``at`` (every field modulo its width)."""
        _SERVO_BLOCK_W.pack_into(buf, at, *self._masked())

    def to_bytes(self) -> bytes:
        return _SERVO_BLOCK_W.pack(*self._masked())

    def _masked(self) -> tuple[int, ...]:
        b, w = 0xFF, 0xFFFF
        return (
            self.type & b,
            self.ics_id & b,
            self.base & w,
            self.measured & w,
            self.output & w,
            self.speed & b,
            self.end & w,
            self.remaining & b,
            self.width & w,
            self.mix1_source & w,
            self.mix1_method & b,
            self.mix2_source & w,
            self.mix2_method & b,
        )

    @classmethod
    def configured(
        cls,
        ics_id: int,
        base: int = 0,
        mix1: tuple[int, int] = (0xFFFF, 0),
        mix2: tuple[int, int] = (0xFFFF, 0),
    ) -> ServoBlock:
        """A block as a ROM image holds it before boot: output and end free (8000h)."""
        return cls(
            ics_id=ics_id,
            base=s16(base & 0xFFFF),
            output=POSITION_FREE,
            end=POSITION_FREE,
            mix1_source=mix1[0],
            mix1_method=mix1[1],
            mix2_source=mix2[0],
            mix2_method=mix2[1],
        )


def mix_source(word: int) -> tuple[bool, bool, int]:
    """Decode a mixing source word (spec 9): ``(is_ics, is_word, operand)``.

    ``operand`` is the RAM address (bits 11-0) or, for an ICS source, ``ics << 8 | offset``
    (bits 13-8 ICS number, 7-0 offset into its block). FFFF means no mixing; check it first.
    """
    if word & 0x8000:
        return True, bool(word & 0x4000), word & 0x3FFF
    return False, bool(word & 0x4000), word & 0x0FFF


def mix_rate(method: int) -> int:
    """The signed multiplier of a mixing method byte (bit 7 sign, bits 6-0 magnitude)."""
    return -(method & 0x7F) if method & 0x80 else method & 0x7F


def mix_method(rate: int) -> int:
    """The method byte of a signed multiplier -127..127 (inverse of :func:`mix_rate`)."""
    if not -127 <= rate <= 127:
        raise ValueError(f"mixing rate {rate} is outside -127..127")
    return 0x80 | -rate if rate < 0 else rate


# ----------------------------------------------------------------------------- ICS allocation

NO_BLOCK: Final = 0xFFFF
"""An allocation-table entry (or vector-table address) that points nowhere."""
ALLOC_TABLE: Final = Struct(f"<{ICS_COUNT}H")
"""``alloc[0..35]`` at RAM 0044h (and its image in ROM)."""


def read_alloc(buf: ReadBuffer, ics: int, at: int = ADDR.ICS_ALLOC) -> int:
    """The raw entry ``alloc[ics]`` (:data:`NO_BLOCK` = none) of the table at ``at``."""
    return read_u16(buf, at + 2 * ics)


def unpack_alloc(buf: ReadBuffer, at: int = ADDR.ICS_ALLOC) -> list[int | None]:
    """The whole table: each ICS number's block address, or None."""
    return [None if a == NO_BLOCK else a for a in ALLOC_TABLE.unpack_from(buf, at)]


def pack_alloc(table: Sequence[int | None]) -> bytes:
    """The 72 bytes of a table (entries missing from the end read as none)."""
    entries = [NO_BLOCK if a is None else a & 0xFFFF for a in table]
    if len(entries) > ICS_COUNT:
        raise ValueError(f"the allocation table has {ICS_COUNT} entries")
    entries += [NO_BLOCK] * (ICS_COUNT - len(entries))
    return ALLOC_TABLE.pack(*entries)


# ----------------------------------------------------------------------------- vector package


class VEC:
    """Bits of a vector package's COND byte (spec 11.3). The low nibble is a
    :class:`~rcb4hv.protocol.Condition` byte (Z, C, ZE, CE), as in JUMP / CALL."""

    Z: Final = 0x01
    C: Final = 0x02
    COMPARE_Z: Final = 0x04
    COMPARE_C: Final = 0x08
    CONDITION: Final = 0x0F
    LITERAL: Final = 0x10  # the source word is a literal
    WORD: Final = 0x20  # compare words (else bytes)
    JUMP: Final = 0x40  # jump (else call)
    EOF: Final = 0x80  # last package of the table
    SIZE: Final = 8


VECTOR_PACKAGE: Final = Struct("<BHHHB")
"""One package: COND, destination word, source word, target (low word, high byte)."""


def operand_ics(word: int) -> tuple[int, int] | None:
    """``(ics, offset)`` of a vector operand word that names an ICS block (bit 15 set,
    bits 14-8 ICS number, 7-0 offset), or None when it is a RAM address."""
    return ((word >> 8) & 0x7F, word & 0xFF) if word & 0x8000 else None


def button_operand(buttons: int) -> int:
    """The button word as the little-endian RAM word a package compares (the board stores
    the button word high byte first)."""
    return int.from_bytes((int(buttons) & 0xFFFF).to_bytes(2, "big"), "little")


def _check(name: str, value: int, lo: int, hi: int) -> None:
    if not isinstance(value, int) or isinstance(value, bool) or not lo <= value <= hi:
        raise ValueError(f"{name} {value!r} out of range {lo}..{hi}")


@dataclass(frozen=True, slots=True)
class VectorPackage:
    """One 8-byte vector-jump package (spec 11.3); EOF is given when it is packed."""

    destination: int
    source: int
    target: int
    compare_z: bool = True
    z: bool = True
    compare_c: bool = False
    c: bool = False
    literal: bool = True
    word: bool = True
    jump: bool = False

    def __post_init__(self) -> None:
        _check("destination", self.destination, 0, 0xFFFF)
        _check("source", self.source, 0, 0xFFFF)
        _check("target", self.target, 0, 0xFFFFFF)  # 24 bits, as on the wire

    @classmethod
    def button(cls, buttons: int, target: int, *, jump: bool = False) -> VectorPackage:
        """Branch to ``target`` when the button word equals ``buttons`` (e.g. Button.CIRCLE)."""
        _check("buttons", int(buttons), 0, 0xFFFF)
        raw = button_operand(Button(int(buttons) & 0x1F7F))
        return cls(ADDR.BUTTONS, raw, target, jump=jump)

    @property
    def condition(self) -> Condition:
        """The Z / C checks as a JUMP / CALL condition."""
        return Condition(self.compare_z, self.z, self.compare_c, self.c)

    def cond_byte(self, last: bool) -> int:
        return (
            self.condition.to_byte()
            | (VEC.LITERAL if self.literal else 0)
            | (VEC.WORD if self.word else 0)
            | (VEC.JUMP if self.jump else 0)
            | (VEC.EOF if last else 0)
        )

    def pack(self, buf: WriteBuffer, at: int, last: bool) -> None:
        t = self.target
        VECTOR_PACKAGE.pack_into(
            buf, at, self.cond_byte(last), self.destination, self.source, t & 0xFFFF, t >> 16
        )

    def to_bytes(self, last: bool) -> bytes:
        out = bytearray(VEC.SIZE)
        self.pack(out, 0, last)
        return bytes(out)

    @classmethod
    def unpack(cls, buf: ReadBuffer, at: int = 0) -> tuple[VectorPackage, bool]:
        """The package at ``at`` and whether it is the last (EOF)."""
        c, dst, src, lo, hi = VECTOR_PACKAGE.unpack_from(buf, at)
        cond = Condition.from_byte(c & VEC.CONDITION)
        pkg = cls(
            destination=dst,
            source=src,
            target=lo | hi << 16,
            z=cond.z,
            c=cond.c,
            compare_z=cond.compare_z,
            compare_c=cond.compare_c,
            literal=bool(c & VEC.LITERAL),
            word=bool(c & VEC.WORD),
            jump=bool(c & VEC.JUMP),
        )
        return pkg, bool(c & VEC.EOF)

    @classmethod
    def from_bytes(cls, data: bytes | bytearray | memoryview) -> tuple[VectorPackage, bool]:
        return cls.unpack(data)


# ----------------------------------------------------------------------------- KRI-3 block

KRI3: Final = Struct(">BBHHBBBBB")
"""The KRI-3 receiver block at 034Ch: type, ID, 2 reserved bytes, the button word (high
byte first), PA1-PA4, checksum."""


@dataclass(frozen=True, slots=True)
class Kri3Block:
    """The 11-byte KRI-3 / KRR receiver block (RAM 034Ch-0356h, ICS 35's slot)."""

    type: int = 1
    ics_id: int = 31
    reserved: int = 0
    buttons: int = 0
    pa1: int = 0
    pa2: int = 0
    pa3: int = 0
    pa4: int = 0
    checksum: int = 0

    @classmethod
    def unpack(cls, buf: ReadBuffer, at: int = ADDR.KRI3_BLOCK) -> Kri3Block:
        return cls(*KRI3.unpack_from(buf, at))

    def to_bytes(self) -> bytes:
        for name in ("type", "ics_id", "pa1", "pa2", "pa3", "pa4", "checksum"):
            _check(f"KRI-3 {name}", getattr(self, name), 0, 0xFF)
        _check("KRI-3 button word", self.buttons, 0, 0xFFFF)
        _check("KRI-3 reserved word", self.reserved, 0, 0xFFFF)
        return KRI3.pack(
            self.type,
            self.ics_id,
            self.reserved,
            self.buttons,
            self.pa1,
            self.pa2,
            self.pa3,
            self.pa4,
            self.checksum,
        )
