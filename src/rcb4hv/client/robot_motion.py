"""The robot-level API's ROM program control: play, stop and resume motions through the host
sequences of :mod:`rcb4hv.protocol.sequences` (spec 11.4), and watch the program's state.

:class:`RobotMotions` is a mixin of :class:`~rcb4hv.client.Robot`.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterable

from rcb4hv.client.core import Rcb4Client
from rcb4hv.client.robot_types import MotionStatus
from rcb4hv.errors import Rcb4TimeoutError
from rcb4hv.protocol import Command
from rcb4hv.protocol import sequences as seq
from rcb4hv.protocol.memory import ADDR, RUN_STATE_SIZE, read_run_state, read_system
from rcb4hv.rom.layout import MotionLayout

__all__ = ["RobotMotions"]

log = logging.getLogger("rcb4hv.client.robot")


class RobotMotions:
    """Motions and the ROM program of the board behind ``self.client``, in ``self.layout``."""

    client: Rcb4Client

    @property
    def layout(self) -> MotionLayout:
        raise NotImplementedError

    def system_word(self) -> int:
        """The system register as its raw word (what :mod:`rcb4hv.protocol.sequences` takes)."""
        return read_system(self.client.read_ram(ADDR.SYSTEM, 2), 0)

    def send_sequence(self, commands: Iterable[Command]) -> None:
        """Send a host sequence (:mod:`rcb4hv.protocol.sequences`) command by command; each
        must be acknowledged (:class:`~rcb4hv.errors.NakError` otherwise)."""
        for cmd in commands:
            self.client.transact(cmd)

    # ------------------------------------------------------------------ motions

    def motion_status(self) -> MotionStatus:
        """PC, call depth and update flags (one frame), and the motion being played."""
        pc, depth, flags = read_run_state(self.client.read_ram(ADDR.PC, RUN_STATE_SIZE), 0)
        motion = self.layout.motion_at(pc)
        running = motion is not None and (depth != 0 or any(flags))
        return MotionStatus(pc, depth, flags, motion if running else None, running)

    def current_motion(self) -> int | None:
        """The motion (1-based) being played, or None."""
        return self.motion_status().motion

    def play_motion(self, motion: int, *, wait: bool = False, timeout: float = 60.0) -> None:
        """Play ``motion`` as HeartToHeart4 does (spec 11.4): suspend the ROM program, reset
        the PC to the main loop, CALL the motion, resume with ICS_F, ROM_F and VEC_F set."""
        address = self.layout.address(motion)
        self.send_sequence(seq.play_motion(self.system_word(), address, self.layout.main_loop))
        log.info("playing motion %d at %06X", motion, address)
        if wait:
            self.wait_motion(timeout=timeout)

    def stop_motion(self, *, reset: bool = True) -> None:
        """Stop the ROM program. With ``reset`` (default) the PC goes back to the main loop
        and the program runs on there (the board's idle state); without it the program is
        only paused (:meth:`resume_motion` continues it)."""
        word = self.system_word()
        self.send_sequence(seq.stop_program(word, self.layout.main_loop, reset=reset))

    def resume_motion(self) -> None:
        """Let the ROM program run again (sets ROM_F)."""
        self.send_sequence(seq.resume_program(self.system_word()))

    def wait_motion(
        self,
        *,
        timeout: float = 60.0,
        poll: float = 0.02,
        on_poll: Callable[[MotionStatus], None] | None = None,
    ) -> None:
        """Wait until no motion plays; Rcb4TimeoutError after ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while True:
            status = self.motion_status()
            if on_poll is not None:
                on_poll(status)
            if not status.running:
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(
                    f"motion {status.motion} still playing after {timeout:g} s (PC {status.pc:06X})"
                )
            time.sleep(poll)
