"""A motion as a sequence of timed poses, for the 3D preview (no browser code here).

A :class:`Playback` is what a simulation of one motion produced: frames of (virtual time,
joint angles, base pose) and, from physics, when the robot fell. Two sources make them:

* :func:`simulated_playback`: the plain simulator (:mod:`rcb4hv.project.simulate`): the
  servo values the board sends each output period (output + trim + mixing) less each
  servo block's trim, through the model's joint map
  (:meth:`~rcb4hv.robot.RobotModel.motion_angles`). It has no
  base pose (the 3D view stands the robot on its feet) and cannot tell a fall.
* :func:`physics_playback`: MuJoCo (:mod:`rcb4hv.physics`, the ``[sim]`` extra): measured
  joint angles, the base pose and the fall.
"""

from __future__ import annotations

import bisect
import importlib.util
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

from rcb4hv.emulator import Board
from rcb4hv.hth4 import Project
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD
from rcb4hv.protocol.memory import NO_BLOCK, SERVO
from rcb4hv.robot import RobotModel, Transform
from rcb4hv.ui.project_actions import project_image, run_motion

if TYPE_CHECKING:
    from rcb4hv.physics import PhysicsBackend, PhysicsWorld

__all__ = [
    "Frame",
    "Playback",
    "board_trims",
    "physics_available",
    "physics_playback",
    "simulated_playback",
]


@dataclass(frozen=True, slots=True)
class Frame:
    """One pose: ``t`` seconds from the motion's start, joint angles in radians by joint
    name, and the base (root link) pose, or None when the source does not know it."""

    t: float
    angles: dict[str, float]
    base: Transform | None = None


@dataclass(frozen=True)
class Playback:
    """A motion's frames in time order; ``fell_at`` (seconds) when physics saw a fall."""

    slot: int
    name: str
    frames: tuple[Frame, ...]
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

    def at(self, t: float) -> Frame:
        """The frame shown at time ``t``: the last one at or before it (the first before 0)."""
        i = bisect.bisect_right(self.times, t) - 1
        return self.frames[max(i, 0)]

    def fallen(self, t: float) -> bool:
        return self.fell_at is not None and t >= self.fell_at


def board_trims(board: Board) -> dict[int, int]:
    """Each allocated servo's trim (the servo block's base value) by ICS number."""
    out: dict[int, int] = {}
    for ics in board.servo_outputs():
        blk = board.alloc(ics)
        if blk != NO_BLOCK:
            out[ics] = SERVO.F_BASE.get(board.ram, blk)
    return out


def _frame(model: RobotModel, t: float, sent: dict[int, int], trims: dict[int, int]) -> Frame:
    """The pose of the values ``sent`` to the servos: each less its trim is the block's
    output (motion space; free and hold are sent with the trim added too, spec 9), and free
    or held servos are left out."""
    # the board adds in 16-bit words (spec 9), so taking the trim off wraps the same way
    motion = {k: (v - trims.get(k, 0)) & 0xFFFF for k, v in sent.items()}
    held = {k: v for k, v in motion.items() if v not in (POSITION_FREE, POSITION_HOLD)}
    return Frame(round(t, 6), model.motion_angles(held))


def simulated_playback(
    project: Project, slot: int, model: RobotModel, *, limit: float = 60.0
) -> Playback:
    """Play motion ``slot`` of ``project`` in the plain simulator (virtual time) and record
    the pose of every output period, from the pose the board holds before the motion."""
    samples: list[tuple[float, dict[int, int]]] = []
    result, sim = run_motion(
        project, slot, lambda t, values: samples.append((t, values)), limit=limit
    )
    trims = board_trims(sim.board)
    frames = [_frame(model, t, v, trims) for t, v in samples]
    if not frames or frames[0].t > 0:
        start = samples[0][1] if samples else sim.board.servo_outputs()
        frames.insert(0, _frame(model, 0.0, start, trims))
    return Playback(slot, result.name, tuple(frames), result.status)


def physics_playback(project: Project, slot: int, model: RobotModel) -> Playback:
    """Play motion ``slot`` of ``project`` with physics (:mod:`rcb4hv.project.physics_sim`):
    the robot stands and settles in the pose the board holds after boot, then plays; frames
    are the simulated joint angles and root pose of every output period, from the motion's
    start until the robot has settled after it. Raises
    :class:`~rcb4hv.errors.PhysicsUnavailableError` without MuJoCo."""
    from rcb4hv.project.physics_sim import PhysicsSimulator
    from rcb4hv.project.relocate import project_layout

    sim = PhysicsSimulator(project_image(project), model, motion_layout=project_layout(project))
    sim.boot()
    assert sim.backend is not None  # boot() attaches it
    frames: list[Frame] = []
    t0 = sim.backend.board_time
    world = sim.world

    def observe(backend: PhysicsBackend) -> None:
        frames.append(Frame(round(backend.board_time - t0, 6), world.joint_angles(), _root(world)))

    frames.append(Frame(0.0, world.joint_angles(), _root(world)))
    sim.backend.observers.append(observe)
    m = project.motion(slot)
    result = sim.play(m.address, slot=slot, name=m.name or "")
    outcome = sim.outcomes[-1]
    return Playback(slot, result.name, tuple(frames), result.status, "physics", outcome.fell_at_s)


def _root(world: PhysicsWorld) -> Transform:
    """The root link's world transform (MuJoCo's free joint: position, then the unit
    quaternion w, x, y, z)."""
    x, y, z, w, qx, qy, qz = (float(v) for v in world.d.qpos[0:7])
    return (
        (1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - w * qz), 2 * (qx * qz + w * qy), x),
        (2 * (qx * qy + w * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - w * qx), y),
        (2 * (qx * qz - w * qy), 2 * (qy * qz + w * qx), 1 - 2 * (qx * qx + qy * qy), z),
        (0.0, 0.0, 0.0, 1.0),
    )


def physics_available() -> bool:
    """True when the physics package and MuJoCo are both importable."""
    return all(importlib.util.find_spec(name) is not None for name in ("mujoco", "rcb4hv.physics"))
