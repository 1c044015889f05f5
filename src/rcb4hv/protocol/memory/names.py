"""The names of RAM addresses (spec 10.1), one table for every text that names RAM.

Scalar names stand for one address (``BUTTONS`` = 0350h, with its size in bytes); table names
take an index (``VAR[3]`` in the assembler, ``VAR3`` in a motion program) at
``base + stride·(index − first)``. The assembler (:mod:`rcb4hv.asm.symbols`) and the motion
programs (:mod:`rcb4hv.hth4.blocks.operands`) both write and read these names.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

from rcb4hv.protocol.memory.map import ADDR

__all__ = ["RAM_SCALARS", "RAM_TABLES", "RamTable"]


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

    def index(self, address: int) -> int | None:
        """The index whose entry starts at ``address``; None if no entry starts there."""
        off = address - self.base
        if 0 <= off <= self.stride * (self.last - self.first) and off % self.stride == 0:
            return off // self.stride + self.first
        return None


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
