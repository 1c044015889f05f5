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
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD, POSITION_MAX, POSITION_MIN
from rcb4hv.protocol.memory import CENTER, COUNTS_PER_DEGREE, S16, SERVO, U16, unpack_alloc
from rcb4hv.protocol.servomode import output_mode
from rcb4hv.robot.servos import speed_cap, wheel_duty
from rcb4hv.rom.calibration import calibrated_ad_inputs

__all__ = ["PhysicsBackend"]

Observer = Callable[["PhysicsBackend"], None]
_US: Final = 1_000_000
_ANGLES_KEPT: Final = 4096
_u16 = U16.unpack_from
_s16 = S16.unpack_from
_OUTPUT: Final = SERVO.OUTPUT
_SPECIAL: Final = frozenset((POSITION_FREE, POSITION_HOLD))
"""The output words that are not an angle (:func:`~rcb4hv.protocol.servomode.output_mode`)."""


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
        self._indices = tuple(world.servos)
        self._wheels = frozenset(i for i, s in world.servos.items() if s.wheel)
        self._band_rad = math.radians(world.options.deadband_deg)
        self._last: dict[int, tuple[int, int, int, int | None, int | None]] = {}
        """Per servo driven to an angle, what it was driven from at the last period (output,
        value sent, trim, stretch, speed)."""
        self._value_terms = {  # RobotModel.motion_value's terms, per servo
            s.index: (CENTER + s.offset, s.sign) for s in world.model.servos
        }
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
        ram = self.board.ram
        table = unpack_alloc(ram)  # the board's allocation table, in one read
        last = len(ram) - SERVO.SIZE
        out = []
        for index in self._indices:
            blk = table[index]
            if blk is not None and blk <= last and ram[blk + SERVO.TYPE] == 0:
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
        mixing), ``dt`` the seconds since the last period.

        A servo whose inputs (value sent, trim, stretch, speed) are those of the last period
        and whose target has reached its goal is left as it is: driving it again would set
        the same target and gain (the common case while a pose is held)."""
        b = self.board
        ram = b.ram
        world = self.world
        stretch = b.stretch
        speed = b.speed_parameter
        commanded = self.commanded
        effective = self._effective
        hold = self._hold
        last = self._last
        wheels = self._wheels
        angles = self._angles
        band = self._band_rad
        hold_is_free = self._hold_is_free
        for index, blk, base in blocks:
            out = _u16(ram, blk + _OUTPUT)[0]
            sent = outs.get(index, out + base)
            if index in wheels:
                self._spin(index, out, sent, base)
                continue
            mode = output_mode(out, hold_is_free) if out in _SPECIAL else "angle"
            if mode == "free":
                world.release(index)
                commanded[index] = None
                effective.pop(index, None)
                hold.pop(index, None)
                last.pop(index, None)
                continue
            gain_key = (index, stretch.get(index))
            speed_key = (index, speed.get(index))
            if mode == "hold":
                goal = hold.get(index)
                if goal is None:
                    goal = hold[index] = world.servo_angle(index)
                key = None
            else:
                if hold:
                    hold.pop(index, None)
                key = (out, sent, base, gain_key[1], speed_key[1])
                if last.get(index) == key and effective.get(index) == commanded.get(index):
                    continue  # the same inputs, the goal reached: as it is
                goal = angles.get((index, sent, base))
                if goal is None:
                    goal = self._angle(index, sent, base)
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
                cap = self._caps.get(speed_key)
                if cap is None:
                    cap = self._cap(index, speed_key[1])
                step = cap * dt
                eff = prev + max(-step, min(step, goal - prev))
            else:
                eff = goal
            effective[index] = eff
            if key is None:
                last.pop(index, None)
            else:
                last[index] = key
            kp = self._gains.get(gain_key)
            if kp is None:
                kp = self._gain(index, gain_key[1])
            world.drive(index, eff, kp)

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
        """Each servo's position (``RobotModel.value`` of its joint angle, written out here:
        it runs for every servo at every period) and the sensors, into the board."""
        world = self.world
        q = world.d.qpos.tolist()
        servos = world.servos
        terms = self._value_terms
        wheels = self._wheels
        wheel_sent = self._wheel_sent
        degrees = math.degrees
        positions: dict[int, int] = {}
        for index, _, base in blocks:
            if index in wheels:  # a wheel reports the speed it was sent (its angle grows)
                p = wheel_sent.get(index, base + CENTER)
            else:
                zero, sign = terms[index]
                angle = q[servos[index].qpos]
                p = round(zero + sign * degrees(angle) * COUNTS_PER_DEGREE) + base
            positions[index] = min(max(p, 0), 0xFFFF)  # the 16-bit register (measure refuses more)
        gyro, accel = world.imu()
        self.board.measure(positions, self.sensors.channels(gyro, accel, self.rest))
