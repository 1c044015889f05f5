"""The values the robot-level API returns (servo table, program and board state, host-side
calibration)."""

from __future__ import annotations

import math
from collections.abc import Collection, Mapping
from dataclasses import dataclass, field
from typing import Final, Literal

from rcb4hv.client.args import finite, integer
from rcb4hv.client.readplan import LinkCost
from rcb4hv.errors import ArgumentError, ArgumentTypeError
from rcb4hv.protocol import (
    COUNTS_PER_DEGREE,
    ServoBlock,
    SystemRegister,
    ics_to_id_port,
)
from rcb4hv.protocol.memory import CENTER, SYS, TimerState
from rcb4hv.protocol.servomode import output_mode
from rcb4hv.rom.layout import LAYOUTS, MotionLayout
from rcb4hv.values import plain

__all__ = [
    "HTH4_20",
    "MAX_SPEED",
    "PLANS_KEPT",
    "SERVO_LIMIT",
    "BoardInfo",
    "Calibration",
    "MotionStatus",
    "ServoInfo",
    "TimerState",
    "robot_options",
    "servo_calibration",
]

MAX_SPEED: Final = 255
"""The longest move one servo command can ask: its speed byte counts output periods."""
SERVO_LIMIT: Final = 35
"""ICS numbers below this can be servos; ICS 35 is the remote-control receiver slot."""
PLANS_KEPT: Final = 64
"""How many bulk-read plans a robot remembers (a control loop reads the same spans)."""

HTH4_20: Final = LAYOUTS["2.0"]
"""HeartToHeart4 2.0 / 2.1: motion n at 0BB8h + 2048 (n - 1) (:data:`HTH4_22` is 2.2)."""


@dataclass(frozen=True, slots=True)
class Calibration:
    """Host-side angle calibration of one servo: ``trim`` in counts added to the centre
    (7500) and ``direction`` (+1 or -1) of positive angles. A field that is not a number is
    an :class:`~rcb4hv.errors.ArgumentTypeError`, a trim that is not finite (NaN, inf) or a
    direction other than +1/-1 an :class:`~rcb4hv.errors.ArgumentError`, both naming it."""

    trim: int = 0
    direction: Literal[1, -1] = 1

    def __post_init__(self) -> None:
        finite("trim", self.trim)
        if finite("direction", self.direction) not in (1, -1):
            raise ArgumentError(f"direction must be +1 or -1, not {plain(self.direction)}")

    def to_position(self, degrees: float) -> int:
        if not math.isfinite(degrees):
            raise ArgumentError(f"angle {degrees!r} is not a finite number of degrees")
        return round(CENTER + self.trim + self.direction * degrees * COUNTS_PER_DEGREE)

    def to_degrees(self, position: int) -> float:
        return self.direction * (position - CENTER - self.trim) / COUNTS_PER_DEGREE


_NO_CALIBRATION: Final = Calibration()


def robot_options(
    layout: object, calibration: object, link_cost: object
) -> tuple[MotionLayout | None, dict[int, Calibration], LinkCost]:
    """A robot's ``layout``, ``calibration`` and ``link_cost`` as it keeps them, checked before
    anything is opened or sent: ``layout`` a :class:`~rcb4hv.rom.layout.MotionLayout` or a
    HeartToHeart4 version naming one (``"2.1"``), ``calibration`` a mapping of ICS number to
    :class:`Calibration`, ``link_cost`` a :class:`~rcb4hv.client.readplan.LinkCost` (None:
    the defaults). A wrong type is an :class:`~rcb4hv.errors.ArgumentTypeError`, an unknown
    version or ICS number an :class:`~rcb4hv.errors.ArgumentError`, each naming the argument."""
    if isinstance(layout, str):
        if layout not in LAYOUTS:
            raise ArgumentError(
                f"layout {layout!r}: HeartToHeart4 layouts are {', '.join(sorted(LAYOUTS))}"
            )
        layout = LAYOUTS[layout]
    elif layout is not None and not isinstance(layout, MotionLayout):
        raise ArgumentTypeError(
            f"layout must be a MotionLayout or a version such as '2.1', not {plain(layout)}"
        )
    if calibration is None:
        calibration = {}
    if not isinstance(calibration, Mapping):
        raise ArgumentTypeError(
            f"calibration must map ICS numbers to Calibration, not {plain(calibration)}"
        )
    cal: dict[int, Calibration] = {}
    for key, value in calibration.items():
        k = integer("calibration: ICS number", key)
        if not 0 <= k < SERVO_LIMIT:
            raise ArgumentError(f"calibration: ICS {k} is not a servo (0..{SERVO_LIMIT - 1})")
        if not isinstance(value, Calibration):
            raise ArgumentTypeError(
                f"calibration: ICS {k} needs a Calibration (e.g. Calibration(trim=40)), "
                f"not {plain(value)}"
            )
        cal[k] = value
    if link_cost is None:
        link_cost = LinkCost()
    elif not isinstance(link_cost, LinkCost):
        raise ArgumentTypeError(f"link_cost must be a LinkCost, not {plain(link_cost)}")
    return layout, cal, link_cost


def servo_calibration(
    calibration: Mapping[int, Calibration], servos: Collection[int] | None, ics: object
) -> Calibration:
    """The host calibration of servo ``ics`` (trim 0, direction +1 without an entry), for a
    robot's degree conversions. An ICS number the robot does not have is refused, an
    :class:`~rcb4hv.errors.ArgumentError` naming the ones it has: not one of ``servos`` (its
    servo table, once discovered), or before that (``servos`` None) not a servo's 0..34."""
    k = integer("ICS number", ics)
    if servos is None:
        if not 0 <= k < SERVO_LIMIT:
            raise ArgumentError(f"no servo at ICS {k} (servos are ICS 0..{SERVO_LIMIT - 1})")
    elif k not in servos:
        raise ArgumentError(f"no servo at ICS {k} (the robot has ICS {sorted(servos)})")
    return calibration.get(k, _NO_CALIBRATION)


@dataclass(frozen=True, slots=True)
class ServoInfo:
    """One servo found through the ICS allocation table and its servo block."""

    ics: int
    block_address: int
    block: ServoBlock

    @property
    def servo_id(self) -> int:
        return ics_to_id_port(self.ics)[0]

    @property
    def port(self) -> str:
        return ics_to_id_port(self.ics)[1]

    @property
    def trim(self) -> int:
        """The board's base value (+2): HeartToHeart4's trim."""
        return self.block.base

    @property
    def state(self) -> str:
        mode = output_mode(self.block.output)
        if mode != "angle":
            return mode
        return "moving" if self.block.speed else "on"

    def describe(self) -> dict[str, object]:
        b = self.block
        return {
            "ics": self.ics,
            "id": self.servo_id,
            "port": self.port,
            "block": f"{self.block_address:04X}",
            "trim": b.base,
            "measured": b.measured,
            "output": b.output,
            "state": self.state,
            "speed": b.speed,
            "remaining": b.remaining,
        }


@dataclass(frozen=True, slots=True)
class MotionStatus:
    """The ROM program's state: PC, call depth, update flags, the motion it is in (playing,
    paused or stopped by a ROM error), whether that motion is being played (or paused), and
    the system register."""

    pc: int
    call_depth: int
    update_flags: bytes
    motion: int | None
    running: bool
    system: int = SYS.ROM_RUN

    @property
    def paused(self) -> bool:
        """The ROM program does not run (ROM_F clear): paused by a host, or stopped by an error."""
        return not self.system & SYS.ROM_RUN

    @property
    def rom_error(self) -> bool:
        """The ROM program stopped with a ROM error: ROMERR set and ROM_F clear (ROMERR alone
        stays set once the program runs again: HeartToHeart4's play sequence keeps it)."""
        return bool(self.system & SYS.ROM_ERROR) and not self.system & SYS.ROM_RUN

    @property
    def state(self) -> str:
        """``stopped by a ROM error``, ``paused``, ``playing`` or ``idle`` (no motion plays)."""
        if self.rom_error:
            return "stopped by a ROM error"
        if self.paused:
            return "paused"
        return "playing" if self.running else "idle"


@dataclass(frozen=True, slots=True)
class BoardInfo:
    """What :meth:`Robot.info` reports: version, system register, program state, servos."""

    version: str
    system: SystemRegister
    pc: int
    call_depth: int
    update_flags: bytes
    servos: list[ServoInfo] = field(default_factory=list)

    def describe(self) -> dict[str, object]:
        return {
            "version": self.version,
            "system_register": self.system.describe(),
            "pc": f"{self.pc:06X}",
            "call_depth": self.call_depth,
            "update_flags": self.update_flags.hex(),
            "servos": [s.describe() for s in self.servos],
        }
