"""Bring your own robot: a URDF plus a joint-map file (work in progress)."""

from __future__ import annotations

import os

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.model import RobotModel

__all__ = ["load_urdf_robot"]


def load_urdf_robot(
    path: str | os.PathLike[str], joint_map: str | os.PathLike[str] | None = None
) -> RobotModel:
    """A robot from a URDF file and its joint map."""
    raise RobotModelError(f"{os.fspath(path)}: URDF robots are not supported yet")
