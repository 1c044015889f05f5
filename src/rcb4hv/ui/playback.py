"""A motion as a sequence of timed poses, for the 3D preview (no browser code here).

A :class:`Playback` is what a simulation of one motion produced: poses of (virtual time,
joint angles, base pose) and, from physics, when the robot fell. Both sources run the motion
through the one run API (:func:`rcb4hv.project.run.run_motions`, its defaults):

* :func:`simulated_playback`: the plain simulator: the values the board sends each output
  period to the servos at an angle, less each servo block's trim
  (:meth:`~rcb4hv.emulator.Board.sent_angles`, the board's one free/hold/angle rule), through
  the model's joint map (:meth:`~rcb4hv.robot.RobotModel.motion_angles`). The base pose is
  where the no-slip travel takes the robot (:mod:`rcb4hv.robot.stride`: a walk walks over
  the floor as designed); a robot on wheels has none (the 3D view stands it on its feet).
  It cannot tell a fall.
* :func:`physics_playback`: MuJoCo (:mod:`rcb4hv.physics`, the ``[sim]`` extra): the run's
  :class:`~rcb4hv.project.physicsresult.TrackPoint` of every output period (measured joint
  angles and the torso's pose) and the fall.
"""

from __future__ import annotations

import bisect
import importlib.util
from dataclasses import dataclass
from functools import cached_property

from rcb4hv.emulator import Board
from rcb4hv.hth4 import Project
from rcb4hv.project.physicsresult import TrackPoint
from rcb4hv.project.relocate import project_image
from rcb4hv.project.run import run_motions
from rcb4hv.robot import RobotModel, Transform
from rcb4hv.robot.geometry import pose_transform
from rcb4hv.robot.stride import StrideTracker, has_stride

__all__ = [
    "Playback",
    "TimedPose",
    "physics_available",
    "physics_playback",
    "simulated_playback",
]


@dataclass(frozen=True, slots=True)
class TimedPose:
    """The robot at ``t`` seconds from the motion's start: joint angles in radians by joint
    name, and the base (root link) pose, or None when the source does not know it."""

    t: float
    angles: dict[str, float]
    base: Transform | None = None


@dataclass(frozen=True)
class Playback:
    """A motion's poses in time order; ``fell_at`` (seconds) when physics saw a fall."""

    slot: int
    name: str
    frames: tuple[TimedPose, ...]
    status: str
    source: str = "simulator"
    fell_at: float | None = None

    def __post_init__(self) -> None:
        if not self.frames:
            raise ValueError("a playback needs at least one frame")
        if self.times != sorted(self.times):
            raise ValueError("playback frames must be in time order")

    @cached_property
    def times(self) -> list[float]:
        return [f.t for f in self.frames]

    @property
    def duration(self) -> float:
        return self.frames[-1].t

    def at(self, t: float) -> TimedPose:
        """The pose shown at time ``t``: the last one at or before it (the first before 0)."""
        i = bisect.bisect_right(self.times, t) - 1
        return self.frames[max(i, 0)]

    def fallen(self, t: float) -> bool:
        return self.fell_at is not None and t >= self.fell_at


def simulated_playback(project: Project, slot: int, model: RobotModel) -> Playback:
    """Play motion ``slot`` of ``project`` in the plain simulator (virtual time) and record
    the pose of every output period, from the pose the board holds before the motion."""
    image, layout = project_image(project)
    samples: list[tuple[float, dict[int, int | None]]] = []

    def listen(t: float, board: Board) -> None:
        samples.append((t, board.sent_angles(trim=False)))

    name = project.motion(slot).name or ""
    run = run_motions(image, [slot], names={slot: name}, motion_layout=layout, listener=listen)
    m = run.motions[0]
    tracker = StrideTracker(model) if has_stride(model) else None
    frames = []
    for t, values in samples:
        if t < m.start_s:
            continue
        angles = model.motion_angles({k: v for k, v in values.items() if v is not None})
        if tracker is not None:
            tracker.update(angles)
        base = tracker.base if tracker is not None else None
        frames.append(TimedPose(round(t - m.start_s, 6), angles, base))
    return Playback(slot, m.result.name, tuple(frames), m.result.status)


def physics_playback(project: Project, slot: int, model: RobotModel) -> Playback:
    """Play motion ``slot`` of ``project`` with physics (:mod:`rcb4hv.project.physics_sim`):
    the robot stands and settles in the pose the board holds after boot, then plays; poses
    are the run's track (simulated joint angles and root pose of every output period), from
    the motion's start until the robot has settled after it. Raises
    :class:`~rcb4hv.errors.PhysicsUnavailableError` without MuJoCo."""
    image, layout = project_image(project)
    name = project.motion(slot).name or ""
    run = run_motions(
        image, [slot], names={slot: name}, motion_layout=layout, robot=model, track=True
    )
    m = run.motions[0]
    assert m.outcome is not None and m.track  # a physics run with track
    t0 = m.track[0].t
    frames = tuple(TimedPose(round(p.t - t0, 6), dict(p.angles), _root(p)) for p in m.track)
    return Playback(slot, m.result.name, frames, m.result.status, "physics", m.outcome.fell_at_s)


def _root(p: TrackPoint) -> Transform:
    """The root link's world transform from its position and unit quaternion (w, x, y, z)."""
    return pose_transform((p.x, p.y, p.z), p.quat)


def physics_available() -> bool:
    """True when the physics package and MuJoCo are both importable."""
    return all(importlib.util.find_spec(name) is not None for name in ("mujoco", "rcb4hv.physics"))
