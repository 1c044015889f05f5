"""Argument checks shared by the edit functions: a value an edit accepts is one the project
file can hold, so saving never fails on it later.

Every check raises :class:`~rcb4hv.errors.EditError` naming the argument and the value.
Integers may be any integral type (``numpy.int64`` from a slider or an IK solution:
:func:`operator.index`); floats, strings and bools are refused, even ``7500.0``: a position
is a count, and a float usually means a missing ``round``.
"""

from __future__ import annotations

import unicodedata
from collections.abc import Mapping

from rcb4hv.errors import EditError, NoRobotModelError
from rcb4hv.hth4._xml import is_xml_text
from rcb4hv.robot.model import RobotModel
from rcb4hv.values import as_index, plain

__all__ = ["as_int", "as_model", "as_name", "as_positions"]


def as_int(what: str, value: object) -> int:
    """``value`` as an ``int`` (:func:`rcb4hv.values.as_index`); EditError "``what`` must be
    an int, not …" otherwise."""
    out = as_index(value)
    if out is None:
        raise EditError(f"{what} must be an int, not {plain(value)}")
    return out


def as_positions(what: str, positions: Mapping[int, int] | None) -> dict[int, int]:
    """Servo positions by ICS number as plain ints (numpy integers accepted); EditError
    naming ``what`` and the servo for a key or value that is not an integer."""
    if positions is None:
        return {}
    if not isinstance(positions, Mapping):
        raise EditError(
            f"{what}: positions are a mapping of ICS number to position, "
            f"not {type(positions).__name__}"
        )
    out: dict[int, int] = {}
    for ics, value in positions.items():
        key = as_int(f"{what}: an ICS number", ics)
        out[key] = as_int(f"{what}: ICS {key}: position", value)
    return out


def as_name(what: str, name: object) -> str:
    """A motion name: a non-blank ``str`` of printable characters that the project file
    can hold (no control characters); EditError naming ``what`` otherwise."""
    if not isinstance(name, str):
        raise EditError(f"{what} must be a str, not {type(name).__name__} {name!r}")
    if not name.strip():
        raise EditError("a motion needs a name")
    bad = [c for c in name if unicodedata.category(c) == "Cc" or not is_xml_text(c)]
    if bad:
        codes = ", ".join(f"U+{ord(c):04X}" for c in dict.fromkeys(bad))
        raise EditError(
            f"{what} {name!r} holds control characters ({codes}): a name is one line of "
            "printable text"
        )
    return name


def as_model(model: object, what: str = "model") -> RobotModel | None:
    """``model`` if it is a :class:`RobotModel` or None; NoRobotModelError otherwise (a
    robot name is loaded first: ``rcb4hv.robot.load_robot(name)``)."""
    if model is None or isinstance(model, RobotModel):
        return model
    raise NoRobotModelError(
        f"{what} must be a RobotModel (rcb4hv.robot.load_robot('kxr-l2')) or None, "
        f"not {type(model).__name__} {model!r}"
    )
