"""Which robot model the dashboard draws (the 3D view) and names joints from (servo table).

In this order:

1. ``rcb4hv ui --robot NAME|FILE``: that model, always (the view may show a robot before any
   project is open).
2. An open project whose servo table names a built-in robot: the same rule as the CLI,
   physics and the editor (:func:`rcb4hv.hth4.robotpick.project_model`).
3. The board's own servo table: the built-in model that maps every servo the board has, with
   the fewest joints to spare. The default emulator board (17 servos: head, three per arm, five
   per leg, left on SIO1-4, see :mod:`rcb4hv.rom.default`) is a subset of the 22-axis KHR-3HV
   only, so it gets ``khr3hv-22``.
4. Otherwise :data:`DEFAULT_ROBOT`.
"""

from __future__ import annotations

import logging
from collections.abc import Iterable
from typing import NamedTuple

from rcb4hv.errors import AmbiguousRobotError, NoRobotModelError, RobotModelError
from rcb4hv.hth4 import Project
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.robot import RobotModel
from rcb4hv.robot.builtin import BUILTIN, load_builtin

__all__ = ["DEFAULT_ROBOT", "RobotChoice", "board_robot", "choose_robot", "named_or_detected"]

log = logging.getLogger(__name__)

DEFAULT_ROBOT = "khr3hv"
"""The robot the RCB-4HV ships in (Kondo's KHR-3HV kit), when nothing else tells."""


def board_robot(indices: Iterable[int]) -> str | None:
    """The built-in model mapping every servo index in ``indices`` with the fewest extra
    joints (None if none maps them all, or two fit equally well)."""
    have = set(indices)
    if not have:
        return None
    fits = sorted(
        (len(load_builtin(n).indices) - len(have), n)
        for n in BUILTIN
        if have <= set(load_builtin(n).indices)
    )
    if not fits or (len(fits) > 1 and fits[0][0] == fits[1][0]):
        return None
    return fits[0][1]


class RobotChoice(NamedTuple):
    """The model the dashboard uses, where it came from, and the models the open project fits
    when its evidence fits several (none picked yet: the dashboard offers them)."""

    model: RobotModel
    source: str
    candidates: tuple[str, ...] = ()


def named_or_detected(named: str | RobotModel, project: Project) -> tuple[RobotModel, str]:
    """``--robot``'s model (a name or a loaded model) when it fits ``project``, else the model
    detected from the project and why the named one was not taken (the one rule for every
    page: a KHR-3HV named for a KXR-L2 project draws and plays nothing the project drives).
    Raises what detection raises when the named model does not fit and none is detected."""
    try:
        return project_model(project, named), ""
    except RobotModelError as exc:
        name = named if isinstance(named, str) else named.name
        return project_model(project), f"--robot {name} does not fit this project ({exc})"


def choose_robot(
    spec: str | None, project: Project | None, board_indices: Iterable[int]
) -> RobotChoice:
    """The model by the rules of this module, from one detection of the project; ``spec`` is
    ``--robot`` (raises :class:`~rcb4hv.errors.RobotModelError` when it names no robot)."""
    if spec is not None:
        if project is not None:
            try:
                model, why = named_or_detected(spec, project)
            except RobotModelError:  # nothing fits better: the named model, as given
                log.info("--robot %s does not fit the open project, nor does any", spec)
            else:
                return RobotChoice(
                    model, f"detected from the project; {why}" if why else f"--robot {spec}"
                )
        return RobotChoice(project_model(None, spec), f"--robot {spec}")
    asks = ""
    candidates: tuple[str, ...] = ()
    if project is not None:
        try:
            return RobotChoice(project_model(project), "detected from the project")
        except AmbiguousRobotError as exc:  # the Editor page offers the candidates
            candidates = tuple(exc.candidates)
            asks = f"; the project fits {', '.join(candidates)}: pick one on the Editor page"
        except NoRobotModelError:
            log.info("the open project names no built-in robot")
    name = board_robot(board_indices)
    if name is not None:
        return RobotChoice(load_builtin(name), "matches the board's servos" + asks, candidates)
    log.info("no robot detected: drawing the default %s", DEFAULT_ROBOT)
    return RobotChoice(load_builtin(DEFAULT_ROBOT), "default" + asks, candidates)
