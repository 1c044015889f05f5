"""Single-stepping a motion in the emulator, one instruction at a time (virtual time).

:class:`MotionStepper` boots a project's ROM image on the emulated board
(:class:`~rcb4hv.project.simulate.Simulator`), starts a motion as a host does and then runs
it one instruction per :meth:`~MotionStepper.step`: the virtual clock advances by one
instruction's time (the board's ``instructions_per_ms``) at a time until an instruction has
run (while servos still move, the update flags hold the program that long). Each step returns
where the program counter is, so an editor can highlight the block being run.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rcb4hv.project.simulate import Simulator
from rcb4hv.protocol import SYS

__all__ = ["MotionStepper", "Step"]

MAX_STEP_S = 30.0
"""The longest one step may take in virtual time (a wait on a stopped timer never ends)."""


@dataclass(frozen=True)
class Step:
    """Where a step left the program: ``pc``, ``done`` (back in the main loop), ``error``
    (the board stopped the program: its reason), the virtual time and instructions run."""

    pc: int
    done: bool
    error: str | None
    time: float
    instructions: int


class MotionStepper(Simulator):
    """A simulator that runs one motion an instruction at a time."""

    _count = 0

    def begin(self, address: int) -> Step:
        """Boot (once) and start the motion at ROM ``address``."""
        if self.boot_result is None:
            self.boot()
        self.start_motion(address)
        self._count = self.board.instructions_executed
        return self._where()

    def _where(self) -> Step:
        b = self.board
        error = None
        if not b.system_register & SYS.ROM_RUN:
            kind, _, text = self._error()
            error = f"{kind}: {text}"
        done = error is None and self._depth() == 0 and b.pc < self.layout.motion_base
        n = b.instructions_executed - self._count
        return Step(b.pc, done, error, self.now, n)

    def step(self) -> Step:
        """Run one instruction (waiting for moving servos first); the new position."""
        b = self.board
        start = b.instructions_executed
        one_us = max(1, math.ceil(1000 / b.config.instructions_per_ms))
        limit_us = round(MAX_STEP_S * 1e6)
        spent = 0
        while b.instructions_executed == start and spent < limit_us:
            here = self._where()
            if here.done or here.error is not None:
                return here
            before = self._t_us
            self.run_us(one_us)
            spent += self._t_us - before
        return self._where()
