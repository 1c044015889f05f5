"""Shared pieces of the text form: mnemonics, numbers, conditions, positions."""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD, Condition

__all__ = [
    "SHIFT_LEFT",
    "SHIFT_RIGHT",
    "SHIFT_WORDS",
    "condition_text",
    "position_text",
    "rom_text",
]

SHIFT_LEFT: Final = "SHL"
SHIFT_RIGHT: Final = "SHR"
SHIFT_WORDS: Final[dict[str, str]] = {SHIFT_LEFT: "SHIFT", SHIFT_RIGHT: "SHIFT"}
"""Spellings of SHIFT by direction; every other mnemonic is the command table's
(:data:`rcb4hv.protocol.registry.BY_MNEMONIC`)."""

POSITION_WORDS: Final[dict[str, int]] = {"FREE": POSITION_FREE, "HOLD": POSITION_HOLD}


def rom_text(address: int) -> str:
    """``$000B80``: how ROM addresses and branch targets are written."""
    return f"${address:06X}"


def condition_text(cond: Condition) -> str:
    """``Z``, ``NZ&C``, ... or ``COND=0x01`` for a byte the flag names cannot express."""
    if (cond.z and not cond.compare_z) or (cond.c and not cond.compare_c):
        return f"COND=0x{cond.to_byte():02X}"
    return str(cond)


def position_text(position: int) -> str:
    """A servo position: decimal counts, or ``FREE`` / ``HOLD``."""
    for word, value in POSITION_WORDS.items():
        if position == value:
            return word
    return str(position)
