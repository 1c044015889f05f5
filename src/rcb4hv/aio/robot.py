"""The common robot-level calls of :class:`rcb4hv.client.Robot` for asyncio code.

Results, units and errors are those of the blocking :class:`~rcb4hv.client.Robot` (its value
types, :func:`~rcb4hv.client.plan_reads`, calibration and range check are reused); waits are
``asyncio.sleep`` polls bounded by their ``timeout``. For anything not here, run the blocking
Robot in a thread (``asyncio.to_thread``) or use :attr:`AsyncRobot.client` directly.
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Iterable, Mapping
from types import TracebackType
from typing import Literal

from rcb4hv.aio.client import AsyncRcb4Client
from rcb4hv.client.core import DEFAULT_TIMEOUT
from rcb4hv.client.robot import (
    MAX_SPEED,
    SERVO_LIMIT,
    Calibration,
    MotionStatus,
    Robot,
    ServoInfo,
    plan_reads,
)
from rcb4hv.errors import NakError, Rcb4TimeoutError
from rcb4hv.protocol import (
    ADDR,
    POSITION_FREE,
    POSITION_HOLD,
    RAM_SIZE,
    SERVO,
    Button,
    Command,
    ServoBlock,
    SystemRegister,
)
from rcb4hv.protocol import sequences as seq
from rcb4hv.protocol.memory import (
    RUN_STATE_SIZE,
    SYS,
    U16_BE,
    ad_volts,
    read_buttons,
    read_pc,
    read_run_state,
    read_s16,
    read_system,
    read_u16,
    u16_bytes,
    unpack_alloc,
)
from rcb4hv.rom.layout import HTH4_22, OLDER_MAIN_LOOP, MotionLayout
from rcb4hv.rom.older import main_loop_layout
from rcb4hv.transport import DEFAULT_BAUD

__all__ = ["AsyncRobot"]

log = logging.getLogger(__name__)

_NO_CAL = Calibration()


class AsyncRobot:
    """``async with await AsyncRobot.open("rcb4emu://") as robot: await robot.positions()``"""

    def __init__(
        self,
        client: AsyncRcb4Client,
        *,
        layout: MotionLayout | None = None,
        calibration: Mapping[int, Calibration] | None = None,
    ) -> None:
        self.client = client
        self.layout = layout
        """The HeartToHeart4 layout; None: read from the board's ROM on first use."""
        self.calibration: dict[int, Calibration] = dict(calibration or {})
        self._servos: dict[int, ServoInfo] | None = None
        self._period: float | None = None

    @classmethod
    async def open(
        cls,
        url: str | None = None,
        *,
        baudrate: int | None = DEFAULT_BAUD,
        timeout: float = DEFAULT_TIMEOUT,
        layout: MotionLayout | None = None,
        calibration: Mapping[int, Calibration] | None = None,
    ) -> AsyncRobot:
        """Open ``url`` (see :meth:`AsyncRcb4Client.open`) and wrap it."""
        client = await AsyncRcb4Client.open(url, baudrate=baudrate, timeout=timeout)
        return cls(client, layout=layout, calibration=calibration)

    async def close(self) -> None:
        await self.client.close()

    async def __aenter__(self) -> AsyncRobot:
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.close()

    # ------------------------------------------------------------------ board

    async def ping(self) -> float:
        """Round-trip time of one ACK check, in seconds."""
        t0 = time.perf_counter()
        await self.client.acknowledge_check()
        return time.perf_counter() - t0

    async def version(self) -> str:
        return (await self.client.get_version_info()).text

    async def board_layout(self) -> MotionLayout:
        """The layout given, else the one the board's ROM holds (two 9-byte reads, as
        :func:`rcb4hv.client.layout.detect_board_layout`), else HeartToHeart4 2.2."""
        if self.layout is None:
            try:
                older = await self.client.read_rom(OLDER_MAIN_LOOP, 9)
                newer = await self.client.read_rom(HTH4_22.main_loop, 9)
                self.layout = main_loop_layout(older, newer) or HTH4_22
            except NakError:
                self.layout = HTH4_22
        return self.layout

    async def system_register(self) -> SystemRegister:
        return SystemRegister.from_bytes(await self.client.read_ram(ADDR.SYSTEM, 2))

    async def system_word(self) -> int:
        """The system register as its raw word (what :mod:`rcb4hv.protocol.sequences` takes)."""
        return read_system(await self.client.read_ram(ADDR.SYSTEM, 2), 0)

    async def send_sequence(self, commands: Iterable[Command]) -> None:
        """Send a host sequence (:mod:`rcb4hv.protocol.sequences`) command by command; each
        must be acknowledged (:class:`~rcb4hv.errors.NakError` otherwise)."""
        for cmd in commands:
            await self.client.transact(cmd)

    async def output_period(self) -> float:
        """Servo output period in seconds (system register bits 5-4), cached."""
        if self._period is None:
            self._period = (await self.system_register()).frame_period_ms / 1000.0
        return self._period

    async def frames_for(self, duration: float) -> int:
        """Servo speed (output periods) for a move lasting ``duration`` seconds."""
        if duration < 0:
            raise ValueError("duration must be >= 0")
        period = await self.output_period()
        frames = max(1, round(duration / period))
        if frames > MAX_SPEED:
            raise ValueError(
                f"{duration:g} s is {frames} output periods of {period * 1000:g} ms; "
                f"the most one move can last is {MAX_SPEED} periods ({MAX_SPEED * period:g} s)"
            )
        return frames

    async def wait_ready(self, timeout: float = 5.0, poll: float = 0.02) -> None:
        """Wait until the ROM program is in its main loop (see :meth:`Robot.wait_ready`)."""
        deadline = time.monotonic() + timeout
        lay = await self.board_layout()
        while True:
            head = await self.client.read_ram(ADDR.SYSTEM, ADDR.CALL_DEPTH + 1)
            word, pc, depth = read_system(head), read_pc(head), head[ADDR.CALL_DEPTH]
            if not word & SYS.ROM_RUN or (lay.main_loop <= pc < lay.motion_base and depth == 0):
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(
                    f"ROM program not in its main loop after {timeout:g} s (PC {pc:06X})"
                )
            await asyncio.sleep(poll)

    # ------------------------------------------------------------------ servos

    async def allocation_table(self) -> list[int | None]:
        """``alloc[0..35]``: the RAM address of each ICS number's block, or None."""
        raw = await self.client.read_ram(ADDR.ICS_ALLOC, 2 * ADDR.ICS_ALLOC_COUNT)
        return unpack_alloc(raw, 0)

    async def discover_servos(self) -> list[ServoInfo]:
        """Servos from the allocation table (see :meth:`Robot.discover_servos`)."""
        table = await self.allocation_table()
        blocks = {
            k: a
            for k, a in enumerate(table)
            if a is not None and k < SERVO_LIMIT and ADDR.USER <= a <= RAM_SIZE - ServoBlock.SIZE
        }
        data = await self._read_spans({k: (a, ServoBlock.SIZE) for k, a in blocks.items()})
        servos = {}
        for k, a in blocks.items():
            block = ServoBlock.from_bytes(data[k])
            if block.type == 0:
                servos[k] = ServoInfo(k, a, block)
        self._servos = servos
        return [servos[k] for k in sorted(servos)]

    async def _known(self) -> dict[int, ServoInfo]:
        if self._servos is None:
            await self.discover_servos()
        assert self._servos is not None
        return self._servos

    async def servo_ids(self) -> list[int]:
        """ICS numbers of the known servos (discovers them on first use)."""
        return sorted(await self._known())

    async def _select(self, ics: Iterable[int] | None) -> list[int]:
        known = await self._known()
        if ics is None:
            return sorted(known)
        out = sorted(set(ics))
        missing = [k for k in out if k not in known]
        if missing:
            raise ValueError(f"no servo at ICS {missing} (known: {sorted(known)})")
        return out

    async def _read_spans(self, spans: Mapping[int, tuple[int, int]]) -> dict[int, bytes]:
        reads = plan_reads(spans.values())
        if not reads:
            return dict.fromkeys(spans, b"")
        lo = reads[0][0]
        window = bytearray(reads[-1][0] + reads[-1][1] - lo)
        for a, n in reads:
            window[a - lo : a - lo + n] = await self.client.read_ram(a, n)
        return {key: bytes(window[a - lo : a - lo + n]) for key, (a, n) in spans.items()}

    async def _read_field(self, ics: list[int], offset: int, size: int) -> dict[int, bytes]:
        known = await self._known()
        return await self._read_spans({k: (known[k].block_address + offset, size) for k in ics})

    async def positions(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> dict[int, int]:
        """Raw positions by ICS number: ``measured`` (+4) or commanded ``output`` (+6)."""
        offset = SERVO.MEASURED if kind == "measured" else SERVO.OUTPUT
        sel = await self._select(ics)
        raw = await self._read_field(sel, offset, 2)
        return {k: read_u16(raw[k], 0) for k in sel}

    async def angles(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> dict[int, float]:
        """Angles in degrees (with the host calibration). Free/hold markers read as NaN."""
        out = {}
        for k, p in (await self.positions(ics, kind)).items():
            special = p in (POSITION_FREE, POSITION_HOLD) or (p == 0 and kind == "output")
            cal = self.calibration.get(k, _NO_CAL)
            out[k] = float("nan") if special else cal.to_degrees(p)
        return out

    async def move(
        self,
        positions: Mapping[int, int],
        duration: float = 0.0,
        *,
        wait: bool = False,
        timeout: float | None = None,
        check_range: bool = True,
    ) -> None:
        """Move servos (ICS number -> raw position) linearly over ``duration`` seconds."""
        if not positions:
            raise ValueError("no servo to move")
        for k, p in positions.items():
            if check_range:
                Robot.check_position(k, p)
            elif not 0 <= p <= 0xFFFF:
                raise ValueError(f"ICS {k}: position {p} is not 16 bits")
        speed = await self.frames_for(duration)
        await self.client.run_const_frame_servo(speed, dict(positions))
        if wait:
            limit = duration + 1.0 if timeout is None else timeout
            await self.wait_interpolation(positions, timeout=limit)

    async def move_angles(
        self,
        angles: Mapping[int, float],
        duration: float = 0.0,
        *,
        wait: bool = False,
        timeout: float | None = None,
    ) -> None:
        """Like :meth:`move` with angles in degrees (host calibration applied)."""
        cal = self.calibration
        target = {k: cal.get(k, _NO_CAL).to_position(a) for k, a in angles.items()}
        await self.move(target, duration, wait=wait, timeout=timeout)

    async def free(self, ics: Iterable[int] | None = None) -> None:
        """Torque off (8000h) for the selected servos (default: all known)."""
        sel = await self._select(ics)
        await self.client.run_const_frame_servo(1, dict.fromkeys(sel, POSITION_FREE))

    async def hold(self, ics: Iterable[int] | None = None) -> None:
        """Torque on at the current position (7FFFh) for the selected servos."""
        sel = await self._select(ics)
        await self.client.run_const_frame_servo(1, dict.fromkeys(sel, POSITION_HOLD))

    async def interpolating(self, ics: Iterable[int] | None = None) -> list[int]:
        """ICS numbers whose interpolation is still running."""
        sel = await self._select(ics)
        raw = await self._read_field(sel, SERVO.SPEED, 1)
        return [k for k in sel if raw[k][0]]

    async def wait_interpolation(
        self, ics: Iterable[int] | None = None, *, timeout: float = 5.0, poll: float | None = None
    ) -> None:
        """Wait until the selected servos finish their moves; Rcb4TimeoutError after
        ``timeout`` seconds."""
        sel = await self._select(ics)
        interval = await self.output_period() if poll is None else poll
        deadline = time.monotonic() + timeout
        while True:
            busy = await self.interpolating(sel)
            if not busy:
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(f"servos {busy} still moving after {timeout:g} s")
            await asyncio.sleep(min(interval, max(0.0, deadline - time.monotonic())))

    # ------------------------------------------------------------------ motions

    async def motion_status(self) -> MotionStatus:
        """PC, call depth and update flags (one frame), and the motion being played."""
        pc, depth, flags = read_run_state(await self.client.read_ram(ADDR.PC, RUN_STATE_SIZE), 0)
        motion = (await self.board_layout()).motion_at(pc)
        running = motion is not None and (depth != 0 or any(flags))
        return MotionStatus(pc, depth, flags, motion if running else None, running)

    async def play_motion(self, motion: int, *, wait: bool = False, timeout: float = 60.0) -> None:
        """Play ``motion`` the way HeartToHeart4 does (spec 11.4; see :meth:`Robot.play_motion`)."""
        lay = await self.board_layout()
        address = lay.address(motion)
        await self.send_sequence(seq.play_motion(await self.system_word(), address, lay.main_loop))
        if wait:
            await self.wait_motion(timeout=timeout)

    async def stop_motion(self, *, reset: bool = True) -> None:
        """Stop the ROM program (``reset``: back to the main loop, running)."""
        main_loop = (await self.board_layout()).main_loop
        word = await self.system_word()
        await self.send_sequence(seq.stop_program(word, main_loop, reset=reset))

    async def resume_motion(self) -> None:
        """Let the ROM program run again (sets ROM_F)."""
        await self.send_sequence(seq.resume_program(await self.system_word()))

    async def wait_motion(self, *, timeout: float = 60.0, poll: float = 0.02) -> None:
        """Wait until no motion plays; Rcb4TimeoutError after ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while True:
            status = await self.motion_status()
            if not status.running:
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(
                    f"motion {status.motion} still playing after {timeout:g} s (PC {status.pc:06X})"
                )
            await asyncio.sleep(poll)

    # ------------------------------------------------------------------ remote and sensors

    async def buttons(self) -> Button:
        """The remote-control button word (0350h, high byte first)."""
        return read_buttons(await self.client.read_ram(ADDR.BUTTONS, 2), 0)

    async def set_buttons(self, buttons: Button | int) -> None:
        """Write the button word: a virtual remote control."""
        value = int(buttons)
        if not 0 <= value <= 0xFFFF:
            raise ValueError("the button word is 16 bits")
        await self.client.write_ram(ADDR.BUTTONS, U16_BE.pack(value))

    async def press_button(self, buttons: Button | int, duration: float = 0.2) -> None:
        """Hold ``buttons`` for ``duration`` seconds, then release."""
        if duration < 0:
            raise ValueError("duration must be >= 0")
        await self.set_buttons(buttons)
        try:
            await asyncio.sleep(duration)
        finally:
            await self.set_buttons(Button.NONE)

    async def battery_voltage(self) -> float:
        """Supply voltage from AD0: AD0 * 25 / 1024 volts."""
        return ad_volts(read_u16(await self.client.read_ram(ADDR.ad(0), 2), 0))

    async def variable(self, n: int) -> int:
        """User variable ``n`` (0-19), a signed 16-bit value."""
        return read_s16(await self.client.read_ram(ADDR.user_variable(n), 2), 0)

    async def set_variable(self, n: int, value: int) -> None:
        if not -0x8000 <= value <= 0xFFFF:
            raise ValueError("user variables are 16 bits")
        await self.client.write_ram(ADDR.user_variable(n), u16_bytes(value))
