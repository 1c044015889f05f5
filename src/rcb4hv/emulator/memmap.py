"""The emulator's names for board memory, all taken from :mod:`rcb4hv.protocol.memory`.

The hot loops index RAM directly (a ``bytearray``), so they use these module constants
rather than attribute look-ups; every offset and address comes from the protocol's memory
map. Nothing else in :mod:`rcb4hv.emulator` spells a raw servo-block offset or RAM address.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD, RAM_SIZE, ROM_SIZE
from rcb4hv.protocol.memory import ADDR, SERVO, SYS

__all__ = [
    "ALLOC",
    "BLOCK_SIZE",
    "BUTTONS",
    "FREE",
    "HOLD",
    "PC",
    "RAM_SIZE",
    "ROM_SIZE",
    "SYS_ICS",
    "SYS_ROM",
    "SYS_VEC",
]

# RAM addresses (spec 10.1)
SYSTEM: Final = ADDR.SYSTEM
PC: Final = ADDR.PC
CALL_DEPTH: Final = ADDR.CALL_DEPTH
UPDATE_FLAGS: Final = ADDR.UPDATE_FLAGS
UPDATE_FLAGS_END: Final = ADDR.UPDATE_FLAGS + 5
AD_VALUES: Final = ADDR.AD_VALUES
PIO_DIRECTION: Final = ADDR.PIO_DIRECTION
TIMERS: Final = ADDR.TIMERS
ALLOC: Final = ADDR.ICS_ALLOC
ALLOC_BYTES: Final = 2 * 36
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
ROMERR_BIT: Final = SYS.ROM_ERROR >> 8

FREE: Final = POSITION_FREE
HOLD: Final = POSITION_HOLD

# the 20-byte servo block (spec 9): byte offsets of its fields
BLOCK_SIZE: Final = 20
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
# a mixing entry: source word, then the method byte
MIX_METHOD: Final = SERVO.MIX1_METHOD - SERVO.MIX1_SOURCE
# high bytes of the word fields
B_BASE_HI: Final = B_BASE + 1
B_MEASURED_HI: Final = B_MEASURED + 1
B_OUTPUT_HI: Final = B_OUTPUT + 1
B_END_HI: Final = B_END + 1
B_WIDTH_HI: Final = B_WIDTH + 1

# a vector package (spec 11.3): 8 bytes, up to 32 in a table
VECTOR_PACKAGE_SIZE: Final = 8
VECTOR_PACKAGES: Final = 32
V_DST: Final = 1  # word: RAM address, or 8000h | ICS << 8 | offset
V_SRC: Final = 3  # word: as V_DST, or a literal with the LITERAL bit
V_TARGET: Final = 5  # 24-bit ROM address
V_COND: Final = 0x0F  # control byte: the condition nibble (same layout as JUMP's COND)
V_LITERAL: Final = 0x10
V_WORD: Final = 0x20
V_JUMP: Final = 0x40  # a JUMP (else a CALL)
V_LAST: Final = 0x80  # the last package of the table
V_ICS_OPERAND: Final = 0x8000


def word(ram: bytearray | bytes, a: int) -> int:
    """The little-endian word at ``a``."""
    return ram[a] | ram[a + 1] << 8


def set_word(ram: bytearray, a: int, v: int) -> None:
    ram[a] = v & 0xFF
    ram[a + 1] = (v >> 8) & 0xFF


def s16(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v
