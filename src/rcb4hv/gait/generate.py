"""A walk for a robot model: the pattern (:mod:`rcb4hv.gait.pattern`) through the one IK
(:func:`rcb4hv.robot.ik.solve_feet`) into joint angles per output period, and into a
HeartToHeart4 motion (:mod:`rcb4hv.hth4.keyframes`).

The robot's figures come from its model: the feet (the two leg effectors), their distance
apart, the leg's length (hip to ankle, straight), the torso's height over the ankles and the
centre of mass (:func:`rcb4hv.robot.kinematics.center_of_mass`) at the home pose. The walk
bends the knees: the hips sink until the leg is :data:`CROUCH` of its length (or as low as
the home pose already is), so the knee has room to lift and reach. The arms stay at home.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

from rcb4hv.errors import GaitError, RobotModelError
from rcb4hv.gait.pattern import Direction, GaitParams, Trajectory, trajectory
from rcb4hv.robot.geometry import CONTACT_TOLERANCE_M, geom_points, stance
from rcb4hv.robot.ik import effectors, limb, solve_feet
from rcb4hv.robot.kinematics import (
    IDENTITY,
    Transform,
    center_of_mass,
    compose,
    forward,
    position,
    rotation_about,
    translation,
)
from rcb4hv.robot.model import RobotModel

__all__ = ["CROUCH", "Body", "Walk", "default_params", "walk"]

log = logging.getLogger(__name__)

CROUCH = 0.88
"""Hip-to-ankle distance while walking, as a share of the straight leg: a documented choice
(knees bent enough to lift a foot and to reach a stride without a straight knee)."""
STRIDE_FORWARD = 0.25
STRIDE_SIDE = 0.12
LIFT = 0.15
WIDTH_MIN = 1.0
"""Defaults per leg length: the forward stride, the side stride and the foot lift as
shares of the leg (hip to ankle, straight); the feet stay at least as far apart as at home.
Documented choices, scaled so a 0.1 m leg walks 25 mm steps with 15 mm lift."""
STEP_TIME = 0.5
"""Default duration of one step (s): a documented choice, about Kondo's sample walks'."""
TURN_DEG = 10.0
"""Default turn per step (degrees)."""
UP = (0.0, 0.0, 1.0)


@dataclass(frozen=True)
class Body:
    """What a walk needs to know of a robot: its foot links, their home transforms (torso
    frame), the leg length, the torso's height over the ankles while walking, the centre of
    mass (torso frame) and its height over the floor while walking."""

    left: str
    right: str
    home_left: Transform
    home_right: Transform
    leg: float
    height: float
    com: tuple[float, float]
    zc: float
    soles: tuple[tuple[float, float], tuple[float, float]] = ((0.0, 0.0), (0.0, 0.0))

    @property
    def width(self) -> float:
        return abs(self.home_left[1][3] - self.home_right[1][3])

    @classmethod
    def of(cls, model: RobotModel) -> Body:
        feet = [n for n, kind in effectors(model).items() if kind == "foot"]
        if len(feet) != 2:
            raise RobotModelError(
                f"{model.name}: walks are generated for two-legged robots (two feet, below "
                "the hands), and this is none: a robot on more legs or on wheels walks with "
                "its own project's motions"
            )
        frames = forward(model, model.home)
        left, right = sorted(feet, key=lambda n: -frames[n][1][3])
        zero = forward(model, {})
        hip = position(compose(zero[limb(model, left)[0].parent], _origin(model, left)))
        leg = math.dist(hip, position(zero[left]))
        home_drop = -(frames[left][2][3] + frames[right][2][3]) / 2.0
        hip_home = position(compose(frames[limb(model, left)[0].parent], _origin(model, left)))
        reach = math.dist(hip_home, position(frames[left]))
        sink = max(0.0, reach - CROUCH * leg)
        com = center_of_mass(model, frames)
        floor_com = stance(model, model.home).com[2]
        return cls(
            left, right, frames[left], frames[right], leg, home_drop - sink,
            (com[0], com[1]), floor_com - sink, (_sole(model, left), _sole(model, right)),
        )  # fmt: skip


KNEE_SEED_RAD = 0.3
"""How far the first pose's IK starts with each straight knee bent (rad): a robot whose home
stands on straight legs (Kondo's KHR-3HV sample homes at 7500) is at the knee's singularity,
where the IK may bend it either way."""


def knees_forward(model: RobotModel, feet: tuple[str, ...]) -> dict[str, float]:
    """``model``'s home pose with each straight knee of the legs ending at ``feet`` bent the
    way a knee bends (the ankle goes behind it), as the IK's start: from straight legs it bent
    the KHR-3HV's knees backwards (project check: past the advisory range on every walk)."""
    seed = dict(model.home)
    for foot in feet:
        for j in limb(model, foot):
            if "knee" not in j.name or abs(seed.get(j.name, 0.0)) > 0.05:
                continue
            x = {
                sign: forward(model, {**seed, j.name: sign * KNEE_SEED_RAD})[foot][0][3]
                for sign in (1.0, -1.0)
            }
            seed[j.name] = KNEE_SEED_RAD * (1.0 if x[1.0] < x[-1.0] else -1.0)
    return seed


def _sole(model: RobotModel, foot: str) -> tuple[float, float]:
    """The middle of the foot's lowest points (its sole), from the ankle, in the foot frame
    at the zero pose (where the models stand with level soles)."""
    pts = [p for g in model.link(foot).geoms for p in geom_points(g, IDENTITY)]
    if not pts:
        return (0.0, 0.0)
    low = min(p[2] for p in pts)
    sole = [p for p in pts if p[2] <= low + CONTACT_TOLERANCE_M]
    xs, ys = [p[0] for p in sole], [p[1] for p in sole]
    return ((min(xs) + max(xs)) / 2.0, (min(ys) + max(ys)) / 2.0)


def _origin(model: RobotModel, foot: str) -> Transform:
    from rcb4hv.robot.kinematics import from_xyz_rpy

    j = limb(model, foot)[0]
    return from_xyz_rpy(j.xyz, j.rpy)


def default_params(
    model: RobotModel,
    direction: Direction,
    *,
    steps: int = 6,
    stride: float | None = None,
    turn: float | None = None,
    lift: float | None = None,
    width: float | None = None,
    step_time: float | None = None,
) -> GaitParams:
    """:class:`GaitParams` with the defaults scaled to ``model``'s leg (see the constants).
    A stride of more than one and a half legs, a width of more than two or a lift of more than
    half a leg is no walk of this robot: ValueError naming it (they were written, every pose
    out of reach, with a log warning)."""
    body = Body.of(model)
    side = direction in ("left", "right")
    for what, value, most in (
        ("stride", stride, 1.5 * body.leg),
        ("width", width, 2.0 * body.leg),
        ("lift", lift, 0.5 * body.leg),
    ):
        if value is not None and value > most:
            raise GaitError(
                f"{what} {value:g} m is more than {model.name}'s legs can make (at most "
                f"{most:.3f} m; its leg is {body.leg:.3f} m)"
            )
    return GaitParams(
        direction=direction,
        steps=steps,
        stride=stride
        if stride is not None
        else (STRIDE_SIDE if side else STRIDE_FORWARD) * body.leg,
        turn=turn if turn is not None else TURN_DEG,
        width=width if width is not None else WIDTH_MIN * body.width,
        lift=lift if lift is not None else LIFT * body.leg,
        step_time=step_time if step_time is not None else STEP_TIME,
    )


@dataclass(frozen=True)
class Walk:
    """A generated walk: its parameters, the pattern, the joint angles per sample and the
    worst IK miss (m; 0 when every pose reached its feet)."""

    params: GaitParams
    pattern: Trajectory
    poses: tuple[dict[str, float], ...]
    worst_error: float
    missed: int
    robot: str = ""
    """The name of the model the walk was made for ("" when not known)."""


def _foot(row: tuple[float, float, float, float], home: Transform) -> Transform:
    x, y, z, yaw = row
    rot = compose(rotation_about(UP, yaw), _rotation(home))
    return compose(translation((x, y, z)), rot)


def _rotation(t: Transform) -> Transform:
    return (
        (t[0][0], t[0][1], t[0][2], 0.0),
        (t[1][0], t[1][1], t[1][2], 0.0),
        (t[2][0], t[2][1], t[2][2], 0.0),
        (0.0, 0.0, 0.0, 1.0),
    )


def walk(model: RobotModel, params: GaitParams, period_s: float = 0.015) -> Walk:
    """Generate ``params``' walk for ``model``, one pose per ``period_s`` (the board's
    output period). The torso stays upright at its walking height and turns with the feet;
    it moves so that the model's centre of mass follows the preview controller's CoM."""
    if not (math.isfinite(period_s) and 0.001 <= period_s <= 0.1):
        raise GaitError(f"period_s is the output period in seconds (0.010-0.025), not {period_s!r}")
    body = Body.of(model)
    if params.direction.startswith("turn") and len(limb(model, body.left)) < 6:
        raise RobotModelError(
            f"{model.name}: its legs have no hip yaw joint, so a foot cannot turn under the "
            "body; a turn in place (made by slipping feet on the real robot) is not generated"
        )
    pat = trajectory(params, body.zc, period_s, body.soles)
    pose = knees_forward(model, (body.left, body.right))
    poses: list[dict[str, float]] = []
    worst, missed = 0.0, 0
    cx, cy = body.com
    for i in range(len(pat.t)):
        yaw = float(pat.yaw[i])
        c, s = math.cos(yaw), math.sin(yaw)
        tx = float(pat.com[i, 0]) - (c * cx - s * cy)
        ty = float(pat.com[i, 1]) - (s * cx + c * cy)
        torso = compose(translation((tx, ty, body.height)), rotation_about(UP, yaw))
        if params.lean:
            torso = compose(torso, rotation_about((0.0, 1.0, 0.0), math.radians(params.lean)))
        feet = {
            body.left: _foot(tuple(pat.left[i]), body.home_left),
            body.right: _foot(tuple(pat.right[i]), body.home_right),
        }
        r = solve_feet(model, feet, torso, pose, max_iter=200 if i == 0 else 60)
        pose = r.angles
        poses.append(pose)
        if not r.reached:
            missed += 1
            worst = max(worst, r.position_error)
    if missed:
        log.warning("%s: %d of %d poses out of reach (worst %.1f mm)", model.name, missed,
                    len(poses), worst * 1000)  # fmt: skip
    return Walk(params, pat, tuple(poses), worst, missed, model.name)
