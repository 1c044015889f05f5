"""Struct views of the RAM regions (spec 10.1): the system word and program state, timers,
counters, user variables, the button word, PA1-PA4, AD channels and PIO.

Each region has a precompiled :class:`struct.Struct` and functions that read it from any
buffer at any address (default: its RAM address), so the same view decodes the emulator's RAM
and a span the client read from a board (pass ``at=0``).
"""

from __future__ import annotations

from dataclasses import dataclass
from struct import Struct
from typing import Final

from rcb4hv.protocol.memory.fields import (
    U16_BE,
    ReadBuffer,
    WriteBuffer,
    read_u16,
    read_u24,
    u16_bytes,
    u24_bytes,
    write_u16,
)
from rcb4hv.protocol.memory.map import ADDR, SYS, Button

__all__ = [
    "AD_CHANNELS",
    "AD_MASK",
    "AD_READINGS",
    "COUNTERS",
    "PA_VALUES",
    "PIO_MASK",
    "PIO_WORDS",
    "PROGRAM_STATE",
    "RUN_STATE",
    "RUN_STATE_SIZE",
    "TIMERS",
    "TIMER_STOPPED",
    "USER_VARIABLES",
    "AdReadings",
    "ProgramState",
    "TimerState",
    "ad_readings",
    "ad_volts",
    "program_reset",
    "read_buttons",
    "read_pc",
    "read_run_state",
    "read_system",
    "read_update_flags",
    "system_word_bytes",
    "write_buttons",
    "write_system",
]

# ----------------------------------------------------------------------------- program state


def read_system(buf: ReadBuffer, at: int = ADDR.SYSTEM) -> int:
    """The system register word (see :class:`~rcb4hv.protocol.memory.SYS`)."""
    return read_u16(buf, at)


def write_system(buf: WriteBuffer, word: int, at: int = ADDR.SYSTEM) -> None:
    write_u16(buf, at, word)


def system_word_bytes(word: int) -> bytes:
    """The two RAM bytes of a system register value."""
    return u16_bytes(word)


PROGRAM_STATE: Final = Struct("<HHBBB5s")
"""RAM 0000h-000Bh: system word, PC (low word, high byte), call depth, unused, update flags."""


@dataclass(frozen=True, slots=True)
class ProgramState:
    """The ROM program's state in RAM 0000h-000Bh (spec 10.1)."""

    system: int
    pc: int
    call_depth: int
    update_flags: bytes

    SIZE = 12

    @classmethod
    def unpack(cls, buf: ReadBuffer, at: int = ADDR.SYSTEM) -> ProgramState:
        word, lo, hi, depth, _unused, flags = PROGRAM_STATE.unpack_from(buf, at)
        return cls(word, lo | hi << 16, depth, flags)

    @property
    def running(self) -> bool:
        """ROM_F is set."""
        return bool(self.system & SYS.ROM_RUN)

    @property
    def waiting(self) -> bool:
        """An update flag is set: the program waits for a servo move to end."""
        return any(self.update_flags)


RUN_STATE: Final = Struct("<HBBB5s")
"""RAM 0002h-000Bh (what a host reads to follow a motion): PC (low word, high byte), call
depth, unused, update flags."""
RUN_STATE_SIZE: Final = RUN_STATE.size


def read_run_state(buf: ReadBuffer, at: int = ADDR.PC) -> tuple[int, int, bytes]:
    """``(pc, call depth, update flags)`` from the bytes starting at the PC."""
    lo, hi, depth, _unused, flags = RUN_STATE.unpack_from(buf, at)
    return lo | hi << 16, depth, flags


def read_pc(buf: ReadBuffer, at: int = ADDR.PC) -> int:
    """The 24-bit program counter."""
    return read_u24(buf, at)


def read_update_flags(buf: ReadBuffer, at: int = ADDR.UPDATE_FLAGS) -> int:
    """The 40 servo update flags (5 bytes, bit n = ICS n) as one integer."""
    return int.from_bytes(buf[at : at + ADDR.UPDATE_FLAGS_SIZE], "little")


def program_reset(pc: int) -> bytes:
    """The 10 bytes written at :attr:`ADDR.PC` to restart the program at ``pc``: PC, call
    depth 0, the unused byte 0 and all update flags 0 (spec 11.4 step 2)."""
    return u24_bytes(pc) + bytes(2 + ADDR.UPDATE_FLAGS_SIZE)


# ----------------------------------------------------------------------------- timers

TIMERS: Final = Struct("<4H")
"""Timers 0-3 at 003Ch (spec 10.3)."""
TIMER_STOPPED: Final = 0x8000
"""Bit 15 of a timer word: stopped. Bits 14-0 count 100 ms steps down."""


@dataclass(frozen=True, slots=True)
class TimerState:
    """A timer's count (100 ms steps) and whether it runs."""

    count: int
    running: bool

    @classmethod
    def from_word(cls, word: int) -> TimerState:
        return cls(word & 0x7FFF, not word & TIMER_STOPPED)

    @classmethod
    def unpack(cls, buf: ReadBuffer, at: int) -> TimerState:
        return cls.from_word(read_u16(buf, at))

    def to_word(self) -> int:
        if not 0 <= self.count <= 0x7FFF:
            raise ValueError("timer counts are 0..32767")
        return self.count | (0 if self.running else TIMER_STOPPED)

    def to_bytes(self) -> bytes:
        return u16_bytes(self.to_word())


# ----------------------------------------------------------------------------- user area

COUNTERS: Final = Struct(f"<{ADDR.COUNTER_COUNT}B")
"""Counters 0-10, one byte each from 0457h."""
USER_VARIABLES: Final = Struct(f"<{ADDR.USER_VARIABLE_COUNT}h")
"""User variables 0-19, signed words from 0462h."""
PA_VALUES: Final = Struct("<4B")
"""PA1-PA4 at 0352h-0355h."""


def read_buttons(buf: ReadBuffer, at: int = ADDR.BUTTONS) -> Button:
    """The button word (stored high byte first), unknown bits dropped."""
    return Button(U16_BE.unpack_from(buf, at)[0] & 0x1F7F)


def write_buttons(buf: WriteBuffer, buttons: int, at: int = ADDR.BUTTONS) -> None:
    """Store a button word (any 16 bits) high byte first."""
    U16_BE.pack_into(buf, at, int(buttons) & 0xFFFF)


# ----------------------------------------------------------------------------- I/O

AD_CHANNELS: Final = Struct(f"<{ADDR.AD_COUNT}H")
"""AD0-AD10: the measured values at 0022h (10-bit) and the references at 000Ch."""
AD_MASK: Final = 0x3FF
AD_READINGS: Final = Struct(f"<{ADDR.AD_COUNT}H{ADDR.AD_COUNT}h")
"""The AD references (000Ch) and, right after them, the measured registers (0022h): signed,
the input minus the reference (spec 10.4). One read of ``AD_READINGS.size`` bytes."""


@dataclass(frozen=True, slots=True)
class AdReadings:
    """AD0-AD10 as the board holds them: ``references`` (000Ch) and ``measured`` (0022h,
    input - reference, signed); :attr:`inputs` what the pins see (measured + reference)."""

    references: tuple[int, ...]
    measured: tuple[int, ...]

    @property
    def inputs(self) -> tuple[int, ...]:
        return tuple((m + r) & 0xFFFF for m, r in zip(self.measured, self.references, strict=True))


def ad_readings(buf: ReadBuffer, at: int = ADDR.AD_REFERENCE) -> AdReadings:
    """The references and measured registers of AD0-AD10 from ``buf`` at ``at``."""
    v = AD_READINGS.unpack_from(buf, at)
    n = ADDR.AD_COUNT
    return AdReadings(v[:n], v[n:])


PIO_WORDS: Final = Struct("<HH")
"""PIO direction (1 = output) and data at 0038h."""
PIO_MASK: Final = 0x3FF


def ad_volts(ad0: int) -> float:
    """Supply voltage from the AD0 value: AD0 * 25 / 1024 volts."""
    return (ad0 & AD_MASK) * 25 / 1024
