"""Where a motion is built to take the robot: its travel when no foot ever slips.

A walk's poses say where each foot goes relative to the body; which way the robot then
moves depends on which feet hold the floor while they change. This module answers that the
way a motion designer reasons, with rigid joints and no physics: in each pose the robot is
set down on the floor, and the feet it stands on stay where they are. The sum of the body's
moves over its planted feet is the motion's **no-slip travel** (:class:`Stride`).

- **A biped** stands on its lowest sole, laid flat on the floor
  (:func:`rcb4hv.robot.balance.ground_frame`), and the foot it stands on -- its anchor --
  keeps its place and heading on the floor. With both feet down (their lowest points within
  :data:`~rcb4hv.robot.balance.CONTACT_TOL`, the set-down's own rule), the one whose sole's
  middle is nearer the centre of mass holds: it carries more of the weight. When the other
  foot becomes the anchor it holds from where it is then.
- **A robot on more feet** (four, six legs) rests on the plane of several feet: it is set
  down as a rigid body settles (:func:`rcb4hv.robot.balance.set_down`, which tips it over an
  edge until its centre of mass is over the feet touching), and the touching feet's
  contact points then move as little as friction allows: the body's move on the floor is the
  one with the least friction work (each point's slip times the force it presses on the
  floor with, :func:`~rcb4hv.robot.balance.floor_forces`; quasi-static Coulomb friction).
  A leg tip is nearly a point, so the feet together hold the heading, not one of them.

It needs no MuJoCo and is the same on every run. It is the motion's design, not what a robot
does on a real floor: a foot that slides, a robot that rocks onto an edge or falls, inertia
-- none of that is in it, and a robot with wheels gets no stride (:func:`has_stride`).
Comparing it with the physics outcome tells a dynamic effect from a motion that is simply
built to go that way. A biped's turn made by sliding both feet on the floor (the KXR-L2's and
the KHR-3HV's, which have no hip yaw) is all slip, so it shows no turn. The tracker is fed
joint angles (rad by name), one pose after another, as often as the board sends them
(:class:`StrideTracker`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Final

from rcb4hv.robot.balance import CONTACT_TOL, Point2, floor_forces, ground_frame, set_down
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

FIT_ITERATIONS: Final = 30
"""Rounds of reweighting in the least-friction-work fit (:func:`_fit`); it settles in a few."""
SLIP_FLOOR_M: Final = 1e-6
"""Slips below this count as this in the fit's reweighting (a micrometre: no slip)."""


@dataclass(frozen=True)
class Stride:
    """A motion's no-slip travel: ``dx_m`` forward and ``dy_m`` left (m, in the frame the
    robot faced at the start), ``dyaw_deg`` counter-clockwise, and ``steps``: how many times
    a foot was put down (a biped's: how often the standing foot changed)."""

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
    """True when ``model`` stands on two feet or more and has no wheels (a wheel's travel is
    not in the poses)."""
    if any(j.kind == "wheel" for j in model.joints):
        return False
    return len(feet(model)) >= 2


def _floor(turn: float, x: float, y: float) -> Transform:
    """A placement on the floor: turned by ``turn`` (rad) about the vertical, shifted by x, y."""
    c, s = math.cos(turn), math.sin(turn)
    return ((c, -s, 0.0, x), (s, c, 0.0, y), (0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 1.0))


def _flat(t: Transform) -> Transform:
    """``t`` reduced to its place on the floor: its position and the heading of its x axis."""
    return _floor(math.atan2(t[1][0], t[0][0]), t[0][3], t[1][3])


def _procrustes(
    pairs: Sequence[tuple[Point2, Point2, float]], heading: float
) -> tuple[float, float, float]:
    """The turn and shift (rad, m, m) that carry each ``p`` nearest its ``q`` in the least
    squares weighted by ``w`` (a 2D Procrustes fit); with points that fix no turn (one, or
    all at one place) the turn stays ``heading``."""
    total = sum(w for _, _, w in pairs)
    px = sum(p[0] * w for p, _, w in pairs) / total
    py = sum(p[1] * w for p, _, w in pairs) / total
    qx = sum(q[0] * w for _, q, w in pairs) / total
    qy = sum(q[1] * w for _, q, w in pairs) / total
    dot = cross = 0.0
    for p, q, w in pairs:
        ax, ay, bx, by = p[0] - px, p[1] - py, q[0] - qx, q[1] - qy
        dot += w * (ax * bx + ay * by)
        cross += w * (ax * by - ay * bx)
    turn = math.atan2(cross, dot) if math.hypot(dot, cross) > 1e-12 else heading
    c, s = math.cos(turn), math.sin(turn)
    return turn, qx - (c * px - s * py), qy - (s * px + c * py)


def _fit(
    pairs: Sequence[tuple[Point2, Point2, float]], heading: float
) -> tuple[float, float, float]:
    """The turn and shift that move the contact points ``p`` to their places ``q`` on the
    floor with the least friction work: the sum of each point's slip times the force ``w``
    it presses on the floor with, minimised (Coulomb friction, quasi-static). Solved by
    iteratively reweighted least squares; where one foot carries more of the weight it
    holds and the others slide."""
    turn, x, y = _procrustes(pairs, heading)
    for _ in range(FIT_ITERATIONS):
        c, s = math.cos(turn), math.sin(turn)
        again = [
            (p, q, w / max(math.hypot(c * p[0] - s * p[1] + x - q[0],
                                       s * p[0] + c * p[1] + y - q[1]), SLIP_FLOOR_M))
            for p, q, w in pairs
        ]  # fmt: skip
        turn2, x2, y2 = _procrustes(again, turn)
        done = abs(turn2 - turn) < 1e-9 and math.hypot(x2 - x, y2 - y) < 1e-9
        turn, x, y = turn2, x2, y2
        if done:
            break
    return turn, x, y


class StrideTracker:
    """Follows a robot's no-slip travel pose by pose (see the module docstring).

    ``update(angles)`` takes each new pose (joint angles, rad by name; joints not named keep
    their last angle, from the model's home pose); :attr:`stride` is the travel since the
    first pose and :attr:`base` where the robot stands now. Raises ``ValueError`` for a
    model :func:`has_stride` refuses."""

    def __init__(self, model: RobotModel) -> None:
        if not has_stride(model):
            raise ValueError(f"{model.name}: a stride needs two feet or more and no wheels")
        self._model = model
        links = {link.name: link for link in model.links}
        corners = {  # each foot's shape corners, in its own frame
            name: [p for g in links[name].geoms for p in geom_points(g, IDENTITY)]
            for name in feet(model)
        }
        self._biped = len(corners) == 2
        if self._biped:  # a sole: the foot's lowest face
            for name, local in corners.items():
                bottom = min(p[2] for p in local)
                corners[name] = [p for p in local if p[2] <= bottom + CONTACT_TOLERANCE_M]
        self._corners = corners
        self._names = tuple(corners)
        self._legs = joints_to(model, self._names)  # enough to place the feet
        self._angles: dict[str, float] = {j.name: 0.0 for j in model.joints}
        self._angles.update(model.home)
        self._last: dict[str, float] | None = None
        self._world: Transform | None = None  # the root's pose on the floor
        self._anchor: str | None = None  # a biped's standing foot
        self._anchor_world: Transform | None = None  # and its flat pose on the floor
        self._placed: dict[tuple[str, int], Point2] = {}  # touching points on the floor
        self._floor: Transform = IDENTITY  # the set-down robot's placement on the floor
        self._start: tuple[float, float] | None = None
        self._heading = 0.0  # the root's heading (rad)
        self._turn = 0.0  # and how far it turned since the first pose, unwrapped
        self._steps = 0

    def update(self, angles: Mapping[str, float]) -> None:
        """Set the robot down in this pose, the feet it stands on kept where they are."""
        self._angles.update(angles)
        if self._last == self._angles:
            return
        self._last = dict(self._angles)
        world = self._stand_biped() if self._biped else self._stand_on_many()
        if world is None:
            return
        self._world = world
        # the twist of the root's orientation about the vertical (as the physics reports it)
        heading = math.atan2(world[1][0] - world[0][1], world[0][0] + world[1][1])
        if self._start is None:
            self._start = (world[0][3], world[1][3])
        else:
            self._turn += math.remainder(heading - self._heading, 2 * math.pi)
        self._heading = heading

    def _stand_biped(self) -> Transform | None:
        model = self._model
        frames = forward(model, self._angles, joints=self._legs)
        points = {
            name: [apply(frames[name], p) for p in sole] for name, sole in self._corners.items()
        }
        ground = ground_frame(model, frames, points, self._names)
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
            return None
        touching = [f for f in low if low[f] <= min(low.values()) + CONTACT_TOL]
        nearest = touching[0]
        if len(touching) > 1:  # the one nearest the centre of mass carries most of it
            com = apply(ground, center_of_mass(model, forward(model, self._angles)))
            nearest = min(touching, key=lambda f: math.dist(middle[f], com[:2]))
        if self._world is None or self._anchor is None or self._anchor_world is None:
            self._anchor = nearest
            self._anchor_world = _flat(compose(ground, frames[nearest]))
        elif nearest != self._anchor:
            self._anchor = nearest
            self._anchor_world = _flat(compose(self._world, frames[nearest]))
            self._steps += 1
        held = _flat(compose(ground, frames[self._anchor]))
        return compose(compose(self._anchor_world, invert(held)), ground)

    def _stand_on_many(self) -> Transform | None:
        model = self._model
        frames = forward(model, self._angles)
        points = {
            name: [apply(frames[name], p) for p in corners]
            for name, corners in self._corners.items()
        }
        down = set_down(model, frames, center_of_mass(model, frames), points, self._names)
        now: dict[tuple[str, int], Vec3] = {}
        for name, pts in points.items():
            for k, p in enumerate(pts):
                q = apply(down.ground, p)
                if q[2] <= CONTACT_TOL:
                    now[(name, k)] = q
        forces = dict(zip(now, floor_forces(1.0, down.com, list(now.values())), strict=True))
        held = [
            ((q[0], q[1]), self._placed[key], forces[key])
            for key, q in now.items()
            if key in self._placed and forces[key] > 0.0
        ]
        if self._world is not None:
            self._steps += len({n for n, _ in now} - {n for n, _ in self._placed})
        if held:
            turn, x, y = _fit(held, math.atan2(self._floor[1][0], self._floor[0][0]))
            self._floor = _floor(turn, x, y)
        floor = self._floor  # nothing held: the placement on the floor stays
        self._placed = {key: apply(floor, q)[:2] for key, q in now.items()}
        return compose(floor, down.ground)

    @property
    def base(self) -> Transform | None:
        """The root link's pose on the floor now (z up, the floor at z = 0, x and y where the
        first pose stood it), None before any pose: where a 3D view draws the robot."""
        return self._world

    @property
    def stride(self) -> Stride:
        """The travel since the first pose (zero before any)."""
        if self._start is None or self._world is None:
            return Stride(0.0, 0.0, 0.0, 0)
        x0, y0 = self._start
        heading0 = self._heading - self._turn
        c, s = math.cos(heading0), math.sin(heading0)
        dx, dy = self._world[0][3] - x0, self._world[1][3] - y0
        return Stride(c * dx + s * dy, -s * dx + c * dy, math.degrees(self._turn), self._steps)


def stride_of(model: RobotModel, poses: Iterable[Mapping[str, float]]) -> Stride:
    """The no-slip travel of ``model`` through ``poses`` (joint angles, rad by name)."""
    tracker = StrideTracker(model)
    for angles in poses:
        tracker.update(angles)
    return tracker.stride
