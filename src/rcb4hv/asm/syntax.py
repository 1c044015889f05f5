"""Shared pieces of the text form: mnemonics, numbers, conditions, positions."""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol import (
    POSITION_FREE,
    POSITION_HOLD,
    Add,
    And,
    Condition,
    Div,
    Mod,
    Mul,
    Or,
    Sub,
    Xor,
)

__all__ = [
    "BINARY_MNEMONICS",
    "condition_text",
    "position_text",
    "rom_text",
]

BINARY_MNEMONICS: Final[dict[str, type]] = {
    "AND": And,
    "OR": Or,
    "XOR": Xor,
    "ADD": Add,
    "SUB": Sub,
    "MUL": Mul,
    "DIV": Div,
    "MOD": Mod,
}

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
