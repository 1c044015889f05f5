"""Play the motions of a ROM image in the emulator, in virtual time, the way a host does.

:class:`Simulator` boots an image in an emulated :class:`~rcb4hv.emulator.Board` on a
:class:`~rcb4hv.emulator.VirtualClock` and plays motions through :meth:`Board.feed` with real
command frames (spec 11.4): suspend (system register without ICS_F/ROM_F/VEC_F), reset the
program (PC = the main loop, depth 0, update flags 0), CALL the motion, resume (ICS_F, ROM_F,
VEC_F). The image's layout (main loop 044Bh or 003FDh, motion slots) is detected from it.
While a button is held for the motion (``hold``) VEC_F is left clear at the resume, so the
held button does not also fire the package bound to it at once; the main loop re-arms VEC_F
when it runs. Runs of motions (boot, then each motion, with or without physics) go through
the one run API, :func:`rcb4hv.project.run.run_motions`.

Each play ends in one of these states (:class:`MotionResult.status`):

``completed``
    The motion returned into the main loop (call depth 0, PC below 0B80h). ``duration`` is the
    virtual time from the resume to the return (resolution 1 ms when the motion ends with its
    own RETURN after a pose, else one output period).
``waiting``
    The program repeats itself exactly - the whole RAM, the call stack and the PC recur at
    the same point of the output-period cycle - and the repeating loop reads an input
    (remote buttons, PA1-PA4, AD channels, PIO, a servo's measured value): it waits for that
    input, as its own program defines. ``loop`` gives the loop's ROM address range, ``inputs``
    what it reads. A recurring state means the loop can never end while the inputs stay as
    they are.
``holding``
    The program repeats itself exactly without reading any input itself, but servos are
    mixed from an AD channel (mixing source in the AD values): the board holds a pose that
    the sensor corrects every output period (a gyro balancing a wheeled robot), as its
    program intends. ``inputs`` names the sensors (``AD1``).
``stalled``
    The program repeats itself exactly without reading any input (an endless loop, or update
    flags that never clear): it can never end.
``timeout``
    Still running without repeating itself: with an explicit ``limit``, after that many
    virtual seconds; by default (``limit=None``) after a :data:`PROGRESS_WINDOW` in which
    neither a servo nor a loop counter or variable changed, or after :data:`MAX_LIMIT` at
    most. A long counted loop that moves its servos is not a timeout: virtual time is cheap.
``error``
    The ROM program stopped (ROM_F cleared): ROMERR (a checksum error in a fetched
    instruction), a command error (unallocated ICS, RAM out of range, ...), a call-stack
    overflow (17th nested CALL) or underflow (RETURN on an empty stack). ``pc`` is the failing
    instruction's address and ``instruction`` its disassembly (the board leaves the PC on it).

A boot that stops (:meth:`Simulator.boot` with status ``error``) names its cause in words
(:func:`rcb4hv.project.instructions.boot_cause`, e.g. ``startup motion 0FB80h: slot 31 holds no
motion; ROMERR ...``); motions can still be played from the host afterwards, as spec 11.4 does.

The kind of error is the board's own record of why the program stopped
(:attr:`rcb4hv.emulator.Board.last_stop`), read in one place
(:func:`rcb4hv.project.instructions.stop_reason`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Iterable
from typing import Any, Final

from rcb4hv.asm import format_command
from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.errors import ProtocolError, SimulationError
from rcb4hv.project.image import button_names
from rcb4hv.project.instructions import boot_cause, input_names, instruction_at, stop_reason
from rcb4hv.project.simresult import MotionResult, Status
from rcb4hv.project.simwatch import Watch, mixed_sensors, progress_state
from rcb4hv.protocol import (
    Ack,
    Command,
    DataReply,
    Return,
    decode_reply,
    encode_command,
)
from rcb4hv.protocol import sequences as seq
from rcb4hv.protocol.memory import (
    ADDR,
    SYS,
    read_system,
    read_u16,
    read_update_flags,
)
from rcb4hv.rom import layout
from rcb4hv.rom.calibration import image_servos
from rcb4hv.rom.layout import MotionLayout
from rcb4hv.rom.older import play_layout

__all__ = [
    "DEFAULT_LIMIT",
    "MAX_LIMIT",
    "PROGRESS_WINDOW",
    "MotionResult",
    "SampleListener",
    "Simulator",
    "Status",
]

log = logging.getLogger(__name__)

SampleListener = Callable[[float, dict[int, int]], None]

DEFAULT_LIMIT: Final = 60.0
"""Virtual seconds of an explicit limit's traditional default (``--limit 60``)."""
PROGRESS_WINDOW: Final = 60.0
"""Without a limit: virtual seconds a motion may run without any progress (no servo, loop
counter or variable changed between two looks this far apart) before it is a ``timeout``.
A pose lasts at most 255 output periods of at most 25 ms (6.4 s: spec 9 and the system
register's period choice), so a motion that makes progress changes something in any 60 s."""
MAX_LIMIT: Final = 3600.0
"""Without a limit: virtual seconds a motion that keeps making progress may run at most (an
hour: far past any motion played from a remote, and cheap, since waits are skipped in bulk)."""

STEP_US: Final = 2000
"""Virtual microseconds per step while the program executes instructions (waits on update
flags are stepped exactly). 2 ms is below the shortest output period (10 ms), so a reported
duration is within one step of the board's; 1 ms steps made simulation ~20% slower."""
BOOT_LIMIT: Final = 30.0
TIMER_US: Final = 100_000


class Simulator:
    """An emulated board on a virtual clock, booted from ``image``.

    ``ics`` lists the ICS numbers that get a virtual servo (default: every allocated slot of
    the image's allocation table). ``listener`` is called with ``(virtual time, {ics: sent
    value})`` after every output period (this slows the emulator down: it then steps every
    period instead of skipping the ones nobody observes).
    """

    def __init__(
        self,
        image: bytes,
        *,
        ics: Iterable[int] | None = None,
        config: EmulatorConfig | None = None,
        listener: SampleListener | None = None,
        motion_layout: MotionLayout | None = None,
    ) -> None:
        if len(image) != layout.ROM_SIZE:
            raise ValueError(f"a ROM image is {layout.ROM_SIZE} bytes, not {len(image)}")
        self.layout = play_layout(image, motion_layout)
        if ics is None:
            ics = image_servos(image)
        if config is None:
            config = EmulatorConfig(virtual_servos=tuple(ics))
        self.clock = VirtualClock()
        self._t_us = 0
        self.board = Board(config, clock=self.clock, rom_image=image)
        self.board.sensors_at_rest()  # a still robot's calibrated sensors read their reference
        if listener is not None:
            self.board.add_output_listener(listener)
        self.boot_result: MotionResult | None = None
        self._stop_before = self.board.last_stop

    # ------------------------------------------------------------------ host side

    def _send(self, cmd: Command) -> bytes:
        reply = self.board.feed(encode_command(cmd))
        if not reply:
            raise SimulationError(f"no reply to {format_command(cmd)}")
        try:
            r = decode_reply(reply, cmd)
        except ProtocolError as exc:
            raise SimulationError(f"bad reply to {format_command(cmd)}: {exc}") from exc
        if isinstance(r, Ack):
            return b""
        if isinstance(r, DataReply):
            return r.data
        raise SimulationError(f"board refused {format_command(cmd)}: {r!r}")

    def _system_word(self) -> int:
        return read_system(self._send(seq.system_query()), 0)

    def start_motion(self, address: int, *, vector: bool = True) -> None:
        """Play the motion at ``address`` as a host does (spec 11.4), through real frames
        (:func:`rcb4hv.protocol.sequences.play_motion`; ROMERR is cleared, so a play after a
        failed one starts clean)."""
        word = self._system_word()
        main = self.layout.main_loop
        for cmd in seq.play_motion(word, address, main, vector=vector, clear_rom_error=True):
            self._send(cmd)

    # ------------------------------------------------------------------ board state

    @property
    def now(self) -> float:
        """Virtual seconds since power-on."""
        return self._t_us / 1e6

    def run_us(self, dt_us: int) -> None:
        """Advance the virtual clock by ``dt_us`` whole microseconds (at least one; no float
        drift) and let the board catch up: the program runs, the servos move."""
        self._t_us += max(1, dt_us)
        # a quarter microsecond above the target: the board truncates to whole microseconds
        self.clock.set((self._t_us + 0.25) / 1e6)
        self.board.tick()

    def _period_us(self) -> int:
        return round(self.board.output_period * 1e6)

    def _flags(self) -> int:
        return read_update_flags(self.board.ram)

    def _depth(self) -> int:
        return self.board.ram[ADDR.CALL_DEPTH]

    def _wait_periods(self) -> int | None:
        """Output periods the program will wait at least (None: flags that never clear): the
        board's own count (:meth:`~rcb4hv.emulator.Board.update_flag_wait`) less the period
        that clears the last flag."""
        k = self.board.update_flag_wait()
        return None if k is None else max(0, k - 1)

    def _instruction_at(self, pc: int) -> tuple[Command | None, str]:
        return instruction_at(self.board.rom, pc)

    def _error(self) -> tuple[str, int, str]:
        """(kind, PC, disassembly) of the instruction that stopped the program, from the
        board's own record since the play began (:func:`stop_reason`)."""
        return stop_reason(self.board, self._stop_before)

    # ------------------------------------------------------------------ running

    def boot(self, limit: float = BOOT_LIMIT) -> MotionResult:
        """Run from power-on until the program idles in the main loop (startup motion done)."""
        b = self.board
        t0, i0 = self._t_us, b.instructions_executed
        seen_main = False
        limit_us = round(limit * 1e6)
        while True:
            dur = (self._t_us - t0) / 1e6
            n = b.instructions_executed - i0
            if not b.system_register & SYS.ROM_RUN:
                kind, pc, text = self._error()
                cause = boot_cause(b.rom, kind, pc)
                res = MotionResult(None, 0, "boot", "error", dur, n, cause, pc, text)
                break
            pc = b.pc
            in_main = self.layout.main_loop <= pc < self.layout.main_loop_end and not self._depth()
            if in_main and seen_main:
                res = MotionResult(None, 0, "boot", "completed", dur, n)
                break
            seen_main = seen_main or in_main
            if self._t_us - t0 >= limit_us:
                res = MotionResult(None, 0, "boot", "timeout", dur, n, pc=pc)
                break
            self._advance(precise=False, cap_us=limit_us - (self._t_us - t0))
        self.boot_result = res
        log.info("boot: %s after %.3f s", res.status, res.duration)
        return res

    def _advance(self, precise: bool, cap_us: int) -> None:
        """One step: a bulk wait while update flags hold the program, else :data:`STEP_US`.

        A bulk wait is ``n + 1`` output periods (the program may run up to one period past the
        end of the wait), or ``n`` periods and then single steps when ``precise``.
        """
        b = self.board
        dt = STEP_US
        sysw = b.system_register
        if not sysw & SYS.ROM_RUN:
            dt = 1_000_000
        elif self._flags():
            n = self._wait_periods()
            period = self._period_us()
            if n is None:
                dt = 1_000_000
            elif precise:
                dt = max(STEP_US, n * period)
            else:
                dt = (n + 1) * period
        self.run_us(min(dt, max(1, cap_us)))

    def _ends_after_wait(self) -> bool:
        """True if the instruction the program waits to fetch returns into the main loop."""
        b = self.board
        if self._depth() != 1:
            return False
        cmd, _ = self._instruction_at(b.pc)
        return isinstance(cmd, Return) and b.call_stack[0] < self.layout.motion_base

    def play(
        self,
        address: int,
        *,
        slot: int | None = None,
        name: str = "",
        hold: int = 0,
        hold_for: float = 0.0,
        limit: float | None = None,
    ) -> MotionResult:
        """Play the motion at ``address``; hold button word ``hold`` for ``hold_for`` seconds.
        ``limit``: virtual seconds before a timeout (None: while it makes progress, see
        :data:`PROGRESS_WINDOW` and :data:`MAX_LIMIT`)."""
        if limit is not None and not limit > 0:
            raise ValueError("limit must be > 0")
        if not 0 <= hold <= 0xFFFF:
            raise ValueError("the button word is 16 bits")
        if hold and hold_for < 0:
            raise ValueError("hold_for must be >= 0")
        if not 0 <= address < layout.ROM_SIZE:
            raise ValueError(f"ROM address {address:#x} out of range")
        b = self.board
        if slot is None:
            slot = self.layout.motion_at(address)
        self.start_motion(address, vector=not hold)
        self._stop_before = b.last_stop  # the host's own suspend, not the motion's stop
        t0, i0 = self._t_us, b.instructions_executed
        held = None
        if hold:
            b.set_buttons(hold)
            held = f"{button_names(hold)} for {hold_for:g} s"

        def result(
            status: Status, at_us: int | None = None, at_n: int | None = None, **kw: Any
        ) -> MotionResult:
            t = (self._t_us if at_us is None else at_us) - t0
            n = (b.instructions_executed if at_n is None else at_n) - i0
            return MotionResult(slot, address, name, status, t / 1e6, n, held=held, **kw)

        hold_us = round(hold_for * 1e6) if hold else None
        try:
            if limit is not None:
                return self._run(result, t0, hold_us, round(limit * 1e6), None)
            window = round(PROGRESS_WINDOW * 1e6)
            return self._run(result, t0, hold_us, round(MAX_LIMIT * 1e6), window)
        finally:
            if read_u16(b.ram, ADDR.BUTTONS):
                b.set_buttons(0)

    def _run(
        self,
        result: Callable[..., MotionResult],
        t0: int,
        hold_us: int | None,
        limit_us: int,
        window_us: int | None,
    ) -> MotionResult:
        """Run until the motion ends; ``window_us``: a timeout also after that long without
        progress (None: ``limit_us`` only)."""
        b = self.board
        watch: Watch | None = None
        look_us = window_us  # elapsed time of the next progress look
        state = progress_state(b)
        while True:
            elapsed = self._t_us - t0
            if hold_us is not None and elapsed >= hold_us:
                b.set_buttons(0)
                hold_us = None
            sysw = b.system_register
            if not sysw & SYS.ROM_RUN:
                kind, pc, text = self._error()
                return result("error", error=kind, pc=pc, instruction=text)
            pc = b.pc
            if self._depth() == 0 and pc < self.layout.motion_base:
                return result("completed")
            if elapsed >= limit_us:
                return result("timeout", pc=pc)
            if look_us is not None and window_us is not None and elapsed >= look_us:
                now_state = progress_state(b)
                if now_state == state:
                    return result("timeout", pc=pc, error="no progress")
                state, look_us = now_state, look_us + window_us
            cap = limit_us - elapsed if look_us is None else min(limit_us, look_us) - elapsed
            if hold_us is not None:
                cap = min(cap, hold_us - elapsed)
            else:
                grid = math.lcm(self._period_us(), TIMER_US)
                if watch is None or watch.grid_us != grid:
                    watch = Watch(self._t_us, grid)
                first = watch.check(b, self._t_us)
                if first is not None:
                    return self._classify(result, first, self._t_us - first[0])
                cap = min(cap, watch.next_look(self._t_us) or grid)
            precise = bool(self._flags()) and self._ends_after_wait()
            self._advance(precise, cap)

    def _classify(
        self, result: Callable[..., MotionResult], entered: tuple[int, int], cycle_us: int
    ) -> MotionResult:
        """Replay one cycle of a recurring state instruction by instruction; say what it reads.
        ``entered``: the time and instruction count at which the state first recurred from,
        which the result reports (both at the same moment)."""
        entered_us, entered_n = entered
        b = self.board
        end = self._t_us + cycle_us
        pcs: dict[int, int] = {}
        # half an instruction per step: never two instructions between two looks at the PC
        half = max(1, round(500 / b.config.instructions_per_ms))
        while self._t_us < end:
            if not b.system_register & SYS.ROM_RUN:
                break
            if self._flags():
                n = self._wait_periods()
                if n is None:
                    self.run_us(end - self._t_us)
                    break
                self.run_us(min(end - self._t_us, max(half, n * self._period_us())))
                while self._flags() and self._t_us < end:
                    self.run_us(min(end - self._t_us, half))
                continue
            pc = b.pc
            pcs[pc] = b.rom[pc]
            self.run_us(min(end - self._t_us, half))
        inputs: list[str] = []
        for pc in sorted(pcs):
            cmd, _ = self._instruction_at(pc)
            if cmd is not None:
                for name in input_names(cmd):
                    if name not in inputs:
                        inputs.append(name)
        loop = (min(pcs), max(a + n - 1 for a, n in pcs.items())) if pcs else None
        if inputs:
            return result(
                "waiting", entered_us, entered_n, loop=loop, inputs=tuple(inputs), pc=b.pc
            )
        sensors = mixed_sensors(b)
        if sensors and pcs:
            return result("holding", entered_us, entered_n, loop=loop, inputs=sensors, pc=b.pc)
        why = "endless loop" if pcs else "update flags that never clear"
        return result("stalled", entered_us, entered_n, loop=loop, error=why, pc=b.pc)
