"""Primitive struct accessors over board memory: little-endian words, 24-bit addresses, fields.

Every accessor works on any buffer: the emulator's RAM ``bytearray``, a RAM span read from a
board (``bytes``), or a whole ROM image with the address of a data image inside it. All
:class:`struct.Struct` objects are compiled once at import; the functions allocate nothing
beyond the tuple ``unpack_from`` returns.

Hot loops can bind the precompiled structs directly (``get = U16.unpack_from`` then
``get(ram, a)[0]``); everything else uses :func:`read_u16` / :func:`write_u16` or a
:class:`Field`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from struct import Struct
from typing import Final, Literal, TypeAlias

__all__ = [
    "S16",
    "U8",
    "U16",
    "U16_BE",
    "U24",
    "Field",
    "ReadBuffer",
    "WriteBuffer",
    "read_s16",
    "read_u16",
    "read_u24",
    "s16",
    "u16_bytes",
    "u24_bytes",
    "write_u16",
    "write_u24",
]

ReadBuffer: TypeAlias = "bytes | bytearray | memoryview"
"""Anything the views read: RAM, a span read from a board, a ROM image."""
WriteBuffer: TypeAlias = "bytearray | memoryview"
"""Anything the views write: the emulator's RAM, a ROM image being built."""

U8: Final = Struct("<B")
U16: Final = Struct("<H")
S16: Final = Struct("<h")
U16_BE: Final = Struct(">H")
U24: Final = Struct("<HB")
"""A 24-bit little-endian ROM address as (low word, high byte); see :func:`read_u24`."""


def s16(value: int) -> int:
    """A 16-bit word read as two's complement."""
    return value - 0x10000 if value & 0x8000 else value


def read_u16(buf: ReadBuffer, address: int) -> int:
    """The little-endian word at ``address``."""
    v: int = U16.unpack_from(buf, address)[0]
    return v


def read_s16(buf: ReadBuffer, address: int) -> int:
    """The signed little-endian word at ``address``."""
    v: int = S16.unpack_from(buf, address)[0]
    return v


def write_u16(buf: WriteBuffer, address: int, value: int) -> None:
    """Store ``value`` (taken modulo 2**16, so -1 is FFFF) as a little-endian word."""
    U16.pack_into(buf, address, value & 0xFFFF)


def read_u24(buf: ReadBuffer, address: int) -> int:
    """The 24-bit little-endian value at ``address`` (a PC, a ROM target)."""
    lo, hi = U24.unpack_from(buf, address)
    return int(lo | hi << 16)


def write_u24(buf: WriteBuffer, address: int, value: int) -> None:
    """Store the low 24 bits of ``value`` little-endian."""
    U24.pack_into(buf, address, value & 0xFFFF, (value >> 16) & 0xFF)


def u16_bytes(value: int) -> bytes:
    """The two RAM bytes of a word (modulo 2**16)."""
    return U16.pack(value & 0xFFFF)


def u24_bytes(value: int) -> bytes:
    """The three bytes of a 24-bit ROM address (modulo 2**24)."""
    return U24.pack(value & 0xFFFF, (value >> 16) & 0xFF)


_READ: Final = {"B": Struct("<B"), "H": U16, "h": S16, "b": Struct("<b"), ">H": U16_BE}
_WRITE: Final = {"B": U8, "H": U16, "h": U16, "b": U8, ">H": U16_BE}


@dataclass(frozen=True, slots=True)
class Field:
    """One field of a memory structure: ``offset`` bytes from the structure's base.

    ``fmt`` is a :mod:`struct` code: ``B`` byte, ``b`` signed byte, ``H`` word, ``h`` signed
    word, ``>H`` big-endian word (the button word). :meth:`get` reads it from any buffer at a
    base address; :meth:`put` stores any value modulo its width (the board accepts every bit
    pattern, so -1 is stored as FF / FFFF).
    """

    name: str
    offset: int
    fmt: Literal["B", "b", "H", "h", ">H"]
    _read: Struct = field(init=False, repr=False, compare=False)
    _write: Struct = field(init=False, repr=False, compare=False)
    _mask: int = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_read", _READ[self.fmt])
        object.__setattr__(self, "_write", _WRITE[self.fmt])
        object.__setattr__(self, "_mask", (1 << (8 * self._read.size)) - 1)

    @property
    def size(self) -> int:
        return int(self._read.size)

    def get(self, buf: ReadBuffer, base: int = 0) -> int:
        """The field of the structure at ``base``."""
        v: int = self._read.unpack_from(buf, base + self.offset)[0]
        return v

    def decode(self, data: ReadBuffer) -> int:
        """The field from its own bytes alone (what reading :meth:`span` returned)."""
        v: int = self._read.unpack_from(data, 0)[0]
        return v

    def put(self, buf: WriteBuffer, base: int, value: int) -> None:
        """Store ``value`` into the field of the structure at ``base``."""
        self._write.pack_into(buf, base + self.offset, value & self._mask)

    def span(self, base: int = 0) -> tuple[int, int]:
        """(address, size) of the field of the structure at ``base``: what to read from a board."""
        return base + self.offset, self.size
