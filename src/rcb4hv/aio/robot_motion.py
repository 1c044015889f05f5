"""The robot-level API's ROM program control: the board's HeartToHeart4 layout, play, stop
and resume motions through the host sequences of :mod:`rcb4hv.protocol.sequences` (spec
11.4), and watch the program's state.

:class:`AsyncRobotMotions` is a mixin of :class:`~rcb4hv.aio.AsyncRobot`. One source, two
faces: ``tools/unasync.py`` writes ``src/rcb4hv/client/robot_motion.py`` (blocking) from
``src/rcb4hv/aio/robot_motion.py`` (asyncio).
"""

from __future__ import annotations

import logging
import time
from asyncio import sleep
from collections.abc import Callable, Iterable
from dataclasses import replace

from rcb4hv.aio.client import AsyncRcb4Client
from rcb4hv.client.args import check_wait, integer
from rcb4hv.client.robot_types import MotionStatus
from rcb4hv.errors import NakError, ProgramStoppedError, Rcb4TimeoutError
from rcb4hv.protocol import Command
from rcb4hv.protocol import sequences as seq
from rcb4hv.protocol.memory import ADDR, RUN_STATE_SIZE, read_run_state, read_system
from rcb4hv.rom.layout import HTH4_22, OLDER_MAIN_LOOP, MotionLayout
from rcb4hv.rom.older import main_loop_layout

__all__ = ["AsyncRobotMotions"]

log = logging.getLogger(__name__)


class AsyncRobotMotions:
    """Motions and the ROM program of the board behind ``self.client``, in ``self.layout``."""

    client: AsyncRcb4Client
    layout: MotionLayout | None
    """The board's HeartToHeart4 layout; None until :meth:`board_layout` reads it."""

    async def board_layout(self) -> MotionLayout:
        """The board's HeartToHeart4 layout: :attr:`layout` if set, else the one whose main
        loop the board's ROM holds, else 2.2 (kept in :attr:`layout`).

        Two 9-byte ROM reads are enough: every HeartToHeart4 main loop starts with a
        system-register write, at 0044Bh in a 2.2 image and at 003FDh in the older ones
        (:func:`rcb4hv.rom.older.main_loop_layout`). 1.3 and 2.0/2.1 share the older main loop
        and differ only in the motion stride, which the boot region does not show: an older
        board is taken as 2.1 (give ``layout=LAYOUTS["1.3"]`` for a 1.3 board)."""
        if self.layout is None:
            try:
                older = await self.client.read_rom(OLDER_MAIN_LOOP, 9)
                newer = await self.client.read_rom(HTH4_22.main_loop, 9)
            except NakError:
                found = None
            else:
                found = main_loop_layout(older, newer)
            self.layout = found or HTH4_22
        return self.layout

    async def system_word(self) -> int:
        """The system register as its raw word (what :mod:`rcb4hv.protocol.sequences` takes)."""
        return read_system(await self.client.read_ram(ADDR.SYSTEM, 2), 0)

    async def send_sequence(self, commands: Iterable[Command]) -> None:
        """Send a host sequence (:mod:`rcb4hv.protocol.sequences`) command by command; each
        must be acknowledged (:class:`~rcb4hv.errors.NakError` otherwise)."""
        for cmd in commands:
            await self.client.transact(cmd)

    # ------------------------------------------------------------------ motions

    async def motion_status(self) -> MotionStatus:
        """The system register, PC, call depth and update flags (one frame), the motion the
        program is in and whether it is being played (also while a host pauses it; not once
        a ROM error stopped it)."""
        raw = await self.client.read_ram(ADDR.SYSTEM, ADDR.PC - ADDR.SYSTEM + RUN_STATE_SIZE)
        system = read_system(raw, 0)
        pc, depth, flags = read_run_state(raw, ADDR.PC - ADDR.SYSTEM)
        motion = (await self.board_layout()).motion_at(pc)
        if motion is not None and depth == 0 and not any(flags):
            motion = None  # the PC rests in a motion's slot outside any call
        status = MotionStatus(pc, depth, flags, motion, False, system)
        return replace(status, running=motion is not None and not status.rom_error)

    async def current_motion(self) -> int | None:
        """The motion (1-based) being played or paused, or None (also when a ROM error stopped
        the program in a motion: :meth:`motion_status` tells that)."""
        status = await self.motion_status()
        return status.motion if status.running else None

    async def play_motion(self, motion: int, *, wait: bool = False, timeout: float = 60.0) -> None:
        """Play ``motion`` as HeartToHeart4 does (spec 11.4): suspend the ROM program, reset
        the PC to the main loop, CALL the motion, resume with ICS_F, ROM_F and VEC_F set.
        With ``wait``, ``timeout`` must be a finite number of seconds > 0 (checked before the
        motion starts)."""
        if wait:
            check_wait(timeout)
        motion = integer("motion", motion)
        lay = await self.board_layout()
        address = lay.address(motion)
        await self.send_sequence(seq.play_motion(await self.system_word(), address, lay.main_loop))
        log.info("playing motion %d at %06X", motion, address)
        if wait:
            await self.wait_motion(timeout=timeout)

    async def stop_motion(self, *, reset: bool = True) -> None:
        """Stop the ROM program. With ``reset`` (default) the PC goes back to the main loop
        and the program runs on there (the board's idle state); without it the program is
        only paused (:meth:`resume_motion` continues it)."""
        main_loop = (await self.board_layout()).main_loop
        word = await self.system_word()
        await self.send_sequence(seq.stop_program(word, main_loop, reset=reset))

    async def resume_motion(self) -> None:
        """Let the ROM program run again (sets ROM_F)."""
        await self.send_sequence(seq.resume_program(await self.system_word()))

    async def wait_motion(
        self,
        *,
        timeout: float = 60.0,
        poll: float = 0.02,
        on_poll: Callable[[MotionStatus], None] | None = None,
    ) -> None:
        """Wait until no motion plays (a paused one is still waited for);
        :class:`~rcb4hv.errors.ProgramStoppedError` at once when the program stops with a ROM
        error (a motion slot that holds no motion), Rcb4TimeoutError after ``timeout``
        seconds (a finite number > 0; ``poll`` one >= 0)."""
        check_wait(timeout, poll)
        deadline = time.monotonic() + timeout
        while True:
            status = await self.motion_status()
            if on_poll is not None:
                on_poll(status)
            if status.rom_error:
                where = "" if status.motion is None else f"motion {status.motion}: "
                raise ProgramStoppedError(
                    f"{where}the board's program stopped with a ROM error at PC "
                    f"{status.pc:06X} (an instruction it cannot execute; a slot with no "
                    "motion in it stops it so)",
                    status.pc,
                    status.motion,
                )
            if not status.running:
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(
                    f"motion {status.motion} still {status.state} after {timeout:g} s "
                    f"(PC {status.pc:06X})"
                )
            await sleep(poll)
