"""The four 100 ms count-down timers (RAM 003Ch-0043h, spec 10.1).

A timer word counts down by one every 100 ms while bit 15 is clear; reaching 0 it becomes
8000h (stopped, bit 15 set). A stopped timer (bit 15 set) is left alone.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.emulator.memmap import FREE, TIMERS

__all__ = ["TIMER_PERIOD_US", "reset_timers", "tick_timers", "timers_idle"]

TIMER_PERIOD_US: Final = 100_000
STOPPED: Final = 0x8000
_HI: Final = tuple(a + 1 for a in TIMERS)


def reset_timers(ram: bytearray) -> None:
    """Power-on: every timer stopped."""
    for a in TIMERS:
        ram[a] = FREE & 0xFF
        ram[a + 1] = FREE >> 8


def timers_idle(ram: bytearray) -> bool:
    """True when all four timers are stopped (nothing changes on a timer tick)."""
    h0, h1, h2, h3 = _HI
    return bool(ram[h0] & ram[h1] & ram[h2] & ram[h3] & 0x80)


def tick_timers(ram: bytearray) -> None:
    """One 100 ms tick."""
    for a in TIMERS:
        v = ram[a] | ram[a + 1] << 8
        if v & STOPPED:
            continue
        v = (v - 1) & 0x7FFF if v else 0
        if v == 0:
            v = STOPPED
        ram[a] = v & 0xFF
        ram[a + 1] = v >> 8
