"""The built-in robots by name, loading a robot by name or file, and detecting a project's robot.

This layer sits below :mod:`rcb4hv.hth4`: callers pass a project's servo table as plain data
(the servo names and ICS numbers of the slots in use), e.g. from
``Project.servos`` (``name``, ``ics_number``, ``in_use``).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping
from functools import cache
from pathlib import Path
from typing import Literal

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.khr3hv import khr3hv, khr3hv_22
from rcb4hv.robot.kxr import kxr_l2, kxr_l2_gripper
from rcb4hv.robot.model import RobotModel, side_of_name

__all__ = [
    "BUILTIN",
    "check_indices",
    "detect_robot",
    "even_side",
    "load_builtin",
    "load_robot",
]

BUILTIN = ("khr3hv", "khr3hv-22", "kxr-l2", "kxr-l2-gripper")

_FACTORIES: dict[str, Callable[[], RobotModel]] = {
    "khr3hv": khr3hv,
    "khr3hv-22": khr3hv_22,
    "kxr-l2": kxr_l2,
    "kxr-l2-gripper": kxr_l2_gripper,
}


def load_builtin(name: str) -> RobotModel:
    """The built-in model ``name`` (one of :data:`BUILTIN`, in any case: ``KHR3HV``, ``KXR-L2``);
    models are immutable, so each is built once."""
    if name.lower() not in _FACTORIES:
        raise RobotModelError(
            f"unknown robot {name!r}: choose one of {', '.join(BUILTIN)}, a KXR kit code "
            "(kxr:CODE, e.g. kxr:L2L5A3), or give a URDF file with its joint map"
        )
    return _builtin(name.lower())


@cache
def _builtin(name: str) -> RobotModel:
    return _FACTORIES[name]()


@cache
def _kit(text: str) -> RobotModel:
    """The stock build of a kit code ``kxr:CODE`` (:mod:`rcb4hv.robot.kit`)."""
    from rcb4hv.robot.kit import kit_model, parse_kit_code

    return kit_model(parse_kit_code(text, strict=True))  # a typed code: every part read


def load_robot(name_or_path: str | os.PathLike[str], joint_map: str | None = None) -> RobotModel:
    """A built-in model by name, a KXR kit code (``kxr:L6``), or a URDF file (``.urdf``)
    with its joint-map file (TOML; by default the URDF's path with ``.toml``, see
    :mod:`rcb4hv.robot.jointmap`)."""
    text = os.fspath(name_or_path)
    if text in _FACTORIES:
        return load_builtin(text)
    if text.lower().startswith("kxr:"):
        return _kit(text)
    path = Path(text)
    if path.is_file():
        from rcb4hv.robot.jointmap import load_urdf_robot

        return load_urdf_robot(path, joint_map)
    if path.suffix or os.sep in text or "/" in text:
        raise RobotModelError(f"{text}: no such robot file")
    return load_builtin(text)  # raises, listing the choices


# --------------------------------------------------------------------- detection


def even_side(names: Mapping[int, str]) -> Literal["left", "right"] | None:
    """Which side a project's even indices (SIO1-4) drive, from its servo names
    (:func:`~rcb4hv.robot.model.side_of_name`): "right", "left", or None when no name states
    a side or two names disagree (no vote: the index set alone then decides)."""
    found = set()
    for index, name in names.items():
        side = side_of_name(name)
        if side is not None:
            found.add(side if index % 2 == 0 else ("left" if side == "right" else "right"))
    return found.pop() if len(found) == 1 else None


def detect_robot(
    servo_names: Mapping[int, str] | Iterable[tuple[int, str]],
    indices: Iterable[int] | None = None,
) -> str | None:
    """The built-in robot a project drives, from its servo table, or None when that is
    ambiguous.

    ``servo_names``: servo index (ICS number) -> display name of each slot in use; ``indices``:
    the indices in use (default: the keys of ``servo_names``). A built-in model matches when
    it maps exactly those indices and, where the names say which side the even indices are
    (右/左, right/left), that side agrees (the KHR-3HV has the left on even indices, the
    KXR-L2 the right). Returns the one matching name, or None.
    """
    names = dict(servo_names)
    used = frozenset(names if indices is None else indices)
    side = even_side({i: n for i, n in names.items() if i in used})
    models = [load_builtin(name) for name in BUILTIN]
    matches = [
        m.name
        for m in models
        if frozenset(m.indices) == used
        and (side is None or even_side({s.index: s.joint for s in m.servos}) == side)
    ]
    return matches[0] if len(matches) == 1 else None


def check_indices(model: RobotModel, indices: Iterable[int]) -> None:
    """Raise :class:`RobotModelError` when ``model`` maps a servo index the project lacks
    (``indices``: the project's servo indices in use)."""
    have = set(indices)
    missing = [s for s in model.servos if s.index not in have]
    if missing:
        listed = ", ".join(f"{s.index} ({s.joint})" for s in missing)
        raise RobotModelError(
            f"{model.name}: the project has no servo at index {listed}; "
            f"it uses {sorted(have) or 'none'}"
        )
