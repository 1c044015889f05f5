"""The four 100 ms count-down timers (RAM 003Ch-0043h, spec 10.1).

A timer word counts down by one every 100 ms while its stop bit (bit 15) is clear; reaching
0 it becomes 8000h (stopped). A stopped timer is left alone.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.emulator.memmap import TIMER_BASE, TIMER_STOPPED, TIMERS

__all__ = ["TIMER_PERIOD_US", "reset_timers", "tick_timers", "timers_idle"]

TIMER_PERIOD_US: Final = 100_000
_COUNT: Final = 0x7FFF
_unpack = TIMERS.unpack_from
_pack = TIMERS.pack_into


def reset_timers(ram: bytearray) -> None:
    """Power-on: every timer stopped."""
    _pack(ram, TIMER_BASE, TIMER_STOPPED, TIMER_STOPPED, TIMER_STOPPED, TIMER_STOPPED)


def timers_idle(ram: bytearray) -> bool:
    """True when all four timers are stopped (nothing changes on a timer tick)."""
    t0, t1, t2, t3 = _unpack(ram, TIMER_BASE)
    return bool(t0 & t1 & t2 & t3 & TIMER_STOPPED)


def _tick(v: int) -> int:
    if v & TIMER_STOPPED:
        return v
    v = (v - 1) & _COUNT if v else 0
    return v if v else TIMER_STOPPED


def tick_timers(ram: bytearray) -> None:
    """One 100 ms tick."""
    t0, t1, t2, t3 = _unpack(ram, TIMER_BASE)
    _pack(ram, TIMER_BASE, _tick(t0), _tick(t1), _tick(t2), _tick(t3))
