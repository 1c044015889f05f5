"""The documented value ranges of the command reference, as checks for the robot level and lint.

The wire layer (:mod:`rcb4hv.protocol.commands`), the ROM layer and the emulator accept every
value the frame format can carry, because real HeartToHeart4 projects hold values outside the
documented ranges and the board runs them (SetStretch 0, positions 2100 or 12700, ...). The
documented ranges are enforced where a person asks for a value - :class:`rcb4hv.client.Robot`
- and reported by the project lint (:mod:`rcb4hv.project.check`). This module is the one place
that states them.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol import (
    ICS_COUNT,
    POSITION_FREE,
    POSITION_HOLD,
    POSITION_MAX,
    POSITION_MIN,
)

__all__ = [
    "OVERRIDE",
    "SERVO_SPEED_MAX",
    "SERVO_SPEED_MIN",
    "STRETCH_MAX",
    "STRETCH_MIN",
    "check_documented_ics",
    "check_documented_position",
    "check_documented_servo_speed",
    "check_documented_stretch",
    "documented_position",
    "documented_servo_speed",
    "documented_stretch",
]

STRETCH_MIN: Final = 1
STRETCH_MAX: Final = 127
"""SetStretch / SetSpeed (12h) values: 1-127 (command reference, 12h parameters)."""

SERVO_SPEED_MIN: Final = 1
SERVO_SPEED_MAX: Final = 255
"""Speed (output periods) of 0Fh/10h/11h: 1-255 (command reference, 10h and 11h)."""


def documented_position(position: int) -> bool:
    """3500..11500, or the special values 7FFFh (hold) and 8000h (free)."""
    return POSITION_MIN <= position <= POSITION_MAX or position in (POSITION_HOLD, POSITION_FREE)


def documented_stretch(value: int) -> bool:
    """A SetStretch / SetSpeed value inside the documented 1-127."""
    return STRETCH_MIN <= value <= STRETCH_MAX


def documented_servo_speed(speed: int) -> bool:
    """A servo-move speed inside the documented 1-255 (0 is outside: spec 13 #7)."""
    return SERVO_SPEED_MIN <= speed <= SERVO_SPEED_MAX


def _int(what: str, value: object) -> int:
    if not isinstance(value, int) or isinstance(value, bool):
        raise ValueError(f"{what} must be an int, not {value!r}")
    return value


def check_documented_ics(ics: int) -> None:
    """ValueError unless ``ics`` is an ICS number 0-35."""
    if not 0 <= _int("ICS number", ics) < ICS_COUNT:
        raise ValueError(f"ICS number {ics} outside 0..{ICS_COUNT - 1}")


OVERRIDE: Final = "check_range=False"
"""What the message of a range check tells the caller to pass to send a value anyway: the
argument of the Python API. A caller with another way to say it (the CLI's ``--unchecked``)
passes its own as ``override``."""


def check_documented_position(ics: int, position: int, *, override: str = OVERRIDE) -> None:
    """ValueError unless ``position`` is 3500..11500, hold or free (the message tells to pass
    ``override`` to send it anyway)."""
    if not documented_position(_int(f"ICS {ics}: position", position)):
        raise ValueError(
            f"ICS {ics}: position {position} outside {POSITION_MIN}..{POSITION_MAX} "
            f"(pass {override} to send it anyway)"
        )


def check_documented_stretch(what: str, ics: int, value: int, *, override: str = OVERRIDE) -> None:
    """ValueError unless ``value`` is a documented SetStretch/SetSpeed value (1-127) (the
    message tells to pass ``override`` to send it anyway)."""
    if not documented_stretch(_int(f"ICS {ics}: {what}", value)):
        raise ValueError(
            f"ICS {ics}: {what} {value} outside {STRETCH_MIN}..{STRETCH_MAX} "
            f"(pass {override} to send it anyway)"
        )


def check_documented_servo_speed(speed: int) -> None:
    """ValueError unless ``speed`` is a documented servo speed (1-255)."""
    if not documented_servo_speed(_int("speed", speed)):
        raise ValueError(f"speed {speed} outside {SERVO_SPEED_MIN}..{SERVO_SPEED_MAX}")
