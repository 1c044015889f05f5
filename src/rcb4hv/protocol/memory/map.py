"""Addresses of the RCB-4HV memory map (spec section 10), the system register, buttons and
unit conversions. The struct views over these addresses are in :mod:`.views`."""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final

from rcb4hv.protocol.operands import ICS_COUNT, POSITION_MAX, POSITION_MIN

__all__ = [
    "ADDR",
    "CENTER",
    "COUNTS_PER_DEGREE",
    "FRAME_PERIODS_MS",
    "SYS",
    "SYSTEM_BAUD_RATES",
    "Button",
    "SystemRegister",
    "bitmap_from_ics",
    "degrees_to_position",
    "ics_from_bitmap",
    "ics_number",
    "ics_to_id_port",
    "position_to_degrees",
]


class ADDR:
    """RAM addresses (spec 10.1) and HeartToHeart4's use of the user area."""

    SYSTEM: Final = 0x0000
    PC: Final = 0x0002
    CALL_DEPTH: Final = 0x0005
    UPDATE_FLAGS: Final = 0x0007
    UPDATE_FLAGS_SIZE: Final = 5
    AD_REFERENCE: Final = 0x000C
    AD_VALUES: Final = 0x0022
    PIO_DIRECTION: Final = 0x0038
    PIO_DATA: Final = 0x003A
    TIMERS: Final = (0x003C, 0x003E, 0x0040, 0x0042)
    ICS_ALLOC: Final = 0x0044
    KRI3_ALLOC: Final = 0x008A  # alloc[35], the remote receiver's slot
    VECTOR_TABLE: Final = 0x008C
    USER: Final = 0x0090
    # HeartToHeart4 2.x user-area layout
    SERVO_BLOCKS: Final = 0x0090
    SERVO_BLOCK_SIZE: Final = 20
    KRI3_BLOCK: Final = 0x034C
    KRI3_BLOCK_SIZE: Final = 11  # up to and including the checksum at 0356h
    BUTTONS: Final = 0x0350
    PA: Final = (0x0352, 0x0353, 0x0354, 0x0355)
    KRI3_CHECKSUM: Final = 0x0356
    VECTOR_PACKAGES: Final = 0x0357
    VECTOR_PACKAGE_COUNT: Final = 32
    COUNTERS: Final = 0x0457
    COUNTER_COUNT: Final = 11
    USER_VARIABLES: Final = 0x0462
    USER_VARIABLE_COUNT: Final = 20
    TEMPORARIES: Final = (0x048A, 0x048C)
    AD_COUNT: Final = 11

    @staticmethod
    def servo_block(ics: int) -> int:
        """Where HeartToHeart4 puts the servo block of ICS ``ics`` (0-35): 0090h + 20 ics."""
        if not 0 <= ics <= 35:
            raise ValueError("ICS numbers are 0-35")
        return 0x0090 + 20 * ics

    @staticmethod
    def timer(n: int) -> int:
        if not 0 <= n <= 3:
            raise ValueError("timers are 0-3")
        return ADDR.TIMERS[n]

    @staticmethod
    def alloc(ics: int) -> int:
        if not 0 <= ics <= 35:
            raise ValueError("ICS numbers are 0-35")
        return 0x0044 + 2 * ics

    @staticmethod
    def ad(channel: int) -> int:
        if not 0 <= channel <= 10:
            raise ValueError("AD channels are 0-10")
        return 0x0022 + 2 * channel

    @staticmethod
    def user_variable(n: int) -> int:
        if not 0 <= n < 20:
            raise ValueError("user variables are 0-19")
        return 0x0462 + 2 * n

    @staticmethod
    def counter(n: int) -> int:
        if not 0 <= n < 11:
            raise ValueError("counters are 0-10")
        return 0x0457 + n


FRAME_PERIODS_MS: Final = (10, 15, 20, 25)
SYSTEM_BAUD_RATES: Final = (115200, 625000, 1250000, 115200)
"""COM / ICS baud rate by the 2-bit code of system register bits 7-6 / 14-13 (spec 10.2).
(:data:`rcb4hv.transport.BAUD_RATES` is the other list: the rates a host port can use.)"""
COUNTS_PER_DEGREE: Final = 8000 / 270
CENTER: Final = 7500


class SYS:
    """Bits of the system register word at RAM 0000h (spec 10.2); see :class:`SystemRegister`."""

    ICS_OUTPUT: Final = 0x0001  # ICS_F: servo output enabled
    ROM_RUN: Final = 0x0002  # ROM_F: run the ROM program
    MESSAGE: Final = 0x0004  # MSG_F
    VECTOR_JUMP: Final = 0x0008  # VEC_F
    ZERO: Final = 0x0100  # Z flag
    CARRY: Final = 0x0200  # C flag
    ROM_ERROR: Final = 0x0400  # ROMERR
    LED: Final = 0x8000


class Button(enum.IntFlag):
    """Remote-control buttons as they appear in the button word (RAM 0350h, high byte first)."""

    NONE = 0
    UP = 0x0001
    DOWN = 0x0002
    RIGHT = 0x0004
    LEFT = 0x0008
    TRIANGLE = 0x0010
    CROSS = 0x0020
    CIRCLE = 0x0040
    SQUARE = 0x0100
    S1 = 0x0200
    S2 = 0x0400
    S3 = 0x0800
    S4 = 0x1000

    def to_ram(self) -> bytes:
        """The two RAM bytes of the button word (stored high byte first)."""
        return int(self).to_bytes(2, "big")

    @classmethod
    def from_ram(cls, data: bytes) -> Button:
        return cls(int.from_bytes(data[:2], "big") & 0x1F7F)


@dataclass(frozen=True, slots=True)
class SystemRegister:
    """The system register (word at RAM 0000h), field by field (spec 10.2)."""

    ics_output: bool = False
    rom_run: bool = False
    message: bool = False
    vector_jump: bool = False
    frame_code: int = 0
    baud_code: int = 0
    zero: bool = False
    carry: bool = False
    rom_error: bool = False
    reserved: int = 0
    ics_baud_code: int = 0
    led: bool = False

    def __post_init__(self) -> None:
        for name in ("frame_code", "baud_code", "ics_baud_code", "reserved"):
            v = getattr(self, name)
            if not isinstance(v, int) or not 0 <= v <= 3:
                raise ValueError(f"{name} must be 0..3")

    @classmethod
    def from_word(cls, word: int) -> SystemRegister:
        if not 0 <= word <= 0xFFFF:
            raise ValueError("the system register is 16 bits")
        return cls(
            ics_output=bool(word & 0x0001),
            rom_run=bool(word & 0x0002),
            message=bool(word & 0x0004),
            vector_jump=bool(word & 0x0008),
            frame_code=(word >> 4) & 3,
            baud_code=(word >> 6) & 3,
            zero=bool(word & 0x0100),
            carry=bool(word & 0x0200),
            rom_error=bool(word & 0x0400),
            reserved=(word >> 11) & 3,
            ics_baud_code=(word >> 13) & 3,
            led=bool(word & 0x8000),
        )

    @classmethod
    def from_bytes(cls, data: bytes) -> SystemRegister:
        return cls.from_word(int.from_bytes(data[:2], "little"))

    def to_word(self) -> int:
        return (
            int(self.ics_output)
            | int(self.rom_run) << 1
            | int(self.message) << 2
            | int(self.vector_jump) << 3
            | self.frame_code << 4
            | self.baud_code << 6
            | int(self.zero) << 8
            | int(self.carry) << 9
            | int(self.rom_error) << 10
            | self.reserved << 11
            | self.ics_baud_code << 13
            | int(self.led) << 15
        )

    def to_bytes(self) -> bytes:
        return self.to_word().to_bytes(2, "little")

    @property
    def frame_period_ms(self) -> int:
        """Servo output period in milliseconds (10, 15, 20 or 25)."""
        return FRAME_PERIODS_MS[self.frame_code]

    @property
    def baud_rate(self) -> int:
        return SYSTEM_BAUD_RATES[self.baud_code]

    @property
    def ics_baud_rate(self) -> int:
        return SYSTEM_BAUD_RATES[self.ics_baud_code]

    @staticmethod
    def frame_code_for(period_ms: int) -> int:
        if period_ms not in FRAME_PERIODS_MS:
            raise ValueError(f"frame period must be one of {FRAME_PERIODS_MS} ms")
        return FRAME_PERIODS_MS.index(period_ms)

    @staticmethod
    def baud_code_for(baud: int) -> int:
        if baud not in SYSTEM_BAUD_RATES:
            raise ValueError(f"baud must be one of {sorted(set(SYSTEM_BAUD_RATES))}")
        return SYSTEM_BAUD_RATES.index(baud)

    def describe(self) -> dict[str, object]:
        """A JSON-friendly view."""
        return {
            "word": f"{self.to_word():04X}",
            "ics_output": self.ics_output,
            "rom_run": self.rom_run,
            "message": self.message,
            "vector_jump": self.vector_jump,
            "frame_period_ms": self.frame_period_ms,
            "baud": self.baud_rate,
            "zero": self.zero,
            "carry": self.carry,
            "rom_error": self.rom_error,
            "ics_baud": self.ics_baud_rate,
            "led": self.led,
        }


def bitmap_from_ics(ics_numbers: Iterable[int], keep_update_flags: bool = False) -> bytes:
    """The 5-byte servo bitmap selecting ``ics_numbers`` (bit 39 = keep update flags)."""
    m = 0
    for k in ics_numbers:
        if not 0 <= k <= 35:
            raise ValueError(f"ICS number {k} out of range 0..35")
        m |= 1 << k
    if keep_update_flags:
        m |= 1 << 39
    return m.to_bytes(5, "little")


def ics_from_bitmap(bitmap: bytes) -> list[int]:
    """The ICS numbers selected by a 5-byte bitmap (bit 39 and bits 36-38 ignored)."""
    value = int.from_bytes(bitmap[:5], "little")
    return [k for k in range(ICS_COUNT) if value >> k & 1]


def ics_number(servo_id: int, sio: int) -> int:
    """ICS number of servo ``servo_id`` (0-17) on port SIO1-8."""
    if not 0 <= servo_id <= 17:
        raise ValueError("servo IDs are 0-17")
    if not 1 <= sio <= 8:
        raise ValueError("SIO ports are 1-8")
    return servo_id * 2 + (0 if sio <= 4 else 1)


def ics_to_id_port(ics: int) -> tuple[int, str]:
    """(servo ID, port group) for an ICS number: group ``"SIO1-4"`` or ``"SIO5-8"``."""
    if not 0 <= ics < ICS_COUNT:
        raise ValueError(f"ICS numbers are 0-{ICS_COUNT - 1}")
    return ics // 2, "SIO1-4" if ics % 2 == 0 else "SIO5-8"


def position_to_degrees(position: int) -> float:
    """Servo position counts to degrees from centre (7500 = 0; 8000/270 counts a degree)."""
    return (position - CENTER) / COUNTS_PER_DEGREE


def degrees_to_position(degrees: float) -> int:
    """Degrees from centre to servo position counts, clamped to the documented
    POSITION_MIN..POSITION_MAX (3500..11500)."""
    pos = round(CENTER + degrees * COUNTS_PER_DEGREE)
    return max(POSITION_MIN, min(POSITION_MAX, pos))
