"""Symbolic names for RAM addresses (spec 10.1; the tables are
:mod:`rcb4hv.protocol.memory.names`) and servo-block fields (spec 9).

Scalar names stand for one address (``BUTTONS`` = 0350h); table names take an index in
brackets (``VAR[3]`` = 0462h + 2·3), also accepted without brackets (``VAR3``, ``PA1``).
``SERVO[n]`` (a HeartToHeart4 servo block at 0090h + 20n) and ``ICS[n]`` take a field name
after a dot (``SERVO[2].OUTPUT``, ``ICS[5].MEASURED``).
"""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol import RAM_SIZE, SERVO
from rcb4hv.protocol.memory import RAM_SCALARS, RAM_TABLES, Field, RamTable

__all__ = [
    "RAM_SCALARS",
    "RAM_TABLES",
    "SERVO_FIELDS",
    "RamTable",
    "field_text",
    "ram_text",
]


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
