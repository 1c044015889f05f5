"""What a motion played with physics reports: :class:`PhysicsOutcome` per motion, the robot's
path (:class:`TrackPoint`), pictures of its shapes (:class:`ShapeFrame`) and the set-up of a
physics run (:class:`PhysicsSetup`); see :mod:`rcb4hv.project.physics_sim` for how each figure
is measured, :mod:`rcb4hv.project.runresult` for a whole run."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

__all__ = ["PhysicsOutcome", "PhysicsSetup", "ShapeFrame", "TrackPoint"]


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
    start_pose: str = "upright"
    fallen_at_start: bool = False

    def to_dict(self) -> dict[str, object]:
        return {
            "start_pose": self.start_pose,
            "fallen_at_start": self.fallen_at_start,
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
    to draw it (``kinematics.forward`` from the torso's pose). ``targets``: the angle (rad)
    each servo driven to an angle is commanded to (free and wheel servos left out);
    ``touching``: the links on the floor; ``com``: the robot's centre of mass (world, m);
    ``com_margin``: how far (m) its ground projection lies inside the convex hull of the floor
    contacts (negative: outside, tipping over that edge; None: touching nothing)."""

    t: float
    x: float
    y: float
    yaw: float
    tilt: float
    z: float = 0.0
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0)
    angles: Mapping[str, float] = field(default_factory=dict)
    targets: Mapping[str, float] = field(default_factory=dict)
    touching: tuple[str, ...] = ()
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    com_margin: float | None = None


@dataclass(frozen=True, slots=True)
class ShapeFrame:
    """A picture of the robot at virtual time ``t``: the corners of each of its shapes (world,
    m), for the side views of ``--plot``."""

    t: float
    shapes: list[tuple[tuple[float, float, float], ...]]


@dataclass(frozen=True)
class PhysicsSetup:
    """How a physics run was set up, and how the robot settled after the (first) boot:
    ``settled_pose`` is its pose (as ``end_pose``) :data:`settle_s` seconds after it was put
    on the floor in ``start`` (a robot that cannot stand in its start pose is down here, before
    any motion plays)."""

    robot: str
    engine: str
    start: str
    settle_s: float
    settled_pose: str
    settled_tilt_deg: float
    what_if: tuple[tuple[str, float], ...] = ()
    """The :class:`~rcb4hv.physics.PhysicsOptions` fields that differ from the documented
    figures (name, value), in field order; empty for a run on the documented model."""

    def to_dict(self) -> dict[str, object]:
        out: dict[str, object] = {
            "robot": self.robot,
            "engine": self.engine,
            "start": self.start,
            "settle_s": self.settle_s,
            "settled_pose": self.settled_pose,
            "settled_tilt_deg": round(self.settled_tilt_deg, 1),
        }
        if self.what_if:
            out["what_if"] = dict(self.what_if)
        return out
