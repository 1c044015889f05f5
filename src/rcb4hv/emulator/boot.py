"""Start a board "switched on a while ago": its start-up program runs in virtual time, then the
clock goes on in real time from there (``rcb4emu://`` and ``rcb4hv emulate`` do this unless
asked for a live boot)."""

from __future__ import annotations

import math
import time

from rcb4hv.emulator.board import Board
from rcb4hv.emulator.clock import ScaledClock
from rcb4hv.errors import ArgumentError
from rcb4hv.protocol.memory import ProgramState
from rcb4hv.rom.layout import HTH4_22, MotionLayout
from rcb4hv.rom.older import play_layout

__all__ = ["BOOT_LIMIT_S", "BootClock", "boot_to_main_loop", "booted"]

BOOT_LIMIT_S = 30.0
"""Board seconds a ``boot=ready`` open lets the start-up program run before giving up."""


class BootClock(ScaledClock):
    """Virtual time while the board boots (``advance``), then real time times ``speed``,
    continuing from where the boot left off (``go_real``)."""

    def __init__(self, speed: float) -> None:
        if not 0 < speed < math.inf:
            raise ArgumentError(f"speed must be a finite number > 0, not {speed!r}")
        self.speed = speed
        self._virtual: float | None = 0.0
        self._base = 0.0
        self._t0 = 0.0

    def now(self) -> float:
        if self._virtual is not None:
            return self._virtual
        return self._base + (time.monotonic() - self._t0) * self.speed

    def advance(self, seconds: float) -> None:
        assert self._virtual is not None
        self._virtual += seconds

    def go_real(self) -> None:
        if self._virtual is not None:
            self._base, self._virtual, self._t0 = self._virtual, None, time.monotonic()


def booted(ram: bytes | bytearray, layout: MotionLayout = HTH4_22) -> bool:
    """The ROM program is stopped, or in ``layout``'s main loop with an empty call stack (the
    test :meth:`rcb4hv.client.Robot.wait_ready` makes on the wire)."""
    state = ProgramState.unpack(ram)
    return not state.running or (
        layout.main_loop <= state.pc < layout.motion_base and state.call_depth == 0
    )


def boot_to_main_loop(
    board: Board, clock: BootClock, layout: MotionLayout | None = None, step: float = 0.05
) -> None:
    """Run ``board``'s start-up program in virtual time until it reaches the main loop of
    ``layout`` (default: the layout the ROM image holds, else HeartToHeart4 2.2)."""
    lay = play_layout(board.rom, layout)
    t = 0.0
    while not booted(board.ram, lay) and t < BOOT_LIMIT_S:
        clock.advance(step)
        board.tick()
        t += step
