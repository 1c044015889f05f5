"""Play a project's motions on a simulated robot: the emulator drives MuJoCo (``--physics``).

:class:`PhysicsSimulator` is a :class:`~rcb4hv.project.simulate.Simulator` whose board has a
:class:`~rcb4hv.physics.PhysicsBackend`. After the boot (run on the board alone, as before)
the robot is put on flat ground in the pose the board holds, its feet lowered onto the floor,
and left to settle for :data:`SETTLE_S` (:attr:`PhysicsSimulator.settled`: the pose it
settled in); then motions play as before, and each is watched until :data:`SETTLE_S` after it
ends (a robot that topples does so within that time). Runs go through
:func:`rcb4hv.project.run.run_motions`. Each motion's :class:`PhysicsOutcome` says:

* ``start_pose``: the robot's pose (as ``end_pose``) when the motion starts;
  ``fallen_at_start``: it is down then although it stood before (it fell while settling after
  the boot, or an earlier motion of a sequence left it lying); a robot put down on purpose
  (``start="on_back"``) is not "fallen";
* ``fell`` / ``fell_at_s``: the robot went from upright to down during the motion (or its
  settling): its torso passed :data:`FALL_TILT_DEG` of tilt having started below it, and
  when, from the motion's start. A motion that starts down cannot fall; a motion that lies
  down on purpose reports a fall too: read ``end_pose``;
* ``end_pose``: ``upright`` (tilt below :data:`FALL_TILT_DEG`), else ``on_back`` /
  ``on_front`` when the torso's forward axis points more up / down than its left axis,
  else ``on_side``. So ``fell`` and ``end_pose`` agree: a motion that started upright and
  ends lying has fallen; one that ends lying without falling started down
  (``fallen_at_start`` or put down on purpose);
* ``dx_m``, ``dy_m``, ``dyaw_deg``: the torso's displacement and turn from the motion's
  start in the frame the robot faced then (x forward, y left, yaw counter-clockwise: ROS
  REP 103);
* ``max_tilt_deg``, ``max_tracking_error_deg`` (largest difference between a joint and the
  board's target for it), ``saturated_joints`` (at the stall torque for
  :data:`SATURATED_S` or more in total).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, Final, Literal

from rcb4hv.emulator import EmulatorConfig
from rcb4hv.physics import (
    DEFAULT_SENSORS,
    BasePose,
    PhysicsBackend,
    PhysicsOptions,
    PhysicsWorld,
    SensorLayout,
)
from rcb4hv.project.check import Finding
from rcb4hv.project.physicsresult import PhysicsOutcome, ShapeFrame, TrackPoint
from rcb4hv.project.runresult import MotionRun
from rcb4hv.project.simresult import MotionResult
from rcb4hv.project.simulate import BOOT_LIMIT, SampleListener, Simulator
from rcb4hv.protocol.memory import SERVO
from rcb4hv.robot.mjcf import TIMESTEP
from rcb4hv.robot.model import RobotModel
from rcb4hv.rom.layout import MotionLayout

__all__ = [
    "FALL_TILT_DEG",
    "FRAME_EVERY_S",
    "SATURATED_S",
    "SETTLE_S",
    "PhysicsOutcome",
    "PhysicsSimulator",
    "ShapeFrame",
    "StartPose",
    "TrackPoint",
    "physics_findings",
    "pose_name",
]

SETTLE_S: Final = 1.0
"""Seconds the robot is left after the boot and after each motion. A body toppling from
standing height lies on the floor well within a second (a 0.4 m robot falls over in about
0.6 s), and the servos reach any pose in far less."""
FALL_TILT_DEG: Final = 60.0
"""Tilt of the torso from the vertical that counts as fallen (no walking or greeting pose
leans the torso this far; lying on the floor is about 90°)."""
FRAME_EVERY_S: Final = 0.25
"""With ``track``, the robot's shapes are kept this often (virtual seconds) for drawing."""
SATURATED_S: Final = 0.1
"""Total time at the stall torque that makes a joint saturated (a move's first instant
always pulls at the limit for a few milliseconds)."""


StartPose = Literal["upright", "on_back", "on_front"]
_START_PITCH: Final[dict[str, float]] = {
    "upright": 0.0,
    "on_back": -math.pi / 2,
    "on_front": math.pi / 2,
}


@dataclass
class _Watch:
    """Accumulates one motion's outcome, one output period at a time."""

    t0: float
    x0: float
    y0: float
    yaw0: float
    upright0: bool
    yaw: float
    start_pose: str
    fallen_at_start: bool
    fell_at: float | None = None
    max_tilt: float = 0.0
    max_error: float = 0.0
    saturated: dict[str, float] = field(default_factory=dict)
    last_t: float = 0.0


def pose_name(base: BasePose) -> str:
    """``upright``, ``on_back``, ``on_front`` or ``on_side`` (see the module docstring)."""
    tilt, up = base.tilt, base.up
    if tilt < math.radians(FALL_TILT_DEG):
        return "upright"
    if abs(up[0]) >= abs(up[1]):
        # the world's up seen from the torso: along +x means its front faces the sky
        return "on_back" if up[0] > 0 else "on_front"
    return "on_side"


class PhysicsSimulator(Simulator):
    """A :class:`Simulator` whose servos are a robot in MuJoCo (see the module docstring)."""

    def __init__(
        self,
        image: bytes,
        robot: RobotModel,
        *,
        motion_layout: MotionLayout | None = None,
        listener: SampleListener | None = None,
        sensors: SensorLayout = DEFAULT_SENSORS,
        track: bool = False,
        timestep: float = TIMESTEP,
        start: StartPose = "upright",
        config: EmulatorConfig | None = None,
        options: PhysicsOptions | None = None,
    ) -> None:
        super().__init__(image, motion_layout=motion_layout, listener=listener, config=config)
        self.start = start
        self.robot = robot
        self.world = PhysicsWorld(robot, timestep=timestep, options=options)
        self._sensors = self.world.options.sensors(sensors)
        self.backend: PhysicsBackend | None = None
        self._watch: _Watch | None = None
        self.track: list[TrackPoint] | None = [] if track else None
        self.frames: list[ShapeFrame] = []
        self._next_frame = 0.0
        self.outcomes: list[PhysicsOutcome] = []
        self.runs: list[MotionRun] = []
        self.settled: BasePose | None = None
        """The robot's pose :data:`SETTLE_S` after it was put on the floor (None before)."""
        self._stood = start == "upright"  # it has stood since it was put down

    # ------------------------------------------------------------------ start

    def boot(self, limit: float = BOOT_LIMIT) -> MotionResult:
        """Boot on the board alone, then stand the robot in the pose the board holds and let
        it settle for :data:`SETTLE_S`."""
        res = super().boot(limit)
        self.world.place(self.board_pose(), pitch=_START_PITCH[self.start])
        self.backend = PhysicsBackend(self.board, self.world, sensors=self._sensors)
        self.backend.observers.append(self._observe)
        self.settled = self.settle()
        return res

    def settle(self, seconds: float = SETTLE_S) -> BasePose:
        """Let the robot move on for ``seconds`` of board time (the program runs as it does);
        its pose then."""
        assert self.backend is not None
        self.run_us(round(seconds * 1e6))
        self.backend.sync()
        return self.world.base()

    def board_pose(self) -> dict[str, float]:
        """Joint angles (rad) of the values the board sends now to servos at an angle (free
        and holding servos are left out: :meth:`~rcb4hv.emulator.Board.sent_angles`)."""
        b = self.board
        angles: dict[str, float] = {}
        sent = b.sent_angles()
        for s in self.robot.servos:
            value = sent.get(s.index)
            if value is None:
                continue
            base = SERVO.F_BASE.get(b.ram, b.alloc(s.index))
            angles[s.joint] = self.robot.angle(s.index, value, base)
        return angles

    # ------------------------------------------------------------------ watching

    def _observe(self, backend: PhysicsBackend) -> None:
        w = self._watch
        base = self.world.base()
        t = backend.board_time
        if base.tilt < math.radians(FALL_TILT_DEG):
            self._stood = True
        if self.track is not None:
            self._track(t, base)
        if w is None:
            return
        # unwrapped yaw: turns beyond 180° add up
        w.yaw += (base.yaw - w.yaw + math.pi) % (2 * math.pi) - math.pi
        w.max_tilt = max(w.max_tilt, base.tilt)
        if w.fell_at is None and w.upright0 and base.tilt >= math.radians(FALL_TILT_DEG):
            w.fell_at = t - w.t0
        dt = t - w.last_t
        w.last_t = t
        world = self.world
        q = world.d.qpos.tolist()
        servos = world.servos
        error = w.max_error
        for index, goal in backend.commanded.items():
            if goal is not None:
                error = max(error, abs(q[servos[index].qpos] - goal))
        w.max_error = error
        for index in world.saturated_servos(backend.commanded):
            joint = servos[index].joint
            w.saturated[joint] = w.saturated.get(joint, 0.0) + dt

    def _track(self, t: float, base: BasePose) -> None:
        assert self.track is not None and self.backend is not None
        world = self.world
        commanded = self.backend.commanded
        angles = world.joint_angles()
        servos = world.servos
        targets = {servos[i].joint: goal for i, goal in commanded.items() if goal is not None}
        pose = (t, base.x, base.y, base.yaw, base.tilt, base.z, world.quaternion(), angles)
        touching = world.touching()
        com, margin = world.centre_of_mass(), world.com_margin()
        self.track.append(TrackPoint(*pose, targets, touching, com, margin))
        if t >= self._next_frame:
            self.frames.append(ShapeFrame(t, world.shapes()))
            self._next_frame = t + FRAME_EVERY_S

    def _start_watch(self) -> None:
        assert self.backend is not None
        base = self.world.base()
        t = self.backend.board_time
        upright = base.tilt < math.radians(FALL_TILT_DEG)
        self._watch = _Watch(
            t,
            base.x,
            base.y,
            base.yaw,
            upright,
            base.yaw,
            pose_name(base),
            not upright and self._stood,
            last_t=t,
        )
        if self.track is not None:  # the path starts where the motion starts
            self._next_frame = t
            self._track(t, base)

    def _outcome(self) -> PhysicsOutcome:
        w = self._watch
        assert w is not None
        base = self.world.base()
        ex, ey = base.x - w.x0, base.y - w.y0
        c, s = math.cos(w.yaw0), math.sin(w.yaw0)
        return PhysicsOutcome(
            fell=w.fell_at is not None,
            fell_at_s=w.fell_at,
            end_pose=pose_name(base),
            dx_m=c * ex + s * ey,
            dy_m=-s * ex + c * ey,
            dyaw_deg=math.degrees(w.yaw - w.yaw0),
            max_tilt_deg=math.degrees(w.max_tilt),
            max_tracking_error_deg=math.degrees(w.max_error),
            saturated_joints=tuple(
                sorted(j for j, secs in w.saturated.items() if secs >= SATURATED_S)
            ),
            start_pose=w.start_pose,
            fallen_at_start=w.fallen_at_start,
        )

    # ------------------------------------------------------------------ playing

    def play(self, address: int, **kw: Any) -> MotionResult:
        """Play a motion (as :meth:`Simulator.play`) and watch the robot until
        :data:`SETTLE_S` after it ends; its outcome is appended to :attr:`outcomes`, the whole
        :class:`MotionRun` to :attr:`runs`."""
        if self.backend is None:
            self.boot()
        assert self.backend is not None
        self.backend.sync()
        start_s = self.now
        n_track = len(self.track) if self.track is not None else 0
        n_frames = len(self.frames)
        self._start_watch()
        res = super().play(address, **kw)
        self.settle()
        outcome = self._outcome()
        self.outcomes.append(outcome)
        track = tuple(self.track[n_track:]) if self.track is not None else ()
        frames = tuple(self.frames[n_frames:])
        self.runs.append(MotionRun(res, outcome, track, frames, start_s))
        self._watch = None
        return res


def physics_findings(runs: Iterable[MotionRun]) -> list[Finding]:
    """``project check --physics`` findings (warnings: the physics is a model of the robot):
    each motion that makes the robot fall, and each joint at its torque limit."""
    out: list[Finding] = []
    for run in runs:
        r, o = run.result, run.outcome
        if o is None:
            continue
        where = f"{r.address:05X}h"
        if o.fell and o.fell_at_s is not None:
            out.append(
                Finding(
                    "warning",
                    "physics-fall",
                    r.slot,
                    r.name,
                    r.address,
                    "",
                    f"motion {r.slot} makes the robot fall at {o.fell_at_s:.2f} s "
                    f"(ends {o.end_pose.replace('_', ' ')}; played from {where})",
                )
            )
        for joint in o.saturated_joints:
            out.append(
                Finding(
                    "warning",
                    "physics-saturation",
                    r.slot,
                    r.name,
                    r.address,
                    "",
                    f"joint {joint} saturates (at its servo's stall torque for "
                    f"{SATURATED_S:g} s or more) in motion {r.slot}",
                )
            )
    return out
