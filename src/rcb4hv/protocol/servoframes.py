"""Servo command frames (0Fh, 10h) from plain values in one step: the host's hot path.

A control loop sends a 10h frame per cycle. Building it through the dataclass (validate each
pair, sort, store a tuple, then encode byte by byte) costs more host time than the frame
spends on the wire at 35 servos, so the frame layouts live here once, as precompiled
:class:`struct.Struct` objects, and :func:`const_frame_servo_frame` and
:func:`single_servo_frame` check the arguments in bulk (C-level ``map``/``min``/``max``, no
per-call dict or list building beyond the one sort) and pack. Anything the bulk check does
not accept as plainly valid is handed to the dataclass, which either raises the precise
``ValueError`` (before any byte is sent) or builds the same frame: the fast path never
accepts what the dataclass would refuse, and gives the same bytes
(``tests/protocol/test_protocol_fastpath.py``). :meth:`RunConstFrameServo.encode` and
:meth:`RunSingleServo.encode` use the same layouts.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable, Mapping, Sequence
from typing import Final
from zlib import adler32

__all__ = [
    "const_frame_servo_frame",
    "pack_const_frame",
    "pack_single_servo",
    "servo_set",
    "single_servo_frame",
]

ICS_LIMIT: Final = 36  # 10h bitmap: ICS numbers 0..35
SINGLE_ICS_LIMIT: Final = 0x80  # 0Fh: any 7-bit ICS number (bit 7 is the update-flag bit)
POSITION_LIMIT: Final = 0xFFFF
FLAG_BIT: Final = 0x80  # bitmap bit 39 / ICS byte bit 7: leave the other update flags alone
CONST_FRAME_CMD: Final = 0x10
SINGLE_SERVO_CMD: Final = 0x0F

_INT: Final = frozenset((int,))
_BIT: Final = tuple(1 << k for k in range(ICS_LIMIT))
# 10h: SIZE CMD bitmap(5: 32 low bits, 8 high bits) SPEED positions(n x u16) - SUM appended
_CONST: Final = tuple(struct.Struct(f"<BBIBB{n}H") for n in range(ICS_LIMIT + 1))
# 0Fh: SIZE CMD ICS SPEED position(u16) SUM
_SINGLE: Final = struct.Struct("<BBBBHB")
_SERVO_SETS: dict[tuple[int, ...], tuple[list[int], int, int]] = {}
_SERVO_SETS_KEPT: Final = 256


def _with_sum(body: bytes) -> bytes:
    return body + bytes((((adler32(body) & 0xFFFF) - 1) & 0xFF,))


def pack_const_frame(
    speed: int, ics: Sequence[int], positions: Sequence[int], set_update_flag: bool
) -> bytes:
    """The 10h frame of already checked, ICS-sorted ``ics`` and ``positions``."""
    n = len(ics)
    if n:
        servos = servo_set(tuple(ics))
        assert servos is not None, "pack_const_frame takes checked ICS numbers"
        _, low, high = servos
    else:
        low = high = 0
    high |= 0 if set_update_flag else FLAG_BIT
    return _with_sum(_CONST[n].pack(9 + 2 * n, CONST_FRAME_CMD, low, high, speed, *positions))


def pack_single_servo(ics: int, speed: int, position: int, set_update_flag: bool) -> bytes:
    """The 0Fh frame of already checked values."""
    b = ics | (0 if set_update_flag else FLAG_BIT)
    s = (7 + SINGLE_SERVO_CMD + b + speed + (position & 0xFF) + (position >> 8)) & 0xFF
    return _SINGLE.pack(7, SINGLE_SERVO_CMD, b, speed, position, s)


def servo_set(order: tuple[int, ...]) -> tuple[list[int], int, int] | None:
    """Sorted ICS numbers, bitmap low 32 bits and high byte of the ints in ``order`` (dict
    order), or None if one is outside 0-35; remembered, a loop commands the same servos."""
    got = _SERVO_SETS.get(order)
    if got is None:
        keys = sorted(order)
        if keys[0] < 0 or keys[-1] >= ICS_LIMIT:
            return None
        bitmap = sum(map(_BIT.__getitem__, keys))
        if len(_SERVO_SETS) >= _SERVO_SETS_KEPT:
            _SERVO_SETS.clear()
        got = _SERVO_SETS[order] = (keys, bitmap & 0xFFFFFFFF, bitmap >> 32)
    return got


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
                    body = _CONST[n].pack(
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
                    return _with_sum(body)
    from rcb4hv.protocol.commands import RunConstFrameServo

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
    from rcb4hv.protocol.commands import RunSingleServo

    return RunSingleServo(ics, speed, position, set_update_flag).encode()
