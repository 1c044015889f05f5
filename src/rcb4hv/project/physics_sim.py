"""Play a project's motions on a simulated robot: the emulator drives MuJoCo (``--physics``).

:class:`PhysicsSimulator` is a :class:`~rcb4hv.project.simulate.Simulator` whose board has a
:class:`~rcb4hv.physics.PhysicsBackend`. After the boot (run on the board alone, as before)
the robot is put on flat ground in the pose the board holds, its feet lowered onto the floor,
and left to settle for :data:`SETTLE_S`; then motions play as before, and each is watched
until :data:`SETTLE_S` after it ends (a robot that topples does so within that time). Each
motion's :class:`PhysicsOutcome` says:

* ``fell`` / ``fell_at_s``: the torso passed :data:`FALL_TILT_DEG` of tilt (having started
  below it), and when, from the motion's start. A motion that lies down on purpose reports
  this too: read ``end_pose``;
* ``end_pose``: ``upright`` (tilt below :data:`FALL_TILT_DEG`), else ``on_back`` /
  ``on_front`` when the torso's forward axis points more up / down than its left axis,
  else ``on_side``;
* ``dx_m``, ``dy_m``, ``dyaw_deg``: the torso's displacement and turn from the motion's
  start in the frame the robot faced then (x forward, y left, yaw counter-clockwise: ROS
  REP 103);
* ``max_tilt_deg``, ``max_tracking_error_deg`` (largest difference between a joint and the
  board's target for it), ``saturated_joints`` (at the stall torque for
  :data:`SATURATED_S` or more in total).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any, Final, Literal

from rcb4hv.emulator import EmulatorConfig
from rcb4hv.physics import (
    DEFAULT_SENSORS,
    PhysicsBackend,
    PhysicsOptions,
    PhysicsWorld,
    SensorLayout,
)
from rcb4hv.project.check import Finding
from rcb4hv.project.physicsresult import Frame, MotionRun, PhysicsOutcome, PhysicsRun, TrackPoint
from rcb4hv.project.simresult import MotionResult
from rcb4hv.project.simulate import BOOT_LIMIT, DEFAULT_LIMIT, SampleListener, Simulator
from rcb4hv.protocol import POSITION_HOLD
from rcb4hv.protocol.memory import NO_BLOCK, SERVO
from rcb4hv.robot.mjcf import TIMESTEP
from rcb4hv.robot.model import RobotModel
from rcb4hv.rom.layout import MotionLayout

__all__ = [
    "FALL_TILT_DEG",
    "FRAME_EVERY_S",
    "SATURATED_S",
    "SETTLE_S",
    "Frame",
    "MotionRun",
    "PhysicsOutcome",
    "PhysicsRun",
    "PhysicsSimulator",
    "StartPose",
    "TrackPoint",
    "physics_findings",
    "play_physics",
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
    fell_at: float | None = None
    max_tilt: float = 0.0
    max_error: float = 0.0
    saturated: dict[str, float] = field(default_factory=dict)
    last_t: float = 0.0


def _end_pose(tilt: float, up: tuple[float, float, float]) -> str:
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
        self.frames: list[Frame] = []
        self._next_frame = 0.0
        self.outcomes: list[PhysicsOutcome] = []
        self.runs: list[MotionRun] = []

    # ------------------------------------------------------------------ start

    def boot(self, limit: float = BOOT_LIMIT) -> MotionResult:
        """Boot on the board alone, then stand the robot in the pose the board holds and let
        it settle for :data:`SETTLE_S`."""
        res = super().boot(limit)
        self.world.place(self.board_pose(), pitch=_START_PITCH[self.start])
        self.backend = PhysicsBackend(self.board, self.world, sensors=self._sensors)
        self.backend.observers.append(self._observe)
        self._run_us(round(SETTLE_S * 1e6))
        self.backend.sync()
        return res

    def board_pose(self) -> dict[str, float]:
        """Joint angles (rad) of the values the board sends now (free servos at 0)."""
        b = self.board
        outs = b.servo_outputs()
        angles: dict[str, float] = {}
        for s in self.robot.servos:
            blk = b.alloc(s.index)
            if blk == NO_BLOCK or s.index not in outs:
                continue
            st = b.servo_state(s.index)
            if st is None or st.output >= POSITION_HOLD:  # free or hold: no angle sent
                continue
            base = SERVO.F_BASE.get(b.ram, blk)
            angles[s.joint] = self.robot.angle(s.index, outs[s.index], base)
        return angles

    # ------------------------------------------------------------------ watching

    def _observe(self, backend: PhysicsBackend) -> None:
        w = self._watch
        base = self.world.base()
        t = backend.board_time
        if self.track is not None:
            world = self.world
            angles = world.joint_angles()
            self.track.append(
                TrackPoint(
                    t, base.x, base.y, base.yaw, base.tilt, base.z, world.quaternion(), angles
                )
            )
            if t >= self._next_frame:
                self.frames.append(Frame(t, self.world.shapes()))
                self._next_frame = t + FRAME_EVERY_S
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
        for index, goal in backend.commanded.items():
            servo = world.servos[index]
            if goal is not None:
                w.max_error = max(w.max_error, abs(world.servo_angle(index) - goal))
                if world.saturated(index):
                    w.saturated[servo.joint] = w.saturated.get(servo.joint, 0.0) + dt

    def _start_watch(self) -> None:
        assert self.backend is not None
        base = self.world.base()
        t = self.backend.board_time
        self._watch = _Watch(
            t,
            base.x,
            base.y,
            base.yaw,
            base.tilt < math.radians(FALL_TILT_DEG),
            base.yaw,
            last_t=t,
        )

    def _outcome(self) -> PhysicsOutcome:
        w = self._watch
        assert w is not None
        base = self.world.base()
        ex, ey = base.x - w.x0, base.y - w.y0
        c, s = math.cos(w.yaw0), math.sin(w.yaw0)
        return PhysicsOutcome(
            fell=w.fell_at is not None,
            fell_at_s=w.fell_at,
            end_pose=_end_pose(base.tilt, base.up),
            dx_m=c * ex + s * ey,
            dy_m=-s * ex + c * ey,
            dyaw_deg=math.degrees(w.yaw - w.yaw0),
            max_tilt_deg=math.degrees(w.max_tilt),
            max_tracking_error_deg=math.degrees(w.max_error),
            saturated_joints=tuple(
                sorted(j for j, secs in w.saturated.items() if secs >= SATURATED_S)
            ),
        )

    # ------------------------------------------------------------------ playing

    def play(self, address: int, **kw: Any) -> MotionResult:
        """Play a motion (as :meth:`Simulator.play`) and watch the robot until
        :data:`SETTLE_S` after it ends; its outcome is appended to :attr:`outcomes`."""
        if self.backend is None:
            self.boot()
        assert self.backend is not None
        self.backend.sync()
        self._start_watch()
        n_track = len(self.track) if self.track is not None else 0
        n_frames = len(self.frames)
        res = super().play(address, **kw)
        self._run_us(round(SETTLE_S * 1e6))
        self.backend.sync()
        outcome = self._outcome()
        self.outcomes.append(outcome)
        track = tuple(self.track[n_track:]) if self.track is not None else ()
        self.runs.append(MotionRun(res, outcome, track, tuple(self.frames[n_frames:])))
        self._watch = None
        return res


def play_physics(
    image: bytes,
    robot: RobotModel,
    slots: list[int],
    names: dict[int, str],
    *,
    motion_layout: MotionLayout,
    sequence: bool,
    limit: float | None = None,
    hold: int = 0,
    hold_for: float = 0.0,
    track: bool = False,
    timestep: float = TIMESTEP,
    start: StartPose = "upright",
    progress: Callable[[MotionRun], None] | None = None,
    options: PhysicsOptions | None = None,
) -> PhysicsRun:
    """Play ``slots`` with physics: one robot for all (``sequence``) or a fresh boot and
    stand for each (``start``: standing, or lying on its back or front). ``limit``: virtual
    seconds per motion, :data:`~rcb4hv.project.simulate.DEFAULT_LIMIT` when None (a robot
    in physics never stops changing its measured positions and sensors for certain, so
    the motion's own progress cannot be what ends it). ``options``: factors on the model's
    chosen figures (:class:`~rcb4hv.physics.PhysicsOptions`)."""
    if limit is None:
        limit = DEFAULT_LIMIT
    runs: list[MotionRun] = []
    virtual = 0.0
    boot: MotionResult | None = None
    sim: PhysicsSimulator | None = None
    for slot in slots:
        if sim is None or not sequence:
            if sim is not None:
                virtual += sim.now
            sim = PhysicsSimulator(
                image,
                robot,
                motion_layout=motion_layout,
                track=track,
                timestep=timestep,
                start=start,
                options=options,
            )
            b = sim.boot()
            boot = boot or b
        sim.play(
            motion_layout.address(slot),
            slot=slot,
            name=names.get(slot, ""),
            hold=hold,
            hold_for=hold_for,
            limit=limit,
        )
        runs.append(sim.runs[-1])
        if progress is not None:
            progress(sim.runs[-1])
    if sim is not None:
        virtual += sim.now
    if boot is None:
        raise ValueError("no motions to play")
    return PhysicsRun(boot, tuple(runs), virtual)


def physics_findings(runs: Iterable[MotionRun]) -> list[Finding]:
    """``project check --physics`` findings (warnings: the physics is a model of the robot):
    each motion that makes the robot fall, and each joint at its torque limit."""
    out: list[Finding] = []
    for run in runs:
        r, o = run.result, run.outcome
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
