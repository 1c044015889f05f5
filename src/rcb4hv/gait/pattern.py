"""Footsteps, the ZMP reference and the CoM and swing-foot trajectories of a walk.

A walk is planned on the floor (x forward, y left, yaw about z): a list of
:class:`Footstep` (which foot lands where), from which the ZMP reference follows (on the
support foot while the other swings, moving from foot to foot in double support), the
centre of mass follows from :class:`~rcb4hv.gait.preview.PreviewController`, and each swing
foot moves along a minimum-jerk path in x, y and yaw while it rises and falls by ``lift``.

Forward and back walks step foot over foot (the body travels ``stride`` per step; a last
step closes the feet); side steps and turns step and close (the leading foot opens by two
strides or two turns, the other closes), so the feet never cross.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from rcb4hv.errors import GaitError
from rcb4hv.gait.preview import Array, PreviewController

__all__ = [
    "DIRECTIONS",
    "Direction",
    "Footstep",
    "GaitParams",
    "Trajectory",
    "phase_samples",
    "plan_footsteps",
    "trajectory",
]

Point = tuple[float, float]
Direction = Literal["forward", "back", "left", "right", "turn-left", "turn-right"]
DIRECTIONS: tuple[Direction, ...] = ("forward", "back", "left", "right", "turn-left", "turn-right")

START_HOLD_S = 0.3
"""Standing still before the first weight shift (s): a documented choice."""
END_HOLD_S = 0.6
"""Standing still after the last step while the CoM settles over both feet (s)."""
MAX_STEPS = 200
MAX_STEP_TIME_S = 5.0
"""The longest walk generated: 200 steps (about 20 s to compute; the CLI and the Walk page
take 40) of at most 5 s each (a KXR's step takes about 0.5 s). Beyond them a walk is
refused at once rather than computed for minutes (``step_time=1e9`` asked for 124 GiB)."""


@dataclass(frozen=True)
class GaitParams:
    """A walk: ``stride`` metres the body travels per step (side steps too), ``turn``
    degrees per step (turns), ``width`` the feet's distance apart (m), ``lift`` the swing
    foot's height (m), ``step_time`` one step (s), ``double_support`` the share of a step
    both feet carry the weight."""

    direction: Direction
    steps: int
    stride: float
    turn: float
    width: float
    lift: float
    step_time: float
    double_support: float = 0.25
    lean: float = 0.0
    """Torso pitch (degrees, + forward): 0 keeps it upright."""

    def __post_init__(self) -> None:
        if self.direction not in DIRECTIONS:
            raise GaitError(f"direction must be one of {', '.join(DIRECTIONS)}")
        if not 1 <= self.steps <= MAX_STEPS:
            raise GaitError(f"a walk takes 1..{MAX_STEPS} steps, not {self.steps}")
        numbers = (self.stride, self.turn, self.width, self.lift, self.step_time, self.lean)
        if not all(math.isfinite(v) for v in numbers):
            raise GaitError("stride, turn, width, lift, step time and lean are finite numbers")
        if not (self.stride >= 0 and self.lift > 0 and self.width > 0 and self.step_time > 0):
            raise GaitError("stride >= 0, lift, width and step time > 0")
        if self.step_time > MAX_STEP_TIME_S:
            raise GaitError(f"a step takes at most {MAX_STEP_TIME_S:g} s, not {self.step_time:g}")
        if self.turn < 0:
            raise GaitError("turn is degrees per step, >= 0: the direction says which way")
        if not 0.05 <= self.double_support <= 0.8:
            raise GaitError("double support must be 0.05..0.8 of a step")

    @property
    def commanded(self) -> float:
        """What the walk should achieve: metres along the direction, or degrees of turn."""
        pairs = math.ceil(self.steps / 2)
        if self.direction in ("forward", "back"):
            return self.steps * self.stride
        if self.direction in ("left", "right"):
            return 2 * pairs * self.stride
        return 2 * pairs * self.turn


@dataclass(frozen=True)
class Footstep:
    """Foot ``side`` (+1 left, -1 right) lands at ``x``, ``y`` (m) turned ``yaw`` (rad)."""

    side: int
    x: float
    y: float
    yaw: float


def _place(side: int, cx: float, cy: float, yaw: float, width: float) -> Footstep:
    off = side * width / 2.0
    return Footstep(side, cx - math.sin(yaw) * off, cy + math.cos(yaw) * off, yaw)


def plan_footsteps(p: GaitParams) -> tuple[tuple[Footstep, Footstep], list[Footstep]]:
    """The feet at the start (left, right) and the steps in order."""
    w = p.width
    start = (_place(1, 0, 0, 0, w), _place(-1, 0, 0, 0, w))
    steps: list[Footstep] = []
    if p.direction in ("forward", "back"):
        sign = 1.0 if p.direction == "forward" else -1.0
        side = -1
        for k in range(1, p.steps + 1):
            steps.append(_place(side, sign * k * p.stride, 0, 0, w))
            side = -side
        steps.append(_place(side, sign * p.steps * p.stride, 0, 0, w))
        return start, steps
    pairs = math.ceil(p.steps / 2)
    lead = 1 if p.direction in ("left", "turn-left") else -1
    for k in range(1, pairs + 1):
        if p.direction in ("left", "right"):
            cy, yaw = lead * 2 * k * p.stride, 0.0
        else:
            cy, yaw = 0.0, lead * math.radians(2 * k * p.turn)
        steps.append(_place(lead, 0, cy, yaw, w))
        steps.append(_place(-lead, 0, cy, yaw, w))
    return start, steps


@dataclass(frozen=True)
class Trajectory:
    """Per sample (period ``dt``): time, ZMP reference and the model's ZMP (x, y), CoM
    (x, y), the body yaw and each foot's pose (x, y, z, yaw) as (T, 4) arrays."""

    dt: float
    t: Array
    zmp_ref: Array
    zmp: Array
    com: Array
    yaw: Array
    left: Array
    right: Array


def phase_samples(p: GaitParams, dt: float) -> tuple[int, int, int, int]:
    """Samples of ``dt`` seconds in each phase of ``p``'s walk: the hold before the first
    step, a step's double and single support, and the hold after the closing shift. Step
    ``k`` (0-based, of :func:`plan_footsteps`) starts at sample ``hold + k * (double +
    single)``."""
    tds = p.step_time * p.double_support
    tss = p.step_time - tds
    return (
        round(START_HOLD_S / dt),
        max(1, round(tds / dt)),
        max(1, round(tss / dt)),
        round(END_HOLD_S / dt),
    )


def _smooth(s: Array) -> Array:
    """Minimum-jerk profile 0 -> 1 (zero speed and acceleration at both ends)."""
    return np.asarray(s**3 * (10.0 - 15.0 * s + 6.0 * s * s), dtype=np.float64)


def trajectory(
    p: GaitParams, zc: float, dt: float, soles: tuple[Point, Point] = ((0.0, 0.0), (0.0, 0.0))
) -> Trajectory:
    """Sample the walk every ``dt`` seconds for a CoM ``zc`` metres above the floor. The ZMP
    reference lies on the middle of each sole: ``soles`` (left, right) is where that is from
    the ankle (foot frame, x forward, y left)."""
    start, steps = plan_footsteps(p)
    mid = {1: soles[0], -1: soles[1]}

    def sole(side: int) -> Array:
        x, y, _, yaw = feet[side]
        dx, dy = mid[side]
        c, s = math.cos(yaw), math.sin(yaw)
        return np.array([x + c * dx - s * dy, y + s * dx + c * dy])

    feet = {1: np.array([start[0].x, start[0].y, 0.0, 0.0]),
            -1: np.array([start[1].x, start[1].y, 0.0, 0.0])}  # fmt: skip
    n_hold, n_ds, n_ss, n_end = phase_samples(p, dt)
    zmp: list[Array] = []
    left: list[Array] = []
    right: list[Array] = []

    def emit(ref: Array) -> None:
        zmp.append(ref)
        left.append(feet[1].copy())
        right.append(feet[-1].copy())

    ref = (sole(1) + sole(-1)) / 2.0
    for _ in range(n_hold):
        emit(ref)
    for st in steps:
        support = sole(-st.side)
        for s in _smooth((np.arange(n_ds) + 1.0) / n_ds):
            emit(ref + (support - ref) * s)
        ref = support
        begin = feet[st.side].copy()
        goal = np.array([st.x, st.y, 0.0, st.yaw])
        phases = (np.arange(n_ss) + 1.0) / n_ss
        for s, phi in zip(_smooth(phases), phases, strict=True):
            feet[st.side] = begin + (goal - begin) * s
            feet[st.side][2] = p.lift * (1.0 - math.cos(2.0 * math.pi * phi)) / 2.0
            emit(ref)
        feet[st.side] = goal
    centre = (sole(1) + sole(-1)) / 2.0
    for s in _smooth((np.arange(n_ds) + 1.0) / n_ds):
        emit(ref + (centre - ref) * s)
    for _ in range(n_end):
        emit(centre)
    zref = np.array(zmp, dtype=np.float64)
    com, zout = PreviewController(dt, zc).track(zref.astype(np.float64))
    la, ra = np.array(left), np.array(right)
    return Trajectory(
        dt,
        np.arange(len(zref), dtype=np.float64) * dt,
        zref,
        zout,
        com,
        (la[:, 3] + ra[:, 3]) / 2.0,
        la,
        ra,
    )
