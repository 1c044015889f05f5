"""Values as a user gives them and reads them: the one rule for "an integer" and for showing
a value in a message, under the argument checks of every layer (``client.args`` raises
:class:`~rcb4hv.errors.ArgumentError` with them, ``hth4.argcheck``
:class:`~rcb4hv.errors.EditError`)."""

from __future__ import annotations

import operator
from numbers import Integral, Real

__all__ = ["as_index", "plain"]


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


def plain(value: object) -> str:
    """``value`` as a user reads it: numbers (numpy's too) by their value, text quoted."""
    if isinstance(value, bool):
        return repr(value)
    if isinstance(value, Integral):
        return str(int(value))
    if isinstance(value, Real):
        return repr(float(value))
    return repr(value)
