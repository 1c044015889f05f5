"""The parts every KXR frame is built of: joint axes, the wheel's limits, the chosen torso
boxes, and the slots (joints with their shapes) the templates put together
(:mod:`rcb4hv.robot.kit.templates`, :mod:`rcb4hv.robot.kit.legged`)."""

from __future__ import annotations

from dataclasses import replace

from rcb4hv.robot.kit.assembly import Slot, cylinder_y
from rcb4hv.robot.kit.figures import fig
from rcb4hv.robot.model import Geom, JointKind, Vec3
from rcb4hv.robot.servos import TRAVEL_DEG

__all__ = [
    "AXIS",
    "TORSO",
    "WHEEL_LIMITS",
    "Z_DOWN",
    "X",
    "Y",
    "Z",
    "add",
    "joint_slot",
    "span",
    "wheel_slot",
]

X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
Z_DOWN = (0.0, 0.0, -1.0)
AXIS: dict[JointKind, Vec3] = {
    "pitch": Y,
    "roll": X,
    "yaw": Z,
    "wheel": Y,
    "grip": (-1.0, 0.0, 0.0),
}
WHEEL_LIMITS = (-TRAVEL_DEG, TRAVEL_DEG)  # a wheel's "angle" is its speed command

# chosen torso boxes (size, centre; mm): the body between the hips/shoulders of each family
TORSO: dict[str, tuple[Vec3, Vec3]] = {
    "humanoid": ((50.0, 69.0, 95.0), (-7.25, 0.0, 37.5)),
    "L6": ((150.0, 87.0, 40.0), (0.0, 0.0, 5.0)),
    "L4T": ((110.0, 105.0, 40.0), (0.0, 0.0, 5.0)),
    "L4D": ((160.0, 70.0, 40.0), (0.0, 0.0, 10.0)),
}


def add(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def joint_slot(
    name: str,
    parent: str | None,
    pos: Vec3,
    kind: JointKind,
    limits: tuple[float, float],
    geoms: tuple[Geom, ...],
    centre: bool = False,
    axis: Vec3 | None = None,
) -> Slot:
    return Slot(name, parent, pos, axis or AXIS[kind], kind, limits, geoms, centre)


def span(a: Vec3, b: Vec3) -> float:
    return max(abs(a[k] - b[k]) for k in range(3))


def wheel_slot(name: str, parent: str, axle: Vec3, tyre_at: Vec3 = (0.0, 0.0, 0.0)) -> Slot:
    """A wheel turning about ``axle`` (its joint), its tyre ``tyre_at`` along from it."""
    tyre = cylinder_y(fig("wheel.radius"), fig("wheel.width"), add(axle, tyre_at))
    return replace(joint_slot(name, parent, axle, "wheel", WHEEL_LIMITS, (tyre,)), optional=True)
