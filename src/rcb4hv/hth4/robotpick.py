"""Which robot model a project drives: the one rule for the CLI, physics, the editor and the
dashboard.

1. An explicit ``--robot NAME|FILE``: that model (a built-in name, or a URDF file with its
   joint map; :func:`rcb4hv.robot.builtin.load_robot`).
2. Otherwise the built-in model whose joint map matches the project's servo table: the
   indices of the servos in use and, where their names say which side the even indices are,
   that side (:func:`rcb4hv.robot.builtin.detect_robot`).
3. Otherwise :class:`~rcb4hv.errors.NoRobotModelError` (also a ``RobotModelError``), naming
   the choices.

Either way a model that maps a servo index the project does not use is refused
(:func:`rcb4hv.robot.builtin.check_indices`), so a wrong ``--robot`` says which servos are
missing instead of drawing or simulating limbs that never move.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from rcb4hv.errors import NoRobotModelError
from rcb4hv.hth4.model import Project
from rcb4hv.robot.builtin import BUILTIN, check_indices, detect_robot, load_robot
from rcb4hv.robot.model import RobotModel

__all__ = ["project_model", "servo_table"]


def servo_table(project: Project) -> dict[int, str]:
    """ICS number -> display name of each servo slot ``project`` uses."""
    return {s.device_number: s.name or "" for s in project.servos if s.in_use}


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
    the project lacks, and :class:`~rcb4hv.errors.NoRobotModelError` when nothing names the
    robot.
    """
    names = servo_table(project) if isinstance(project, Project) else dict(project or {})
    used = sorted(set(names if indices is None else indices))
    if name is None:
        found = detect_robot(names, used) if names else None
        if found is None:
            why = (
                f"no built-in robot model matches this project's servos {used}"
                if names
                else "no project servo table to detect the robot from"
            )
            raise NoRobotModelError(f"{why}: name one with --robot {'|'.join(BUILTIN)}|FILE")
        name = found
    model = name if isinstance(name, RobotModel) else load_robot(name)
    if names or indices is not None:
        check_indices(model, used)
    return model
