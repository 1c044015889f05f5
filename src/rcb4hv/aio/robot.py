"""The robot-level API on top of :class:`~rcb4hv.aio.AsyncRcb4Client`: servos by ICS
number, angles in degrees, moves timed in seconds, motions, buttons, sensors and memory.

One source, two faces: ``src/rcb4hv/aio/robot.py`` (asyncio) is the only source of the robot
API, and ``tools/unasync.py`` writes ``src/rcb4hv/client/robot.py`` (blocking) from it, so
both faces have the same methods, arguments, results and frames on the wire.

Everything here is built from the wire commands of the client; nothing is cached across
calls except the servo table (:meth:`AsyncRobot.discover_servos`), the layout and the output
period.
"""

from __future__ import annotations

import logging
import time
from asyncio import sleep
from collections.abc import Iterable, Mapping
from types import TracebackType
from typing import Literal

from rcb4hv.aio.client import DEFAULT_TIMEOUT, AsyncRcb4Client, Progress
from rcb4hv.aio.robot_io import AsyncRobotIO
from rcb4hv.aio.robot_motion import AsyncRobotMotions
from rcb4hv.client.args import (
    check_choice,
    check_ics,
    check_ics_list,
    check_wait,
    finite,
    integer,
    seconds,
    servo_targets,
)
from rcb4hv.client.readplan import LinkCost, plan_cheapest
from rcb4hv.client.robot_types import (
    MAX_SPEED,
    PLANS_KEPT,
    SERVO_LIMIT,
    BoardInfo,
    Calibration,
    ServoInfo,
    robot_options,
    servo_calibration,
)
from rcb4hv.errors import ArgumentError, Rcb4TimeoutError
from rcb4hv.protocol import (
    ADDR,
    ICS_COUNT,
    POSITION_FREE,
    POSITION_HOLD,
    RAM_SIZE,
    SERVO,
    ServoBlock,
    SystemRegister,
    VersionReply,
)
from rcb4hv.protocol.memory import (
    SYS,
    Field,
    ProgramState,
    read_pc,
    read_system,
    system_word_bytes,
    unpack_alloc,
)
from rcb4hv.protocol.ranges import check_documented_stretch
from rcb4hv.rom.layout import MotionLayout
from rcb4hv.transport import DEFAULT_BAUD

__all__ = ["AsyncRobot"]

log = logging.getLogger(__name__)

KINDS = ("measured", "output")
"""The positions a servo block holds: the measured one (+4) and the commanded output (+6)."""


class AsyncRobot(AsyncRobotMotions, AsyncRobotIO):
    """The robot-level API.

    ``async with await AsyncRobot.open("rcb4emu://") as robot: await robot.discover_servos()``

    ``calibration`` maps ICS numbers to host-side :class:`Calibration` (trim, direction) used by
    the degree methods. Positions outside 3500..11500 (other than hold/free) raise ValueError
    before anything is sent unless ``check_range=False`` is passed to the call.

    ``layout`` is the board's HeartToHeart4 layout; None: read from its ROM on first use
    (:meth:`board_layout`). ``link_cost`` is the time model bulk reads are planned with (see
    :func:`~rcb4hv.client.readplan.plan_cheapest`): windows over several servo blocks or one
    frame per servo, whichever costs the link less.
    """

    def __init__(
        self,
        client: AsyncRcb4Client,
        *,
        layout: MotionLayout | None = None,
        calibration: Mapping[int, Calibration] | None = None,
        link_cost: LinkCost | None = None,
    ) -> None:
        layout, cal, cost = robot_options(layout, calibration, link_cost)  # typed errors
        self.client = client
        self.link_cost = cost
        self._plans: dict[tuple[LinkCost, tuple[tuple[int, int], ...]], list[tuple[int, int]]] = {}
        self.layout = layout
        self.calibration: dict[int, Calibration] = cal
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
        link_cost: LinkCost | None = None,
    ) -> AsyncRobot:
        """Open ``url`` (see :meth:`AsyncRcb4Client.open`) and wrap it. ``layout``,
        ``calibration`` and ``link_cost`` are checked before the link is opened."""
        robot_options(layout, calibration, link_cost)
        client = await AsyncRcb4Client.open(url, baudrate=baudrate, timeout=timeout)
        return cls(client, layout=layout, calibration=calibration, link_cost=link_cost)

    async def close(self) -> None:
        await self.client.close()

    async def reconnect(self) -> None:
        """Reopen the link (after a disconnect); what the robot knew of the board is kept."""
        await self.client.reconnect()

    async def __aenter__(self) -> AsyncRobot:
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.close()

    # ------------------------------------------------------------------ basics

    async def ping(self) -> float:
        """Round-trip time of one ACK check, in seconds."""
        await self.client.settle()  # not the wait for a reply an earlier call left owed
        t0 = time.perf_counter()
        await self.client.acknowledge_check()
        return time.perf_counter() - t0

    async def version(self) -> VersionReply:
        return await self.client.get_version_info()

    async def read_ram(self, address: int, size: int) -> bytes:
        return await self.client.read_ram(address, size)

    async def write_ram(self, address: int, data: bytes) -> None:
        await self.client.write_ram(address, data)

    async def ram_dump(self) -> bytes:
        """All 0490h bytes of RAM (10 frames)."""
        return await self.client.read_ram(0, RAM_SIZE)

    async def read_rom(self, address: int, size: int, progress: Progress | None = None) -> bytes:
        return await self.client.read_rom(address, size, progress)

    async def write_rom(
        self, address: int, data: bytes, *, verify: bool = True, progress: Progress | None = None
    ) -> None:
        await self.client.write_rom(address, data, verify=verify, progress=progress)

    # ------------------------------------------------------------------ system register

    async def system_register(self) -> SystemRegister:
        return SystemRegister.from_bytes(await self.client.read_ram(ADDR.SYSTEM, 2))

    async def set_system_register(self, value: SystemRegister | int) -> None:
        word = value.to_word() if isinstance(value, SystemRegister) else integer("value", value)
        if not 0 <= word <= 0xFFFF:
            raise ArgumentError(f"the system register is 16 bits (0..65535), not {word}")
        await self.client.write_ram(ADDR.SYSTEM, system_word_bytes(word))
        self._period = None

    async def output_period(self, refresh: bool = False) -> float:
        """Servo output period in seconds (system register bits 5-4), cached."""
        if self._period is None or refresh:
            self._period = (await self.system_register()).frame_period_ms / 1000.0
        return self._period

    async def frames_for(self, duration: float) -> int:
        """Servo speed (output periods) for a move lasting ``duration`` seconds (at least 1)."""
        duration = seconds("duration", duration)
        period = await self.output_period()
        frames = max(1, round(duration / period))
        if frames > MAX_SPEED:
            raise ArgumentError(
                f"{duration:g} s is {frames} output periods of {period * 1000:g} ms; "
                f"the most one move can last is {MAX_SPEED} periods ({MAX_SPEED * period:g} s)"
            )
        return frames

    async def info(self) -> BoardInfo:
        """Version, system register, ROM program state and the servo table."""
        version = (await self.client.get_version_info()).text
        state = ProgramState.unpack(await self.client.read_ram(ADDR.SYSTEM, ProgramState.SIZE), 0)
        servos = await self.discover_servos()
        return BoardInfo(
            version=version,
            system=SystemRegister.from_word(state.system),
            pc=state.pc,
            call_depth=state.call_depth,
            update_flags=state.update_flags,
            servos=servos,
        )

    async def wait_ready(self, timeout: float = 5.0, poll: float = 0.02) -> None:
        """Wait until the ROM program has finished its start-up: its PC is in the main loop
        (between the layout's main loop and motion area) with an empty call stack, or the
        program is stopped. A HeartToHeart4 image copies the servo table into RAM during
        start-up, so call this before :meth:`discover_servos` right after power-on.
        ``timeout`` is a finite number of seconds > 0, ``poll`` one >= 0 (ArgumentError)."""
        check_wait(timeout, poll)
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
            await sleep(poll)

    # ------------------------------------------------------------------ servo discovery

    async def allocation_table(self) -> list[int | None]:
        """``alloc[0..35]``: the RAM address of each ICS number's block, or None (FFFF)."""
        raw = await self.client.read_ram(ADDR.ICS_ALLOC, 2 * ICS_COUNT)
        return unpack_alloc(raw, 0)

    async def discover_servos(self) -> list[ServoInfo]:
        """Servos = allocated ICS numbers 0-34 whose block has type 0, read in the fewest
        frames; the result is cached for the position and move methods."""
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
        log.debug("discovered %d servos: %s", len(servos), sorted(servos))
        return [servos[k] for k in sorted(servos)]

    async def servo_ids(self) -> list[int]:
        """ICS numbers of the known servos (discovers them on first use)."""
        return sorted(await self._known())

    async def _known(self) -> dict[int, ServoInfo]:
        if self._servos is None:
            await self.discover_servos()
        assert self._servos is not None
        return self._servos

    async def _select(self, ics: Iterable[int] | None) -> list[int]:
        known = await self._known()
        if ics is None:
            return sorted(known)
        out = sorted(set(check_ics_list(ics)))
        missing = [k for k in out if k not in known]
        if missing:
            raise ArgumentError(f"no servo at ICS {missing} (known: {sorted(known)})")
        return out

    async def _read_spans(self, spans: Mapping[int, tuple[int, int]]) -> dict[int, bytes]:
        """Read several RAM spans (keyed by anything) with the cheapest plan (``link_cost``)."""
        reads = self._plan(tuple(spans.values()))
        if not reads:
            return dict.fromkeys(spans, b"")
        lo = reads[0][0]
        window = bytearray(reads[-1][0] + reads[-1][1] - lo)
        for a, n in reads:
            window[a - lo : a - lo + n] = await self.client.read_ram(a, n)
        return {key: bytes(window[a - lo : a - lo + n]) for key, (a, n) in spans.items()}

    async def _read_field(self, ics: list[int], fld: Field) -> dict[int, int]:
        """One servo-block field of each of the ``ics`` servos, in the fewest frames."""
        known = await self._known()
        raw = await self._read_spans({k: fld.span(known[k].block_address) for k in ics})
        return {k: fld.decode(raw[k]) for k in ics}

    async def read_plan(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> list[tuple[int, int]]:
        """The ``(address, size)`` RAM reads :meth:`positions` sends for ``ics``."""
        check_choice("kind", kind, KINDS)
        fld = SERVO.F_MEASURED if kind == "measured" else SERVO.F_OUTPUT
        known = await self._known()
        spans = tuple(fld.span(known[k].block_address) for k in await self._select(ics))
        return list(self._plan(spans))

    def _plan(self, spans: tuple[tuple[int, int], ...]) -> list[tuple[int, int]]:
        """:func:`plan_cheapest` of ``spans``, remembered: a loop reads the same spans."""
        key = (self.link_cost, spans)
        plan = self._plans.get(key)
        if plan is None:
            if len(self._plans) >= PLANS_KEPT:
                self._plans.clear()
            plan = self._plans[key] = plan_cheapest(spans, self.link_cost)
        return plan

    # ------------------------------------------------------------------ positions

    async def positions(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> dict[int, int]:
        """Raw positions by ICS number: ``measured`` (+4) or commanded ``output`` (+6)."""
        check_choice("kind", kind, KINDS)
        fld = SERVO.F_MEASURED if kind == "measured" else SERVO.F_OUTPUT
        return await self._read_field(await self._select(ics), fld)

    async def servo_states(self, ics: Iterable[int] | None = None) -> list[ServoInfo]:
        """Fresh servo blocks (positions, speed, remaining steps) of the selected servos."""
        sel = await self._select(ics)
        known = await self._known()
        raw = await self._read_spans({k: (known[k].block_address, ServoBlock.SIZE) for k in sel})
        return [ServoInfo(k, known[k].block_address, ServoBlock.from_bytes(raw[k])) for k in sel]

    def to_degrees(self, ics: int, position: int) -> float:
        """The angle of raw ``position`` (host calibration); ArgumentError for an ICS number
        the robot does not have (:func:`~rcb4hv.client.robot_types.servo_calibration`)."""
        return servo_calibration(self.calibration, self._servos, ics).to_degrees(position)

    def to_position(self, ics: int, degrees: float) -> int:
        """The raw position of ``degrees`` (host calibration); ArgumentError for an ICS number
        the robot does not have (as :meth:`to_degrees`) or an angle that is not finite."""
        cal = servo_calibration(self.calibration, self._servos, ics)
        return cal.to_position(finite(f"ICS {ics}: angle", degrees))

    async def angles(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> dict[int, float]:
        """Angles in degrees (with the host calibration). Free/hold markers read as NaN."""
        out = {}
        for k, p in (await self.positions(ics, kind)).items():
            special = p in (POSITION_FREE, POSITION_HOLD) or (p == 0 and kind == "output")
            out[k] = float("nan") if special else self.to_degrees(k, p)
        return out

    # ------------------------------------------------------------------ moves

    @staticmethod
    def check_position(ics: int, position: int) -> None:
        """ArgumentError (a ValueError) unless ``ics`` is an ICS number 0..35 and ``position``
        an int in the documented 3500..11500 (or hold/free)."""
        servo_targets({ics: position}, check_range=True)

    async def move(
        self,
        positions: Mapping[int, int],
        duration: float = 0.0,
        *,
        wait: bool = False,
        timeout: float | None = None,
        check_range: bool = True,
    ) -> None:
        """Move servos (ICS number -> raw position) linearly over ``duration`` seconds.

        One RunConstFrameServo frame; ``wait`` waits for the interpolation to end. A servo the
        board has not allocated is a ValueError before anything is sent.
        """
        targets = servo_targets(positions, check_range)
        if not targets:
            raise ArgumentError("no servo to move")
        if timeout is not None:
            check_wait(timeout)
        duration = seconds("duration", duration)
        await self._select(targets)
        speed = await self.frames_for(duration)
        await self.client.run_const_frame_servo(speed, targets)
        if wait:
            await self.wait_interpolation(
                positions, timeout=duration + 1.0 if timeout is None else timeout
            )

    async def move_angles(
        self,
        angles: Mapping[int, float],
        duration: float = 0.0,
        *,
        wait: bool = False,
        timeout: float | None = None,
    ) -> None:
        """Like :meth:`move` with angles in degrees (host calibration applied)."""
        await self.move(
            {k: self.to_position(k, a) for k, a in angles.items()},
            duration,
            wait=wait,
            timeout=timeout,
        )

    async def free(self, ics: Iterable[int] | None = None) -> None:
        """Torque off (position 8000h) for the selected servos (default: all known)."""
        sel = await self._select(ics)
        await self.client.run_const_frame_servo(1, {k: POSITION_FREE for k in sel})

    async def hold(self, ics: Iterable[int] | None = None) -> None:
        """Torque on at the current position (7FFFh) for the selected servos."""
        sel = await self._select(ics)
        await self.client.run_const_frame_servo(1, {k: POSITION_HOLD for k in sel})

    async def neutral(
        self, ics: Iterable[int] | None = None, duration: float = 1.0, *, wait: bool = False
    ) -> None:
        """Every selected servo to 0 degrees (centre plus host trim) over ``duration``."""
        sel = await self._select(ics)
        await self.move_angles(dict.fromkeys(sel, 0.0), duration, wait=wait)

    async def interpolating(self, ics: Iterable[int] | None = None) -> list[int]:
        """ICS numbers whose interpolation is still running (speed byte +8 non-zero)."""
        sel = await self._select(ics)
        speeds = await self._read_field(sel, SERVO.F_SPEED)
        return [k for k in sel if speeds[k]]

    async def wait_interpolation(
        self, ics: Iterable[int] | None = None, *, timeout: float = 5.0, poll: float | None = None
    ) -> None:
        """Wait until the selected servos finish their moves; Rcb4TimeoutError after
        ``timeout`` seconds. Polls once per output period by default."""
        check_wait(timeout, poll)
        sel = await self._select(ics)
        interval = await self.output_period() if poll is None else poll
        deadline = time.monotonic() + timeout
        while True:
            busy = await self.interpolating(sel)
            if not busy:
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(f"servos {busy} still moving after {timeout:g} s")
            await sleep(min(interval, max(0.0, deadline - time.monotonic())))

    async def _stretch_values(
        self,
        what: str,
        values: Mapping[int, int] | int,
        ics: Iterable[int] | None,
        check_range: bool,
    ) -> dict[int, int]:
        vals = (
            dict(values)
            if isinstance(values, Mapping)
            else dict.fromkeys(await self._select(ics), values)
        )
        vals = {check_ics(k): integer(f"ICS {k}: {what}", v) for k, v in vals.items()}
        for k, v in vals.items():
            if check_range:
                check_documented_stretch(what, k, v)
        await self._select(vals)
        return vals

    async def set_stretch(
        self,
        values: Mapping[int, int] | int,
        ics: Iterable[int] | None = None,
        *,
        check_range: bool = True,
    ) -> None:
        """Stretch (holding gain) 1-127: a mapping, or one value for the selected servos.

        Values outside the documented 1-127 raise ValueError unless ``check_range=False``
        (the wire carries any byte; real projects send 0)."""
        vals = await self._stretch_values("stretch", values, ics, check_range)
        await self.client.set_stretch(vals)

    async def set_speed(
        self,
        values: Mapping[int, int] | int,
        ics: Iterable[int] | None = None,
        *,
        check_range: bool = True,
    ) -> None:
        """Servo speed parameter 1-127: a mapping, or one value for the selected servos
        (``check_range`` as for :meth:`set_stretch`)."""
        vals = await self._stretch_values("speed", values, ics, check_range)
        await self.client.set_speed(vals)
