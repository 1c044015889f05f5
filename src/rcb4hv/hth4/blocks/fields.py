"""Reading a block's JSON fields with errors that name the field (``blocks[3].frames``)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Final

from rcb4hv.errors import EditError

__all__ = ["CONDITIONS", "CONDITION_NAMES", "Fields", "Json", "condition_json", "ics_map_json"]

Json = object
"""A value read from or written to a JSON program (checked where it is used)."""

CONDITION_NAMES: Final = {
    0x00: "always",
    0x05: "equal",
    0x04: "not_equal",
    0x0A: "greater_or_equal",
    0x08: "less",
    0x0E: "greater",
}
"""COND byte (spec 6) -> name. After a compare (SUB, ``dst - src``): Z = equal, C = dst >= src
(no borrow). Other bytes are written as their number (0-15)."""

CONDITIONS: Final = {
    **{name: byte for byte, name in CONDITION_NAMES.items()},
    "zero": 0x05,
    "not_zero": 0x04,
    "carry": 0x0A,
    "no_carry": 0x08,
}
"""Name -> COND byte, with the flag names as aliases."""


class Fields:
    """The fields of one block object; every getter names ``where.field`` in its error."""

    def __init__(self, obj: Mapping[str, Json], where: str) -> None:
        self.obj = obj
        self.where = where

    def path(self, name: str) -> str:
        return f"{self.where}.{name}" if self.where else name

    def has(self, name: str) -> bool:
        return name in self.obj

    def get(self, name: str) -> Json:
        if name not in self.obj:
            raise EditError(f"{self.path(name)}: missing")
        return self.obj[name]

    def integer(self, name: str, lo: int, hi: int, default: int | None = None) -> int:
        if default is not None and name not in self.obj:
            return default
        v = self.get(name)
        if isinstance(v, bool) or not isinstance(v, int):
            raise EditError(f"{self.path(name)}: expected an integer, not {v!r}")
        if not lo <= v <= hi:
            raise EditError(f"{self.path(name)}: {v} outside {lo}..{hi}")
        return v

    def flag(self, name: str, default: bool) -> bool:
        v = self.obj.get(name, default)
        if not isinstance(v, bool):
            raise EditError(f"{self.path(name)}: expected true or false, not {v!r}")
        return v

    def text(self, name: str) -> str:
        v = self.get(name)
        if not isinstance(v, str):
            raise EditError(f"{self.path(name)}: expected a string, not {v!r}")
        return v

    def condition(self, name: str = "if") -> int:
        v = self.obj.get(name, "always")
        if isinstance(v, str) and v in CONDITIONS:
            return CONDITIONS[v]
        if isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 0x0F:
            return v
        raise EditError(
            f"{self.path(name)}: {v!r} is not a condition ({', '.join(CONDITIONS)} or 0-15)"
        )

    def ics_map(self, name: str, hi: int) -> dict[int, int]:
        """``{"ICS": value}`` with ICS numbers 0-35 as keys and values 0..``hi``."""
        v = self.get(name)
        if not isinstance(v, Mapping):
            raise EditError(f"{self.path(name)}: expected an object {{ICS: value}}, not {v!r}")
        out: dict[int, int] = {}
        for k, value in v.items():
            where = f"{self.path(name)}.{k}"
            if not (isinstance(k, str) and k.isdigit() and int(k) <= 35):
                raise EditError(f"{where}: the key is an ICS number 0-35")
            if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= hi:
                raise EditError(f"{where}: expected an integer 0..{hi}, not {value!r}")
            out[int(k)] = value
        return out

    def check_known(self, known: tuple[str, ...]) -> None:
        for k in self.obj:
            if k not in known:
                raise EditError(f"{self.path(k)}: unknown field (known: {', '.join(known)})")


def condition_json(byte: int) -> Json:
    """The JSON of COND byte ``byte``: its name, or the number."""
    return CONDITION_NAMES.get(byte, byte)


def ics_map_json(pairs: tuple[tuple[int, int], ...]) -> dict[str, int]:
    return {str(k): v for k, v in pairs}
