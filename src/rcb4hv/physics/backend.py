"""Physics as a servo backend of the emulator: the board's outputs drive simulated servos.

:class:`PhysicsBackend` hangs on a :class:`~rcb4hv.emulator.Board` as an output listener.
After every output period (the moment a real RCB-4 sends its servo frame on the ICS bus):

1. the physics catches up with the board's time, in steps of ``world.timestep`` (lock-step
   on a virtual clock: both advance by the same board microseconds);
2. each mapped servo's state is read from its block: **free** (8000h, or 7FFFh where the
   board's config treats hold as free) goes limp, **hold** (7FFFh) keeps the angle it has,
   any other value is a target angle, ``RobotModel.angle(index, sent, base)`` (the one
   conversion; the block's base is the servo's trim);
3. a target moves towards the command at most at the servo's speed cap (its SetSpeed value
   as a fraction of the no-load speed), and the servo's stiffness follows its SetStretch
   value (:func:`rcb4hv.robot.mjcf.stiffness`);
4. the simulated joint angles go back into the board as the servos' measured positions
   (``RobotModel.value``), reported into the blocks at the next period as the ICS reply
   would be, and the gyro and accelerometer into their AD channels
   (:mod:`rcb4hv.physics.sensors`).

So a host reading a servo sees where the joint is, a free limb falls and reads back where it
fell to, and a limb pushed by hand (or by the floor) can be read.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Final

from rcb4hv.emulator import Board
from rcb4hv.physics.sensors import DEFAULT_SENSORS, SensorLayout
from rcb4hv.physics.world import PhysicsWorld
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD
from rcb4hv.protocol.memory import NO_BLOCK, SERVO
from rcb4hv.robot.mjcf import speed_cap

__all__ = ["PhysicsBackend"]

Observer = Callable[["PhysicsBackend"], None]
_US: Final = 1_000_000


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
        self.observers: list[Observer] = []
        self._t0_us = round(board.now * _US)
        self._dt_us = round(world.timestep * _US)
        self._steps = 0
        self._last_us = self._t0_us
        self.commanded: dict[int, float | None] = {}
        """The board's target angle (rad) of each servo at the last period (None: free)."""
        self._effective: dict[int, float] = {}
        self._hold: dict[int, float] = {}
        self._hold_is_free = board.config.position_7fff == "free"
        board.external_servos = True
        self._command(0.0, board.servo_outputs())
        self._measure()
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
        self._command((t_us - self._last_us) / _US, outs)
        self._last_us = t_us
        self._measure()

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

    def _command(self, dt: float, outs: dict[int, int]) -> None:
        """New servo targets from the blocks; ``outs`` the values sent (output + base +
        mixing), ``dt`` the seconds since the last period."""
        b = self.board
        ram = b.ram
        world = self.world
        model = world.model
        stretch = b.stretch
        speed = b.speed_parameter
        for index, servo in world.servos.items():
            blk = b.alloc(index)
            if blk == NO_BLOCK or SERVO.F_TYPE.get(ram, blk) != 0:
                continue
            out = SERVO.F_OUTPUT.get(ram, blk)
            if out == POSITION_FREE or (out == POSITION_HOLD and self._hold_is_free):
                world.release(index)
                self.commanded[index] = None
                self._effective.pop(index, None)
                self._hold.pop(index, None)
                continue
            now = world.servo_angle(index)
            if out == POSITION_HOLD:
                goal = self._hold.setdefault(index, now)
            else:
                self._hold.pop(index, None)
                sent = outs.get(index, out)
                goal = model.angle(index, sent, SERVO.F_BASE.get(ram, blk))
            self.commanded[index] = goal
            prev = self._effective.get(index, now)
            step = speed_cap(servo.spec, speed.get(index)) * dt
            eff = prev + max(-step, min(step, goal - prev)) if dt > 0 else goal
            self._effective[index] = eff
            world.drive(index, eff, world.stiffness(index, stretch.get(index)))

    def _measure(self) -> None:
        b = self.board
        ram = b.ram
        world = self.world
        model = world.model
        positions: dict[int, int] = {}
        for index in world.servos:
            blk = b.alloc(index)
            if blk == NO_BLOCK:
                continue
            base = SERVO.F_BASE.get(ram, blk)
            positions[index] = model.value(index, world.servo_angle(index), base)
        gyro, accel = world.imu()
        b.measure(positions, self.sensors.channels(gyro, accel))
