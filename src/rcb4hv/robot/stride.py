"""Where a motion is built to take the robot: its travel when no foot ever slips.

A walk's poses say where each foot goes relative to the body; which way the robot then
moves depends on which foot holds the floor while they change. This module answers that the
way a motion designer reasons, with rigid joints and no physics: the robot stands on the
floor in each pose as :func:`rcb4hv.robot.balance.ground_frame` sets it down (the lowest
sole flat, the lowest point on the floor), and the foot it stands on -- its **anchor** --
stays where it is on the floor (position and heading). The anchor is the foot on the floor
(its lowest point within :data:`~rcb4hv.robot.geometry.CONTACT_TOLERANCE_M` of the lowest)
whose sole's middle is nearest the centre of mass: with one foot down that foot, with two
the one that carries more of the weight. When another foot becomes the anchor, it holds from
where it is then. So a pose change moves the body over the planted foot, and the robot's
travel is the sum of those moves: the *no-slip travel* (:class:`Stride`).

It needs no MuJoCo and is the same on every run. It is the motion's design, not what a robot
does on a real floor: a foot that slides, a robot that rocks onto an edge or falls, a wheel
-- none of that is in it (a robot with wheel joints gets no stride). Comparing it with the
physics outcome tells a dynamic effect (slip, rocking, a fall) from a motion that is simply
built to go that way. A turn made by sliding both feet on the floor (the KXR-L2's and the
KHR-3HV's, which have no hip yaw) is all slip, so it shows no turn. Only bipeds
(:func:`has_stride`). The tracker is fed joint angles (rad by name), one pose after
another, as often as the board sends them (:class:`StrideTracker`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from rcb4hv.robot.balance import ground_frame
from rcb4hv.robot.geometry import CONTACT_TOLERANCE_M, feet, geom_points
from rcb4hv.robot.kinematics import (
    IDENTITY,
    Transform,
    apply,
    center_of_mass,
    compose,
    forward,
    invert,
    joints_to,
)
from rcb4hv.robot.model import RobotModel, Vec3

__all__ = ["Stride", "StrideTracker", "has_stride", "stride_of"]


@dataclass(frozen=True)
class Stride:
    """A motion's no-slip travel: ``dx_m`` forward and ``dy_m`` left (m, in the frame the
    robot faced at the start), ``dyaw_deg`` counter-clockwise, and ``steps``: how many times
    the standing foot changed."""

    dx_m: float
    dy_m: float
    dyaw_deg: float
    steps: int

    def to_dict(self) -> dict[str, object]:
        return {
            "dx_m": round(self.dx_m, 5),
            "dy_m": round(self.dy_m, 5),
            "dyaw_deg": round(self.dyaw_deg, 3),
            "steps": self.steps,
        }


def has_stride(model: RobotModel) -> bool:
    """True when ``model`` walks on two feet and no wheels: a biped, whose standing sole lies
    flat on the floor. (A wheel's travel is not in the poses; a four- or six-legged robot
    stands on the plane of several feet, which this rule does not find.)"""
    if any(j.kind == "wheel" for j in model.joints):
        return False
    return len(feet(model)) == 2


def _flat(t: Transform) -> tuple[Transform, float]:
    """``t`` reduced to its position on the floor and its heading (and the heading, rad)."""
    yaw = math.atan2(t[1][0], t[0][0])
    c, s = math.cos(yaw), math.sin(yaw)
    return (
        (c, -s, 0.0, t[0][3]),
        (s, c, 0.0, t[1][3]),
        (0.0, 0.0, 1.0, 0.0),
        (0.0, 0.0, 0.0, 1.0),
    ), yaw


class StrideTracker:
    """Follows a robot's no-slip travel pose by pose (see the module docstring).

    ``update(angles)`` takes each new pose (joint angles, rad by name; joints not named keep
    their last angle, from the model's home pose); :attr:`stride` is the travel since the
    first pose. Raises ``ValueError`` for a model :func:`has_stride` refuses."""

    def __init__(self, model: RobotModel) -> None:
        if not has_stride(model):
            raise ValueError(f"{model.name}: a stride needs two feet and no wheels")
        self._model = model
        links = {link.name: link for link in model.links}
        self._soles: dict[str, list[Vec3]] = {}  # each foot's lowest face, in its own frame
        for name in feet(model):
            local = [p for g in links[name].geoms for p in geom_points(g, IDENTITY)]
            bottom = min(p[2] for p in local)
            self._soles[name] = [p for p in local if p[2] <= bottom + CONTACT_TOLERANCE_M]
        self._names = tuple(self._soles)
        self._legs = joints_to(model, self._names)  # enough to place the feet
        self._everything = joints_to(model, links)  # and the centre of mass
        self._angles: dict[str, float] = {j.name: 0.0 for j in model.joints}
        self._angles.update(model.home)
        self._last: dict[str, float] | None = None
        self._anchor: str | None = None
        self._anchor_world: Transform | None = None  # the anchor's flat pose on the floor
        self._world: Transform | None = None  # the root's pose on the floor
        self._start: tuple[float, float] | None = None
        self._heading = 0.0  # the root's heading (rad), unwrapped
        self._turn = 0.0
        self._steps = 0

    def update(self, angles: Mapping[str, float]) -> None:
        """Stand the robot in this pose, its anchor foot kept where it is on the floor."""
        self._angles.update(angles)
        if self._last == self._angles:
            return
        self._last = dict(self._angles)
        frames = forward(self._model, self._angles, joints=self._legs)
        points = {
            name: [apply(frames[name], p) for p in sole] for name, sole in self._soles.items()
        }
        ground = ground_frame(self._model, frames, points, self._names)
        low: dict[str, float] = {}
        middle: dict[str, tuple[float, float]] = {}
        for name, root_points in points.items():
            pts = [apply(ground, p) for p in root_points]
            if pts:
                low[name] = min(p[2] for p in pts)
                middle[name] = (
                    sum(p[0] for p in pts) / len(pts),
                    sum(p[1] for p in pts) / len(pts),
                )
        if not low:
            return
        touching = [f for f in low if low[f] <= min(low.values()) + CONTACT_TOLERANCE_M]
        nearest = touching[0]
        if len(touching) > 1:  # the one nearest the centre of mass carries most of it
            whole = forward(self._model, self._angles, joints=self._everything)
            com = apply(ground, center_of_mass(self._model, whole))
            nearest = min(touching, key=lambda f: math.dist(middle[f], com[:2]))
        if self._world is None or self._anchor is None or self._anchor_world is None:
            self._anchor = nearest
            self._anchor_world = _flat(compose(ground, frames[nearest]))[0]
        elif nearest != self._anchor:
            self._anchor = nearest
            self._anchor_world = _flat(compose(self._world, frames[nearest]))[0]
            self._steps += 1
        held = _flat(compose(ground, frames[self._anchor]))[0]
        self._world = compose(compose(self._anchor_world, invert(held)), ground)
        flat, heading = _flat(self._world)
        if self._start is None:
            self._start = (flat[0][3], flat[1][3])
        else:
            self._turn += math.remainder(heading - self._heading, 2 * math.pi)
        self._heading = heading

    @property
    def base(self) -> Transform | None:
        """The root link's pose on the floor now (z up, the floor at z = 0, x and y where the
        first pose stood it), None before any pose: where a 3D view draws the robot."""
        return self._world

    @property
    def stride(self) -> Stride:
        """The travel since the first pose (zero before any)."""
        if self._start is None:
            return Stride(0.0, 0.0, 0.0, 0)
        assert self._world is not None
        x0, y0 = self._start
        yaw0 = self._heading - self._turn
        c, s = math.cos(yaw0), math.sin(yaw0)
        dx, dy = self._world[0][3] - x0, self._world[1][3] - y0
        return Stride(c * dx + s * dy, -s * dx + c * dy, math.degrees(self._turn), self._steps)


def stride_of(model: RobotModel, poses: Iterable[Mapping[str, float]]) -> Stride:
    """The no-slip travel of ``model`` through ``poses`` (joint angles, rad by name)."""
    tracker = StrideTracker(model)
    for angles in poses:
        tracker.update(angles)
    return tracker.stride
