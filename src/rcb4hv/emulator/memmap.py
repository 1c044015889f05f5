"""The emulator's names for board memory, all taken from the typed map
(:mod:`rcb4hv.protocol.memory`).

The hot loops index RAM (a ``bytearray``) directly, so they bind these module constants and
the map's precompiled structs (``U16.unpack_from`` and friends) rather than going through
attribute look-ups or :class:`~rcb4hv.protocol.memory.Field` objects. Every address, offset
and bit here is the map's own; nothing else in :mod:`rcb4hv.emulator` spells one.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol import ICS_COUNT, POSITION_FREE, POSITION_HOLD, RAM_SIZE, ROM_SIZE
from rcb4hv.protocol.memory import (
    ADDR,
    NO_BLOCK,
    S16,
    SERVO,
    SYS,
    TIMER_STOPPED,
    TIMERS,
    U16,
    U24,
    VEC,
    VECTOR_PACKAGE,
    mix_rate,
    mix_source,
    operand_ics,
    read_u16,
    s16,
    write_u16,
)

__all__ = [
    "NO_BLOCK",
    "RAM_SIZE",
    "ROM_SIZE",
    "S16",
    "SERVO",
    "TIMERS",
    "TIMER_STOPPED",
    "U16",
    "U24",
    "VEC",
    "VECTOR_PACKAGE",
    "mix_rate",
    "mix_source",
    "operand_ics",
    "read_u16",
    "s16",
    "write_u16",
]

# RAM addresses (spec 10.1)
SYSTEM: Final = ADDR.SYSTEM
SYSTEM_HI: Final = ADDR.SYSTEM + 1  # the flag byte: Z, C, ROMERR
PC: Final = ADDR.PC
CALL_DEPTH: Final = ADDR.CALL_DEPTH
UPDATE_FLAGS: Final = ADDR.UPDATE_FLAGS
UPDATE_FLAGS_END: Final = ADDR.UPDATE_FLAGS + ADDR.UPDATE_FLAGS_SIZE
AD_REFERENCE: Final = ADDR.AD_REFERENCE
AD_VALUES: Final = ADDR.AD_VALUES
AD_CHANNELS: Final = ADDR.AD_COUNT
# a write here changes a reference: the board samples its AD inputs again (spec 10.4)
AD_REFERENCE_END: Final = ADDR.AD_REFERENCE + 2 * ADDR.AD_COUNT
PIO_DIRECTION: Final = ADDR.PIO_DIRECTION
TIMER_BASE: Final = ADDR.TIMERS[0]
ALLOC: Final = ADDR.ICS_ALLOC
ALLOC_END: Final = ADDR.ICS_ALLOC + 2 * ICS_COUNT
VECTOR_TABLE: Final = ADDR.VECTOR_TABLE
BUTTONS: Final = ADDR.BUTTONS
PA: Final = ADDR.PA
# vector operands from the button word up (HeartToHeart4's user area) never change by
# themselves: only a host or the program writes them
STATIC_VECTOR_RAM: Final = ADDR.BUTTONS

# the system-register bits as the hot paths test them: low byte RAM[0], high byte RAM[1]
SYS_ICS: Final = SYS.ICS_OUTPUT
SYS_ROM: Final = SYS.ROM_RUN
SYS_VEC: Final = SYS.VECTOR_JUMP
Z_BIT: Final = SYS.ZERO >> 8
C_BIT: Final = SYS.CARRY >> 8
ROMERR_BIT: Final = SYS.ROM_ERROR >> 8

FREE: Final = POSITION_FREE
HOLD: Final = POSITION_HOLD

# the servo block (spec 9): byte offsets of its fields (writes in the hot loops store the
# two bytes of a word separately: the *_HI offsets)
BLOCK_SIZE: Final = SERVO.SIZE
B_TYPE: Final = SERVO.TYPE
B_BASE: Final = SERVO.BASE
B_MEASURED: Final = SERVO.MEASURED
B_OUTPUT: Final = SERVO.OUTPUT
B_SPEED: Final = SERVO.SPEED
B_END: Final = SERVO.END
B_REMAINING: Final = SERVO.REMAINING
B_WIDTH: Final = SERVO.WIDTH
B_MIX1: Final = SERVO.MIX1_SOURCE
B_MIX2: Final = SERVO.MIX2_SOURCE
B_MEASURED_HI: Final = B_MEASURED + 1
B_OUTPUT_HI: Final = B_OUTPUT + 1
B_END_HI: Final = B_END + 1
B_WIDTH_HI: Final = B_WIDTH + 1

# vector packages (spec 11.3)
VECTOR_PACKAGE_COUNT: Final = ADDR.VECTOR_PACKAGE_COUNT
