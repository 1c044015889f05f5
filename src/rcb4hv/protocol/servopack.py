"""The layouts of the servo command frames (0Fh, 10h) and their packers.

The frame layouts live here once, as precompiled :class:`struct.Struct` objects; the packers
take values already checked and add the checksum through :func:`rcb4hv.protocol.frame.seal`.
Both the command classes (:meth:`RunConstFrameServo.encode`, :meth:`RunSingleServo.encode` in
:mod:`.servocmds`) and the one-step frame builders of the host's hot path
(:mod:`.servoframes`) use them.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence
from typing import Final

from rcb4hv.protocol.frame import seal
from rcb4hv.protocol.operands import ICS_COUNT, Op

__all__ = [
    "CONST_FRAME_CMD",
    "CONST_LAYOUTS",
    "FLAG_BIT",
    "POSITION_LIMIT",
    "SINGLE_ICS_LIMIT",
    "SINGLE_LAYOUT",
    "SINGLE_SERVO_CMD",
    "pack_const_frame",
    "pack_single_servo",
    "servo_set",
]

SINGLE_ICS_LIMIT: Final = 0x80  # 0Fh: any 7-bit ICS number (bit 7 is the update-flag bit)
POSITION_LIMIT: Final = 0xFFFF
FLAG_BIT: Final = 0x80  # bitmap bit 39 / ICS byte bit 7: leave the other update flags alone
CONST_FRAME_CMD: Final = Op.CONST_FRAME_SERVO
SINGLE_SERVO_CMD: Final = Op.SINGLE_SERVO

_BIT: Final = tuple(1 << k for k in range(ICS_COUNT))
# 10h: SIZE CMD bitmap(5: 32 low bits, 8 high bits) SPEED positions(n x u16) - SUM appended
CONST_LAYOUTS: Final = tuple(struct.Struct(f"<BBIBB{n}H") for n in range(ICS_COUNT + 1))
# 0Fh: SIZE CMD ICS SPEED position(u16) - SUM appended
SINGLE_LAYOUT: Final = struct.Struct("<BBBBH")
_SERVO_SETS: dict[tuple[int, ...], tuple[list[int], int, int]] = {}
_SERVO_SETS_KEPT: Final = 256


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
    return seal(CONST_LAYOUTS[n].pack(9 + 2 * n, CONST_FRAME_CMD, low, high, speed, *positions))


def pack_single_servo(ics: int, speed: int, position: int, set_update_flag: bool) -> bytes:
    """The 0Fh frame of already checked values."""
    b = ics | (0 if set_update_flag else FLAG_BIT)
    return seal(SINGLE_LAYOUT.pack(7, SINGLE_SERVO_CMD, b, speed, position))


def servo_set(order: tuple[int, ...]) -> tuple[list[int], int, int] | None:
    """Sorted ICS numbers, bitmap low 32 bits and high byte of the ints in ``order`` (dict
    order), or None if one is outside 0-35; remembered, a loop commands the same servos."""
    got = _SERVO_SETS.get(order)
    if got is None:
        keys = sorted(order)
        if keys[0] < 0 or keys[-1] >= ICS_COUNT:
            return None
        bitmap = sum(map(_BIT.__getitem__, keys))
        if len(_SERVO_SETS) >= _SERVO_SETS_KEPT:
            _SERVO_SETS.clear()
        got = _SERVO_SETS[order] = (keys, bitmap & 0xFFFFFFFF, bitmap >> 32)
    return got
