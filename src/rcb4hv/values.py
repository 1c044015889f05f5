"""Values as a user gives them and reads them: the one rule for "an integer" and for showing
a value in a message, under the argument checks of every layer (``client.args`` raises
:class:`~rcb4hv.errors.ArgumentError` with them, ``hth4.argcheck``
:class:`~rcb4hv.errors.EditError`)."""

from __future__ import annotations

import operator
from numbers import Integral, Real

__all__ = ["as_index", "parse_address", "plain"]

_HEX_DIGITS = frozenset("0123456789abcdef")


def as_index(value: object) -> int | None:
    """``value`` as an ``int`` when it is an integer of any integral type (numpy's too:
    :func:`operator.index`), else None: not bools, not floats (``1.0`` too: a position or a
    slot is counted, and a float usually means a missing ``round``), not text."""
    if isinstance(value, bool):
        return None
    try:
        return operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        return None


def parse_address(text: str) -> int:
    """An address (or any integer a user types) in the forms the board's tools write:
    decimal ``2944``, ``0x0B80``, ``0B80h`` (HeartToHeart4) or ``$000B80`` (the assembler);
    case is ignored, ``_`` separates digits. ValueError for anything else. The one parser of
    every command line argument that takes an address."""
    t = text.strip().lower().replace("_", "")
    sign = -1 if t.startswith("-") else 1
    t = t[1:] if t[:1] in ("+", "-") else t
    if t.startswith("$") or t.endswith("h"):
        digits = t[1:] if t.startswith("$") else t[:-1]
        if not digits or not set(digits) <= _HEX_DIGITS:
            raise ValueError(f"not a number: {text!r}")
        return sign * int(digits, 16)
    if not t[:1].isdigit():
        raise ValueError(f"not a number: {text!r}")
    return sign * int(t, 0)


def plain(value: object) -> str:
    """``value`` as a user reads it: numbers (numpy's too) by their value, text quoted."""
    if isinstance(value, bool):
        return repr(value)
    if isinstance(value, Integral):
        return str(int(value))
    if isinstance(value, Real):
        return repr(float(value))
    return repr(value)
