"""What a motion played with physics reports: :class:`PhysicsOutcome` per motion, the robot's
path (:class:`TrackPoint`) and pictures (:class:`Frame`), and :class:`PhysicsRun` for a whole
run (see :mod:`rcb4hv.project.physics_sim` for how each figure is measured)."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from rcb4hv.project.simresult import MotionResult

__all__ = ["Frame", "MotionRun", "PhysicsOutcome", "PhysicsRun", "TrackPoint"]


@dataclass(frozen=True)
class PhysicsOutcome:
    """What one motion did to the simulated robot (see the module docstring)."""

    fell: bool
    fell_at_s: float | None
    end_pose: str
    dx_m: float
    dy_m: float
    dyaw_deg: float
    max_tilt_deg: float
    max_tracking_error_deg: float
    saturated_joints: tuple[str, ...]

    def to_dict(self) -> dict[str, object]:
        return {
            "fell": self.fell,
            "fell_at_s": None if self.fell_at_s is None else round(self.fell_at_s, 3),
            "end_pose": self.end_pose,
            "dx_m": round(self.dx_m, 4),
            "dy_m": round(self.dy_m, 4),
            "dyaw_deg": round(self.dyaw_deg, 1),
            "max_tilt_deg": round(self.max_tilt_deg, 1),
            "max_tracking_error_deg": round(self.max_tracking_error_deg, 1),
            "saturated_joints": list(self.saturated_joints),
        }


@dataclass(frozen=True, slots=True)
class TrackPoint:
    """The robot at one output period: virtual time (s), the torso's position (m), yaw and
    tilt (rad) and orientation (quaternion w, x, y, z), and every joint's angle (rad): enough
    to draw it (``kinematics.forward`` from the torso's pose)."""

    t: float
    x: float
    y: float
    yaw: float
    tilt: float
    z: float = 0.0
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    angles: Mapping[str, float] = field(default_factory=dict)


@dataclass(frozen=True, slots=True)
class Frame:
    """The robot at virtual time ``t``: the corners of each of its shapes (world, m)."""

    t: float
    shapes: list[tuple[tuple[float, float, float], ...]]


@dataclass(frozen=True)
class MotionRun:
    """One motion played with physics: its result, outcome and (``track``) the robot's path
    and frames from the motion's start until it has settled after its end."""

    result: MotionResult
    outcome: PhysicsOutcome
    track: tuple[TrackPoint, ...] = ()
    frames: tuple[Frame, ...] = ()


@dataclass(frozen=True)
class PhysicsRun:
    """:func:`play_physics`'s answer: the (first) boot, each motion, the virtual seconds."""

    boot: MotionResult
    motions: tuple[MotionRun, ...]
    virtual_s: float
