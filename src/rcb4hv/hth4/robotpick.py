"""Which robot model a project drives: the one rule for the CLI, physics, the editor and the
dashboard.

1. An explicit ``--robot NAME|FILE``: that model (a built-in name, a kit code ``kxr:CODE``,
   or a URDF file with its joint map; :func:`rcb4hv.robot.builtin.load_robot`). A kit code
   on a project builds the kit's frame with the project's own servo names (its joint map),
   so ``--robot kxr:L4T`` settles an ambiguous project; a code whose frame the names
   contradict is refused for every family, naming the servo and the joint (names that say
   nothing take the code's stock build; :func:`rcb4hv.robot.kit.detect.detect_kit`).
2. Otherwise the project's own evidence (:func:`detect_project`):

   * a title carrying a KXR kit code (``Hello_KXR-L6(V1.0)``): the kit model built from the
     code and the servo names (:func:`rcb4hv.robot.kit.detect_kit`);
   * else the built-in model whose joint map matches the servo table (indices in use and,
     where the names say, which side the even indices are;
     :func:`rcb4hv.robot.builtin.detect_robot`), unless the servo names describe a
     legged KXR kit, which wins;
   * else a kit model from the servo names alone.

   A kit model equal to a built-in one (the KXR-L2 with or without grippers) is the
   built-in one.
3. Otherwise :class:`~rcb4hv.errors.NoRobotModelError` (also a ``RobotModelError``), naming
   the choices, or :class:`~rcb4hv.errors.AmbiguousRobotError` listing the candidates.

Either way a model that maps a servo index the project does not use is refused
(:func:`rcb4hv.robot.builtin.check_indices`), so a wrong ``--robot`` says which servos are
missing instead of drawing or simulating limbs that never move.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Iterable, Mapping

from rcb4hv.errors import AmbiguousRobotError, NoRobotModelError
from rcb4hv.hth4.model import Project
from rcb4hv.hth4.poses import motion_poses
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD, POSITION_MAX, POSITION_MIN
from rcb4hv.robot.builtin import BUILTIN, check_indices, detect_robot, load_builtin, load_robot
from rcb4hv.robot.kit import Detection, detect_kit, parse_kit_code
from rcb4hv.robot.model import RobotModel

__all__ = ["detect_project", "home_pose", "motion_extremes", "project_model", "servo_table"]

log = logging.getLogger(__name__)

_HOME = re.compile(r"ホーム|home", re.I)
_EQUIVALENT = ("kxr-l2", "kxr-l2-gripper")


def servo_table(project: Project) -> dict[int, str]:
    """ICS number -> display name of each servo slot ``project`` uses."""
    return {s.device_number: s.name or "" for s in project.servos if s.in_use}


def home_pose(project: Project) -> dict[int, int]:
    """The motion values of the project's home pose: where its first used motion named home
    position (``ホームポジション``, ``home``) leaves the servos, each at the last value a pose
    gave it (a pose that moves a few servos keeps the others where the earlier poses put
    them; hold keeps a value, free drops it); {} when it has none."""
    for motion in project.used_motions:
        if motion.name and _HOME.search(motion.name):
            state: dict[int, int] = {}
            for pose in motion_poses(motion):
                for i, v in pose.values.items():
                    if v == POSITION_FREE:
                        state.pop(i, None)
                    elif v != POSITION_HOLD:
                        state[i] = v
            if state:
                return state
    return {}


def motion_extremes(project: Project) -> dict[int, tuple[int, int]]:
    """The smallest and largest value each ICS number takes in the poses of the project's
    used motions, of the values within the servo's travel (3500-11500; Kondo's motions send
    2100 or 12700 only to push a joint to its end): what its mechanical limits must allow."""
    out: dict[int, tuple[int, int]] = {}
    for motion in project.used_motions:
        for pose in motion_poses(motion):
            for i, v in pose.values.items():
                if POSITION_MIN <= v <= POSITION_MAX:
                    lo, hi = out.get(i, (v, v))
                    out[i] = (min(lo, v), max(hi, v))
    return out


def _builtin_twin(model: RobotModel) -> RobotModel:
    """The built-in model with exactly ``model``'s joint map, else ``model``."""
    mine = {(s.index, s.joint, s.sign) for s in model.servos}
    for name in _EQUIVALENT:
        twin = load_builtin(name)
        if {(s.index, s.joint, s.sign) for s in twin.servos} == mine:
            return twin
    return model


def detect_project(
    project: Project | Mapping[int, str], name: str | None = None, title: str = ""
) -> tuple[RobotModel, Detection | None]:
    """The model of ``project`` (or of a servo table with its ``title``) by rules 1-2 of the
    module docstring and its evidence (None for a built-in found by its servo table or named
    by ``name``)."""
    extremes: dict[int, tuple[int, int]] = {}
    if isinstance(project, Project):
        names, title, home = servo_table(project), project.project_title or "", home_pose(project)
        extremes = motion_extremes(project)
    else:
        names, home = dict(project), {}
    if name is not None:
        code = parse_kit_code(name, strict=True) if name.lower().startswith("kxr:") else None
        if code is None or not names:
            return load_robot(name), None
        det = detect_kit(title, names, home, force=code, extremes=extremes)
        if det.model.name != code.name:  # never wrong in silence: say why it is not the code
            log.log(
                logging.WARNING if det.conflicts else logging.INFO,
                "--robot %s: the project's servo names make it %s (%s)",
                code.name,
                det.model.name,
                "; ".join(det.conflicts) or "the names complete the code",
            )
        return det.model, det
    if parse_kit_code(title) is not None:
        det = detect_kit(title, names, home, extremes=extremes)
        return _builtin_twin(det.model), det
    legged: Detection | None = None
    ambiguous: AmbiguousRobotError | None = None
    try:
        legged = detect_kit(None, names, home, extremes=extremes)
    except AmbiguousRobotError as exc:
        ambiguous = exc
    except NoRobotModelError as exc:
        log.debug("no kit from the servo names: %s", exc)
    found = detect_robot(names, sorted(names)) if names else None
    if legged is not None and legged.model.name.startswith("kxr:L2") is False:
        return legged.model, legged
    if found is not None:
        return load_builtin(found), None
    if legged is not None and "KHR" not in title.upper():
        return _builtin_twin(legged.model), legged
    if ambiguous is not None:
        raise ambiguous
    used = sorted(names)
    why = (
        f"no built-in robot model matches this project's servos {used}"
        if names
        else "no project servo table to detect the robot from"
    )
    raise NoRobotModelError(f"{why}: name one with --robot {'|'.join(BUILTIN)}|kxr:CODE|FILE")


def project_model(
    project: Project | Mapping[int, str] | None,
    name: str | RobotModel | None = None,
    indices: Iterable[int] | None = None,
) -> RobotModel:
    """The robot model ``project`` drives (see the module docstring).

    ``project``: a project, or its servo table (:func:`servo_table`; None when there is none,
    e.g. a bare ROM image); ``name``: ``--robot`` (or the model it loaded); ``indices``: the
    servo indices in use (default: the servo table's). Raises
    :class:`~rcb4hv.errors.RobotModelError` for an unknown name or a model needing servos
    the project lacks, :class:`~rcb4hv.errors.NoRobotModelError` when nothing names the
    robot and :class:`~rcb4hv.errors.AmbiguousRobotError` when the evidence fits several.
    """
    names = servo_table(project) if isinstance(project, Project) else dict(project or {})
    used = sorted(set(names if indices is None else indices))
    if isinstance(name, RobotModel):
        model = name
    elif project is None or (not names and not isinstance(project, Project)):
        if name is None:
            raise NoRobotModelError(
                "no project servo table to detect the robot from: name one with "
                f"--robot {'|'.join(BUILTIN)}|kxr:CODE|FILE"
            )
        model = load_robot(name)
    else:
        if indices is not None:
            names = {i: n for i, n in names.items() if i in set(used)}
        source: Project | Mapping[int, str] = project if isinstance(project, Project) else names
        model, _ = detect_project(source, name)
    if names or indices is not None:
        check_indices(model, used)
    return model
