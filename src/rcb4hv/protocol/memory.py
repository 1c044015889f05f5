"""The RCB-4HV memory map (spec section 10), the system register, servo blocks and helpers."""

from __future__ import annotations

import enum
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final

__all__ = [
    "ADDR",
    "BAUD_RATES",
    "COUNTS_PER_DEGREE",
    "FRAME_PERIODS_MS",
    "SYS",
    "Button",
    "ServoBlock",
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
    AD_REFERENCE: Final = 0x000C
    AD_VALUES: Final = 0x0022
    PIO_DIRECTION: Final = 0x0038
    PIO_DATA: Final = 0x003A
    TIMERS: Final = (0x003C, 0x003E, 0x0040, 0x0042)
    ICS_ALLOC: Final = 0x0044
    VECTOR_TABLE: Final = 0x008C
    USER: Final = 0x0090
    RAM_SIZE: Final = 0x0490
    # HeartToHeart4 2.x user-area layout
    SERVO_BLOCKS: Final = 0x0090
    SERVO_BLOCK_SIZE: Final = 20
    KRI3_BLOCK: Final = 0x034C
    BUTTONS: Final = 0x0350
    PA: Final = (0x0352, 0x0353, 0x0354, 0x0355)
    KRI3_CHECKSUM: Final = 0x0356
    VECTOR_PACKAGES: Final = 0x0357
    COUNTERS: Final = 0x0457
    USER_VARIABLES: Final = 0x0462
    USER_VARIABLE_COUNT: Final = 20
    TEMPORARIES: Final = (0x048A, 0x048C)

    @staticmethod
    def timer(n: int) -> int:
        if not 0 <= n <= 3:
            raise ValueError("timers are 0-3")
        return 0x003C + 2 * n

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
BAUD_RATES: Final = (115200, 625000, 1250000, 115200)
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
        return BAUD_RATES[self.baud_code]

    @property
    def ics_baud_rate(self) -> int:
        return BAUD_RATES[self.ics_baud_code]

    @staticmethod
    def frame_code_for(period_ms: int) -> int:
        if period_ms not in FRAME_PERIODS_MS:
            raise ValueError(f"frame period must be one of {FRAME_PERIODS_MS} ms")
        return FRAME_PERIODS_MS.index(period_ms)

    @staticmethod
    def baud_code_for(baud: int) -> int:
        if baud not in BAUD_RATES:
            raise ValueError(f"baud must be one of {sorted(set(BAUD_RATES))}")
        return BAUD_RATES.index(baud)

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


def _s16(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v


@dataclass(frozen=True, slots=True)
class ServoBlock:
    """The 20-byte servo block HeartToHeart4 puts at 0090h + 20n (spec section 9)."""

    type: int = 0
    ics_id: int = 0
    base: int = 0
    measured: int = 0
    output: int = 0x8000
    speed: int = 0
    end: int = 0
    remaining: int = 0
    width: int = 0
    mix1_source: int = 0xFFFF
    mix1_method: int = 0
    mix2_source: int = 0xFFFF
    mix2_method: int = 0

    SIZE = 20

    @classmethod
    def from_bytes(cls, data: bytes) -> ServoBlock:
        if len(data) < 20:
            raise ValueError("a servo block is 20 bytes")

        def w(i: int) -> int:
            return data[i] | data[i + 1] << 8

        return cls(
            type=data[0],
            ics_id=data[1],
            base=_s16(w(2)),
            measured=w(4),
            output=w(6),
            speed=data[8],
            end=w(9),
            remaining=data[11],
            width=_s16(w(12)),
            mix1_source=w(14),
            mix1_method=data[16],
            mix2_source=w(17),
            mix2_method=data[19],
        )

    def to_bytes(self) -> bytes:
        out = bytearray(20)
        out[0] = self.type & 0xFF
        out[1] = self.ics_id & 0xFF
        out[2:4] = (self.base & 0xFFFF).to_bytes(2, "little")
        out[4:6] = (self.measured & 0xFFFF).to_bytes(2, "little")
        out[6:8] = (self.output & 0xFFFF).to_bytes(2, "little")
        out[8] = self.speed & 0xFF
        out[9:11] = (self.end & 0xFFFF).to_bytes(2, "little")
        out[11] = self.remaining & 0xFF
        out[12:14] = (self.width & 0xFFFF).to_bytes(2, "little")
        out[14:16] = (self.mix1_source & 0xFFFF).to_bytes(2, "little")
        out[16] = self.mix1_method & 0xFF
        out[17:19] = (self.mix2_source & 0xFFFF).to_bytes(2, "little")
        out[19] = self.mix2_method & 0xFF
        return bytes(out)


# offsets inside a servo block
class SERVO:
    TYPE: Final = 0
    ID: Final = 1
    BASE: Final = 2
    MEASURED: Final = 4
    OUTPUT: Final = 6
    SPEED: Final = 8
    END: Final = 9
    REMAINING: Final = 11
    WIDTH: Final = 12
    MIX1_SOURCE: Final = 14
    MIX1_METHOD: Final = 16
    MIX2_SOURCE: Final = 17
    MIX2_METHOD: Final = 19


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
    return [k for k in range(36) if value >> k & 1]


def ics_number(servo_id: int, sio: int) -> int:
    """ICS number of servo ``servo_id`` (0-17) on port SIO1-8."""
    if not 0 <= servo_id <= 17:
        raise ValueError("servo IDs are 0-17")
    if not 1 <= sio <= 8:
        raise ValueError("SIO ports are 1-8")
    return servo_id * 2 + (0 if sio <= 4 else 1)


def ics_to_id_port(ics: int) -> tuple[int, str]:
    """(servo ID, port group) for an ICS number: group ``"SIO1-4"`` or ``"SIO5-8"``."""
    if not 0 <= ics <= 35:
        raise ValueError("ICS numbers are 0-35")
    return ics // 2, "SIO1-4" if ics % 2 == 0 else "SIO5-8"


def position_to_degrees(position: int) -> float:
    """Servo position counts to degrees from centre (7500 = 0; 8000/270 counts a degree)."""
    return (position - CENTER) / COUNTS_PER_DEGREE


def degrees_to_position(degrees: float) -> int:
    """Degrees from centre to servo position counts, clamped to 3500..11500."""
    pos = round(CENTER + degrees * COUNTS_PER_DEGREE)
    return max(3500, min(11500, pos))
