"""Symbolic names for RAM addresses (spec 10.1) and servo-block fields (spec 9).

Scalar names stand for one address (``BUTTONS`` = 0350h); table names take an index in
brackets (``VAR[3]`` = 0462h + 2·3), also accepted without brackets (``VAR3``, ``PA1``).
``SERVO[n]`` (a HeartToHeart4 servo block at 0090h + 20n) and ``ICS[n]`` take a field name
after a dot (``SERVO[2].OUTPUT``, ``ICS[5].MEASURED``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

from rcb4hv.protocol import ADDR, RAM_SIZE, SERVO
from rcb4hv.protocol.memory import Field

__all__ = [
    "RAM_SCALARS",
    "RAM_TABLES",
    "SERVO_FIELDS",
    "RamTable",
    "field_text",
    "ram_text",
]


@dataclass(frozen=True, slots=True)
class RamTable:
    """``name[first..last]`` at ``base + stride·(index − first)``, each ``size`` bytes."""

    name: str
    base: int
    stride: int
    first: int
    last: int
    size: int

    def address(self, index: int) -> int:
        if not self.first <= index <= self.last:
            raise ValueError(f"{self.name} index {index} out of range {self.first}..{self.last}")
        return self.base + self.stride * (index - self.first)


# name -> (address, size)
RAM_SCALARS: Final[dict[str, tuple[int, int]]] = {
    "SYSTEM": (ADDR.SYSTEM, 2),
    "PC": (ADDR.PC, 3),
    "CALL_DEPTH": (ADDR.CALL_DEPTH, 1),
    "UPDATE_FLAGS": (ADDR.UPDATE_FLAGS, 5),
    "PIO_DIR": (ADDR.PIO_DIRECTION, 2),
    "PIO_DATA": (ADDR.PIO_DATA, 2),
    "VECTOR_TABLE": (ADDR.VECTOR_TABLE, 2),
    "KRI3": (ADDR.KRI3_BLOCK, 4),
    "BUTTONS": (ADDR.BUTTONS, 2),
    "KRI3_SUM": (ADDR.KRI3_CHECKSUM, 1),
}

RAM_TABLES: Final[dict[str, RamTable]] = {
    t.name: t
    for t in (
        RamTable("AD_REF", ADDR.AD_REFERENCE, 2, 0, 10, 2),
        RamTable("AD", ADDR.AD_VALUES, 2, 0, 10, 2),
        RamTable("TIMER", ADDR.TIMERS[0], 2, 0, 3, 2),
        RamTable("ALLOC", ADDR.ICS_ALLOC, 2, 0, 35, 2),
        RamTable("SERVO", ADDR.SERVO_BLOCKS, ADDR.SERVO_BLOCK_SIZE, 0, 34, 20),
        RamTable("PA", ADDR.PA[0], 1, 1, 4, 1),
        RamTable("VPKG", ADDR.VECTOR_PACKAGES, 8, 0, 31, 8),
        RamTable("COUNTER", ADDR.COUNTERS, 1, 0, 10, 1),
        RamTable("VAR", ADDR.USER_VARIABLES, 2, 0, ADDR.USER_VARIABLE_COUNT - 1, 2),
        RamTable("TEMP", ADDR.TEMPORARIES[0], 2, 0, 1, 2),
    )
}

SERVO_FIELDS: Final[dict[str, tuple[int, int]]] = {
    name.removeprefix("F_"): (f.offset, f.size)
    for name, f in vars(SERVO).items()
    if name.startswith("F_") and isinstance(f, Field)
}
"""Field name -> (offset, size) inside a 20-byte servo block: the protocol's servo-block fields
(:class:`rcb4hv.protocol.memory.SERVO`), by the names of their offsets."""


def field_text(offset: int) -> str:
    """``.OUTPUT``, ``.OUTPUT+1`` or ``+N`` for a byte offset into a servo block."""
    for name, (off, size) in SERVO_FIELDS.items():
        if off <= offset < off + size:
            return f".{name}" + (f"+{offset - off}" if offset > off else "")
    return f"+{offset}"


def _build_ram_names() -> tuple[str, ...]:
    names = [f"0x{a:04X}" for a in range(RAM_SIZE)]
    for name, (addr, size) in RAM_SCALARS.items():
        for k in range(size):
            names[addr + k] = name + (f"+{k}" if k else "")
    for table in RAM_TABLES.values():
        for index in range(table.first, table.last + 1):
            start = table.address(index)
            for k in range(table.size):
                if table.name == "SERVO":
                    names[start + k] = f"SERVO[{index}]{field_text(k)}"
                else:
                    names[start + k] = f"{table.name}[{index}]" + (f"+{k}" if k else "")
    return tuple(names)


_RAM_NAMES: Final = _build_ram_names()


def ram_text(address: int, symbols: bool = True) -> str:
    """The operand text inside ``RAM[...]``: a symbol (``VAR[0]+1``) or ``0x0463``."""
    if symbols:
        return _RAM_NAMES[address]
    return f"0x{address:04X}"
