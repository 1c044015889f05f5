"""Physics as a servo backend of the emulator: the board's outputs drive simulated servos.

:class:`PhysicsBackend` hangs on a :class:`~rcb4hv.emulator.Board` as an output listener.
After every output period (the moment a real RCB-4 sends its servo frame on the ICS bus):

1. the physics catches up with the board's time, in steps of ``world.timestep`` (lock-step
   on a virtual clock: both advance by the same board microseconds);
2. each mapped servo's state is read from its block: **free** (8000h, or 7FFFh where the
   board's config treats hold as free) goes limp, **hold** (7FFFh) keeps the angle it has,
   any other value is a target angle, ``RobotModel.angle(index, sent, base)`` (the value
   sent includes the block's base, the servo's trim: the model's one conversion rule); a
   value past the servo's travel (3500..11500 sent, +-135 deg) stops at its end, as the
   servo does (Kondo's own motions command 2100 or 12700 to push a joint to its end);
3. a target moves towards the command at most at the servo's speed cap (its SetSpeed value
   as a fraction of the no-load speed), and the servo's stiffness follows its SetStretch
   value (:func:`rcb4hv.robot.servos.stiffness`);
4. the simulated joint angles go back into the board as the servos' measured positions
   (``RobotModel.value``), reported into the blocks at the next period as the ICS reply
   would be, and the gyro and accelerometer into their AD channels as inputs: a calibrated
   channel reads its image reference at rest plus the signal (:mod:`rcb4hv.physics.sensors`),
   and the board's measured register the signal alone (spec 10.4).

So a host reading a servo sees where the joint is, a free limb falls and reads back where it
fell to, and a limb pushed by hand (or by the floor) can be read.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Final

from rcb4hv.emulator import Board
from rcb4hv.physics.sensors import DEFAULT_SENSORS, SensorLayout
from rcb4hv.physics.world import PhysicsWorld
from rcb4hv.protocol import POSITION_MAX, POSITION_MIN
from rcb4hv.protocol.memory import CENTER, NO_BLOCK, S16, SERVO, U16
from rcb4hv.protocol.servomode import output_mode
from rcb4hv.robot.servos import speed_cap, wheel_duty
from rcb4hv.rom.calibration import calibrated_ad_inputs

__all__ = ["PhysicsBackend"]

Observer = Callable[["PhysicsBackend"], None]
_US: Final = 1_000_000
_ANGLES_KEPT: Final = 4096
_u16 = U16.unpack_from
_s16 = S16.unpack_from


class PhysicsBackend:
    """Simulated servos and sensors for ``board`` (see the module docstring).

    Physics time 0 is the board time at construction; the world should already hold the
    robot in the pose the board holds (:meth:`PhysicsWorld.place`). ``observers`` are
    called after every output period's physics, e.g. to record the robot's path.
    """

    def __init__(
        self,
        board: Board,
        world: PhysicsWorld,
        *,
        sensors: SensorLayout = DEFAULT_SENSORS,
    ) -> None:
        self.board = board
        self.world = world
        self.sensors = sensors
        self.rest = calibrated_ad_inputs(board.rom)
        """The calibrated channels' readings at rest (the image's AD references)."""
        self.observers: list[Observer] = []
        self._t0_us = round(board.now * _US)
        self._dt_us = round(world.timestep * _US)
        self._steps = 0
        self._last_us = self._t0_us
        self.commanded: dict[int, float | None] = {}
        """The board's target angle (rad) of each servo at the last period (None: free;
        wheel servos are not listed: their value is a speed, see :meth:`_spin`)."""
        self._effective: dict[int, float] = {}
        self._hold: dict[int, float] = {}
        self._band: dict[int, float] = {}
        """Per servo, the target its dead band keeps (PhysicsOptions.deadband_deg)."""
        self._angles: dict[tuple[int, int, int], float] = {}
        self._gains: dict[tuple[int, int | None], float] = {}
        self._caps: dict[tuple[int, int | None], float] = {}
        self._hold_is_free = board.config.position_7fff == "free"
        self._wheel_sent: dict[int, int] = {}
        board.external_servos = True
        blocks = self._blocks()
        self._command(0.0, board.servo_outputs(), blocks)
        self._measure(blocks)
        board.add_output_listener(self._period)

    def close(self) -> None:
        """Detach from the board (its virtual servos follow their sent values again)."""
        self.board.remove_output_listener(self._period)
        self.board.external_servos = False

    @property
    def time(self) -> float:
        """Physics seconds simulated so far."""
        return self._steps * self._dt_us / _US

    @property
    def board_time(self) -> float:
        """The board time (s) the physics has reached."""
        return (self._t0_us + self._steps * self._dt_us) / _US

    # ------------------------------------------------------------------ the period

    def _period(self, t: float, outs: dict[int, int]) -> None:
        t_us = round(t * _US)
        self._advance(t_us)
        blocks = self._blocks()
        self._command((t_us - self._last_us) / _US, outs, blocks)
        self._last_us = t_us
        self._measure(blocks)

    def sync(self) -> None:
        """Bring the physics up to the board's time (call outside an output period)."""
        self._advance(round(self.board.now * _US))

    def _advance(self, t_us: int) -> None:
        target = (t_us - self._t0_us) // self._dt_us
        n = target - self._steps
        if n > 0:
            self.world.step(n)
            self._steps = target
            for cb in self.observers:
                cb(self)

    def _blocks(self) -> list[tuple[int, int, int]]:
        """(index, block address, base) of each mapped servo with a type-0 block."""
        b = self.board
        ram = b.ram
        out = []
        for index in self.world.servos:
            blk = b.alloc(index)
            if blk != NO_BLOCK and blk + SERVO.SIZE <= len(ram) and ram[blk + SERVO.TYPE] == 0:
                out.append((index, blk, _s16(ram, blk + SERVO.BASE)[0]))
        return out

    def _angle(self, index: int, sent: int, base: int) -> float:
        """``RobotModel.angle``, remembered: a held pose sends the same values every period."""
        key = (index, sent, base)
        a = self._angles.get(key)
        if a is None:
            if len(self._angles) > _ANGLES_KEPT:
                self._angles.clear()
            travel = max(POSITION_MIN, min(POSITION_MAX, sent))  # the servo's own end stops
            a = self._angles[key] = self.world.model.angle(index, travel, base)
        return a

    def _gain(self, index: int, stretch: int | None) -> float:
        key = (index, stretch)
        kp = self._gains.get(key)
        if kp is None:
            kp = self._gains[key] = self.world.stiffness(index, stretch)
        return kp

    def _cap(self, index: int, speed: int | None) -> float:
        key = (index, speed)
        v = self._caps.get(key)
        if v is None:
            cap = speed_cap(self.world.servos[index].spec, speed)
            v = self._caps[key] = cap * self.world.options.speed_cap
        return v

    def _command(self, dt: float, outs: dict[int, int], blocks: list[tuple[int, int, int]]) -> None:
        """New servo targets from the ``blocks``; ``outs`` the values sent (output + base +
        mixing), ``dt`` the seconds since the last period."""
        b = self.board
        ram = b.ram
        world = self.world
        stretch = b.stretch
        speed = b.speed_parameter
        commanded = self.commanded
        effective = self._effective
        hold = self._hold
        servos = world.servos
        band = math.radians(world.options.deadband_deg)
        for index, blk, base in blocks:
            out = _u16(ram, blk + SERVO.OUTPUT)[0]
            if servos[index].wheel:
                self._spin(index, out, outs.get(index, out + base), base)
                continue
            mode = output_mode(out, self._hold_is_free)
            if mode == "free":
                world.release(index)
                commanded[index] = None
                effective.pop(index, None)
                hold.pop(index, None)
                continue
            if mode == "hold":
                goal = hold.get(index)
                if goal is None:
                    goal = hold[index] = world.servo_angle(index)
            else:
                if hold:
                    hold.pop(index, None)
                goal = self._angle(index, outs.get(index, out + base), base)
                if band:
                    kept = self._band.get(index)
                    if kept is not None and abs(goal - kept) <= band:
                        goal = kept
                    else:
                        self._band[index] = goal
            commanded[index] = goal
            prev = effective.get(index)
            if prev is None:
                prev = world.servo_angle(index)
            if dt > 0:
                step = self._cap(index, speed.get(index)) * dt
                eff = prev + max(-step, min(step, goal - prev))
            else:
                eff = goal
            effective[index] = eff
            world.drive(index, eff, self._gain(index, stretch.get(index)))

    def _spin(self, index: int, out: int, sent: int, base: int) -> None:
        """A wheel servo: the value sent sets its speed (free: limp; hold: keeps turning)."""
        mode = output_mode(out, self._hold_is_free)
        if mode == "free":
            self.world.release(index)
            self._wheel_sent.pop(index, None)
        elif mode == "angle":
            self.world.spin(index, wheel_duty(self._angle(index, sent, base)))
            self._wheel_sent[index] = sent

    def _measure(self, blocks: list[tuple[int, int, int]]) -> None:
        b = self.board
        model = self.world.model
        angles = self.world.servo_angles()
        wheels = self._wheel_sent
        positions = {  # a wheel reports the speed it was sent (its angle grows without end)
            index: wheels.get(index, base + CENTER)
            if self.world.servos[index].wheel
            else model.value(index, angles[index], base)
            for index, _, base in blocks
        }
        gyro, accel = self.world.imu()
        b.measure(positions, self.sensors.channels(gyro, accel, self.rest))
