"""Servo command frames (0Fh, 10h) from plain values in one step: the host's hot path.

A control loop sends a 10h frame per cycle. Building it through the dataclass (validate each
pair, sort, store a tuple, then encode byte by byte) costs more host time than the frame
spends on the wire at 35 servos, so :func:`const_frame_servo_frame` and
:func:`single_servo_frame` check the arguments in bulk (C-level ``map``/``min``/``max``, no
per-call dict or list building beyond the one sort) and pack them with the layouts of
:mod:`.servopack`. Anything the bulk check does not accept as plainly valid is handed to the
dataclass, which either raises the precise ``ValueError`` (before any byte is sent) or
builds the same frame: the fast path never accepts what the dataclass would refuse, and
gives the same bytes (``tests/protocol/test_protocol_fastpath.py``).
"""

from __future__ import annotations

import struct
from collections.abc import Iterable, Mapping
from typing import Final

from rcb4hv.protocol.frame import seal
from rcb4hv.protocol.servocmds import RunConstFrameServo, RunSingleServo
from rcb4hv.protocol.servopack import (
    CONST_FRAME_CMD,
    CONST_LAYOUTS,
    FLAG_BIT,
    POSITION_LIMIT,
    SINGLE_ICS_LIMIT,
    pack_single_servo,
    servo_set,
)

__all__ = ["const_frame_servo_frame", "single_servo_frame"]

_INT: Final = frozenset((int,))


def const_frame_servo_frame(
    speed: int,
    positions: Mapping[int, int] | Iterable[tuple[int, int]],
    set_update_flag: bool = True,
) -> bytes:
    """The frame of ``RunConstFrameServo(speed, positions, set_update_flag)``.

    Raises ``ValueError`` exactly when the dataclass does.
    """
    if (
        type(positions) is dict
        and positions
        and type(speed) is int
        and 0 <= speed <= 0xFF
        and type(set_update_flag) is bool
        and set(map(type, positions)) <= _INT  # before the lookup: True == 1 as a key
    ):
        servos = servo_set(tuple(positions))
        if servos is not None:
            keys, low, high = servos
            values = list(map(positions.__getitem__, keys))
            if set(map(type, values)) <= _INT:
                n = len(keys)
                try:  # "H" refuses values outside 0..FFFF
                    body = CONST_LAYOUTS[n].pack(
                        9 + 2 * n,
                        CONST_FRAME_CMD,
                        low,
                        high if set_update_flag else high | FLAG_BIT,
                        speed,
                        *values,
                    )
                except struct.error:
                    pass
                else:
                    return seal(body)
    return RunConstFrameServo(speed, positions, set_update_flag).encode()


def single_servo_frame(ics: int, speed: int, position: int, set_update_flag: bool = True) -> bytes:
    """The frame of ``RunSingleServo(ics, speed, position, set_update_flag)``.

    Raises ``ValueError`` exactly when the dataclass does.
    """
    if (
        type(ics) is int
        and type(speed) is int
        and type(position) is int
        and type(set_update_flag) is bool
        and 0 <= ics < SINGLE_ICS_LIMIT
        and 0 <= speed <= 0xFF
        and 0 <= position <= POSITION_LIMIT
    ):
        return pack_single_servo(ics, speed, position, set_update_flag)
    return RunSingleServo(ics, speed, position, set_update_flag).encode()
