"""The robot-level API on top of :class:`~rcb4hv.client.Rcb4Client`: servos by ICS number,
angles in degrees, moves timed in seconds, motions, buttons, sensors and memory.

Everything here is built from the wire commands of the client; nothing is cached across
calls except the servo table (:meth:`Robot.discover_servos`) and the output period.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from types import TracebackType
from typing import Final, Literal

from rcb4hv.client.core import DEFAULT_TIMEOUT, Progress, Rcb4Client
from rcb4hv.client.readplan import LinkCost, plan_cheapest, plan_reads
from rcb4hv.errors import Rcb4TimeoutError
from rcb4hv.protocol import (
    ADDR,
    COUNTS_PER_DEGREE,
    ICS_COUNT,
    POSITION_FREE,
    POSITION_HOLD,
    RAM_SIZE,
    SERVO,
    Button,
    ServoBlock,
    SystemRegister,
    VersionReply,
    ics_to_id_port,
)
from rcb4hv.protocol.memory import SYS
from rcb4hv.protocol.ranges import (
    check_documented_ics,
    check_documented_position,
    check_documented_stretch,
)
from rcb4hv.rom.layout import HTH4_22, LAYOUTS, MotionLayout
from rcb4hv.transport import DEFAULT_BAUD

from .layout import detect_board_layout

__all__ = [
    "CENTER",
    "HTH4_20",
    "HTH4_22",
    "BoardInfo",
    "Calibration",
    "LinkCost",
    "MotionLayout",
    "MotionStatus",
    "Robot",
    "ServoInfo",
    "TimerState",
    "plan_reads",
]

log = logging.getLogger(__name__)

CENTER: Final = 7500
MAX_SPEED: Final = 255
SERVO_LIMIT: Final = 35  # ICS 35 is the remote-control receiver slot
PLANS_KEPT: Final = 64


HTH4_20: Final = LAYOUTS["2.0"]
"""HeartToHeart4 2.0 / 2.1: motion n at 0BB8h + 2048 (n - 1) (:data:`HTH4_22` is 2.2)."""


@dataclass(frozen=True, slots=True)
class Calibration:
    """Host-side angle calibration of one servo: ``trim`` in counts added to the centre
    (7500) and ``direction`` (+1 or -1) of positive angles."""

    trim: int = 0
    direction: Literal[1, -1] = 1

    def __post_init__(self) -> None:
        if self.direction not in (1, -1):
            raise ValueError("direction must be +1 or -1")

    def to_position(self, degrees: float) -> int:
        return round(CENTER + self.trim + self.direction * degrees * COUNTS_PER_DEGREE)

    def to_degrees(self, position: int) -> float:
        return self.direction * (position - CENTER - self.trim) / COUNTS_PER_DEGREE


@dataclass(frozen=True, slots=True)
class ServoInfo:
    """One servo found through the ICS allocation table and its servo block."""

    ics: int
    block_address: int
    block: ServoBlock

    @property
    def servo_id(self) -> int:
        return ics_to_id_port(self.ics)[0]

    @property
    def port(self) -> str:
        return ics_to_id_port(self.ics)[1]

    @property
    def trim(self) -> int:
        """The board's base value (+2): HeartToHeart4's trim."""
        return self.block.base

    @property
    def state(self) -> str:
        out = self.block.output
        if out == POSITION_FREE:
            return "free"
        if out == POSITION_HOLD:
            return "hold"
        return "moving" if self.block.speed else "on"

    def describe(self) -> dict[str, object]:
        b = self.block
        return {
            "ics": self.ics,
            "id": self.servo_id,
            "port": self.port,
            "block": f"{self.block_address:04X}",
            "trim": b.base,
            "measured": b.measured,
            "output": b.output,
            "state": self.state,
            "speed": b.speed,
            "remaining": b.remaining,
        }


@dataclass(frozen=True, slots=True)
class MotionStatus:
    """The ROM program's state: PC, call depth, update flags, and the motion it is in."""

    pc: int
    call_depth: int
    update_flags: bytes
    motion: int | None
    running: bool


@dataclass(frozen=True, slots=True)
class TimerState:
    count: int
    running: bool


@dataclass(frozen=True, slots=True)
class BoardInfo:
    version: str
    system: SystemRegister
    pc: int
    call_depth: int
    update_flags: bytes
    servos: list[ServoInfo] = field(default_factory=list)

    def describe(self) -> dict[str, object]:
        return {
            "version": self.version,
            "system_register": self.system.describe(),
            "pc": f"{self.pc:06X}",
            "call_depth": self.call_depth,
            "update_flags": self.update_flags.hex(),
            "servos": [s.describe() for s in self.servos],
        }


class Robot:
    """The robot-level API. ``with Robot.open("rcb4emu://") as robot: robot.discover_servos()``.

    ``calibration`` maps ICS numbers to host-side :class:`Calibration` (trim, direction) used by
    the degree methods. Positions outside 3500..11500 (other than hold/free) raise ValueError
    before anything is sent unless ``check_range=False`` is passed to the call.

    ``link_cost`` is the time model bulk reads are planned with (see
    :func:`~rcb4hv.client.readplan.plan_cheapest`): windows over several servo blocks or one
    frame per servo, whichever costs the link less.
    """

    def __init__(
        self,
        client: Rcb4Client,
        *,
        layout: MotionLayout | None = None,
        calibration: Mapping[int, Calibration] | None = None,
        link_cost: LinkCost | None = None,
    ) -> None:
        self.client = client
        self.link_cost = link_cost if link_cost is not None else LinkCost()
        self._plans: dict[tuple[LinkCost, tuple[tuple[int, int], ...]], list[tuple[int, int]]] = {}
        self._layout = layout
        self.calibration: dict[int, Calibration] = dict(calibration or {})
        self._servos: dict[int, ServoInfo] | None = None
        self._period: float | None = None

    @classmethod
    def open(
        cls,
        url: str | None = None,
        *,
        baudrate: int | None = DEFAULT_BAUD,
        timeout: float = DEFAULT_TIMEOUT,
        layout: MotionLayout | None = None,
        calibration: Mapping[int, Calibration] | None = None,
        link_cost: LinkCost | None = None,
    ) -> Robot:
        """Open ``url`` (see :meth:`Rcb4Client.open`) and wrap it."""
        client = Rcb4Client.open(url, baudrate=baudrate, timeout=timeout)
        return cls(client, layout=layout, calibration=calibration, link_cost=link_cost)

    @property
    def layout(self) -> MotionLayout:
        """The board's HeartToHeart4 layout: as given, else read from its ROM on first use
        (:func:`rcb4hv.client.layout.detect_board_layout`), else 2.2."""
        if self._layout is None:
            self._layout = detect_board_layout(self.client) or HTH4_22
        return self._layout

    @layout.setter
    def layout(self, value: MotionLayout) -> None:
        self._layout = value

    def close(self) -> None:
        self.client.close()

    def __enter__(self) -> Robot:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    # ------------------------------------------------------------------ basics

    def ping(self) -> float:
        """Round-trip time of one ACK check, in seconds."""
        t0 = time.perf_counter()
        self.client.acknowledge_check()
        return time.perf_counter() - t0

    def version(self) -> VersionReply:
        return self.client.get_version_info()

    def read_ram(self, address: int, size: int) -> bytes:
        return self.client.read_ram(address, size)

    def write_ram(self, address: int, data: bytes) -> None:
        self.client.write_ram(address, data)

    def ram_dump(self) -> bytes:
        """All 0490h bytes of RAM (10 frames)."""
        return self.client.read_ram(0, RAM_SIZE)

    def read_rom(self, address: int, size: int, progress: Progress | None = None) -> bytes:
        return self.client.read_rom(address, size, progress)

    def write_rom(
        self, address: int, data: bytes, *, verify: bool = True, progress: Progress | None = None
    ) -> None:
        self.client.write_rom(address, data, verify=verify, progress=progress)

    # ------------------------------------------------------------------ system register

    def system_register(self) -> SystemRegister:
        return SystemRegister.from_bytes(self.client.read_ram(ADDR.SYSTEM, 2))

    def set_system_register(self, value: SystemRegister | int) -> None:
        word = value.to_word() if isinstance(value, SystemRegister) else value
        if not 0 <= word <= 0xFFFF:
            raise ValueError("the system register is 16 bits")
        self.client.write_ram(ADDR.SYSTEM, word.to_bytes(2, "little"))
        self._period = None

    def _system_word(self) -> int:
        return int.from_bytes(self.client.read_ram(ADDR.SYSTEM, 2), "little")

    def output_period(self, refresh: bool = False) -> float:
        """Servo output period in seconds (system register bits 5-4), cached."""
        if self._period is None or refresh:
            self._period = self.system_register().frame_period_ms / 1000.0
        return self._period

    def frames_for(self, duration: float) -> int:
        """Servo speed (output periods) for a move lasting ``duration`` seconds (at least 1)."""
        if duration < 0:
            raise ValueError("duration must be >= 0")
        period = self.output_period()
        frames = max(1, round(duration / period))
        if frames > MAX_SPEED:
            raise ValueError(
                f"{duration:g} s is {frames} output periods of {period * 1000:g} ms; "
                f"the most one move can last is {MAX_SPEED} periods ({MAX_SPEED * period:g} s)"
            )
        return frames

    def info(self) -> BoardInfo:
        """Version, system register, ROM program state and the servo table."""
        version = self.client.get_version_info().text
        head = self.client.read_ram(0, 12)
        servos = self.discover_servos()
        return BoardInfo(
            version=version,
            system=SystemRegister.from_bytes(head[0:2]),
            pc=int.from_bytes(head[2:5], "little"),
            call_depth=head[5],
            update_flags=head[7:12],
            servos=servos,
        )

    def wait_ready(self, timeout: float = 5.0, poll: float = 0.02) -> None:
        """Wait until the ROM program has finished its start-up: its PC is in the main loop
        (between the layout's main loop and motion area) with an empty call stack, or the
        program is stopped. A HeartToHeart4 image copies the servo table into RAM during
        start-up, so call this before :meth:`discover_servos` right after power-on."""
        deadline = time.monotonic() + timeout
        lay = self.layout
        while True:
            head = self.client.read_ram(ADDR.SYSTEM, 6)
            word, pc, depth = head[0] | head[1] << 8, int.from_bytes(head[2:5], "little"), head[5]
            if not word & SYS.ROM_RUN or (lay.main_loop <= pc < lay.motion_base and depth == 0):
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(
                    f"ROM program not in its main loop after {timeout:g} s (PC {pc:06X})"
                )
            time.sleep(poll)

    # ------------------------------------------------------------------ servo discovery

    def allocation_table(self) -> list[int | None]:
        """``alloc[0..35]``: the RAM address of each ICS number's block, or None (FFFF)."""
        raw = self.client.read_ram(ADDR.ICS_ALLOC, 2 * ICS_COUNT)
        out: list[int | None] = []
        for k in range(ICS_COUNT):
            v = raw[2 * k] | raw[2 * k + 1] << 8
            out.append(None if v == 0xFFFF else v)
        return out

    def discover_servos(self) -> list[ServoInfo]:
        """Servos = allocated ICS numbers 0-34 whose block has type 0, read in the fewest
        frames; the result is cached for the position and move methods."""
        table = self.allocation_table()
        blocks = {
            k: a
            for k, a in enumerate(table)
            if a is not None and k < SERVO_LIMIT and ADDR.USER <= a <= RAM_SIZE - ServoBlock.SIZE
        }
        data = self._read_spans({k: (a, ServoBlock.SIZE) for k, a in blocks.items()})
        servos = {}
        for k, a in blocks.items():
            block = ServoBlock.from_bytes(data[k])
            if block.type == 0:
                servos[k] = ServoInfo(k, a, block)
        self._servos = servos
        log.debug("discovered %d servos: %s", len(servos), sorted(servos))
        return [servos[k] for k in sorted(servos)]

    @property
    def servo_ids(self) -> list[int]:
        """ICS numbers of the known servos (discovers them on first use)."""
        return sorted(self._known())

    def _known(self) -> dict[int, ServoInfo]:
        if self._servos is None:
            self.discover_servos()
        assert self._servos is not None
        return self._servos

    def _select(self, ics: Iterable[int] | None) -> list[int]:
        known = self._known()
        if ics is None:
            return sorted(known)
        out = sorted(set(ics))
        missing = [k for k in out if k not in known]
        if missing:
            raise ValueError(f"no servo at ICS {missing} (known: {sorted(known)})")
        return out

    def _read_spans(self, spans: Mapping[int, tuple[int, int]]) -> dict[int, bytes]:
        """Read several RAM spans (keyed by anything) with the cheapest plan (``link_cost``)."""
        reads = self._plan(tuple(spans.values()))
        if not reads:
            return dict.fromkeys(spans, b"")
        lo = reads[0][0]
        window = bytearray(reads[-1][0] + reads[-1][1] - lo)
        for a, n in reads:
            window[a - lo : a - lo + n] = self.client.read_ram(a, n)
        return {key: bytes(window[a - lo : a - lo + n]) for key, (a, n) in spans.items()}

    def _read_field(self, ics: list[int], offset: int, size: int) -> dict[int, bytes]:
        known = self._known()
        return self._read_spans({k: (known[k].block_address + offset, size) for k in ics})

    def read_plan(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> list[tuple[int, int]]:
        """The ``(address, size)`` RAM reads :meth:`positions` sends for ``ics``."""
        offset = SERVO.MEASURED if kind == "measured" else SERVO.OUTPUT
        known = self._known()
        spans = tuple((known[k].block_address + offset, 2) for k in self._select(ics))
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

    def positions(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> dict[int, int]:
        """Raw positions by ICS number: ``measured`` (+4) or commanded ``output`` (+6)."""
        offset = SERVO.MEASURED if kind == "measured" else SERVO.OUTPUT
        sel = self._select(ics)
        raw = self._read_field(sel, offset, 2)
        return {k: int.from_bytes(raw[k], "little") for k in sel}

    def servo_states(self, ics: Iterable[int] | None = None) -> list[ServoInfo]:
        """Fresh servo blocks (positions, speed, remaining steps) of the selected servos."""
        sel = self._select(ics)
        raw = self._read_field(sel, 0, ServoBlock.SIZE)
        known = self._known()
        return [ServoInfo(k, known[k].block_address, ServoBlock.from_bytes(raw[k])) for k in sel]

    def to_degrees(self, ics: int, position: int) -> float:
        return self.calibration.get(ics, _NO_CAL).to_degrees(position)

    def to_position(self, ics: int, degrees: float) -> int:
        return self.calibration.get(ics, _NO_CAL).to_position(degrees)

    def angles(
        self, ics: Iterable[int] | None = None, kind: Literal["measured", "output"] = "measured"
    ) -> dict[int, float]:
        """Angles in degrees (with the host calibration). Free/hold markers read as NaN."""
        out = {}
        for k, p in self.positions(ics, kind).items():
            special = p in (POSITION_FREE, POSITION_HOLD) or (p == 0 and kind == "output")
            out[k] = float("nan") if special else self.to_degrees(k, p)
        return out

    # ------------------------------------------------------------------ moves

    @staticmethod
    def check_position(ics: int, position: int) -> None:
        """ValueError unless ``position`` is in the documented 3500..11500 (or hold/free)."""
        check_documented_position(ics, position)

    def move(
        self,
        positions: Mapping[int, int],
        duration: float = 0.0,
        *,
        wait: bool = False,
        timeout: float | None = None,
        check_range: bool = True,
    ) -> None:
        """Move servos (ICS number -> raw position) linearly over ``duration`` seconds.

        One RunConstFrameServo frame; ``wait`` waits for the interpolation to end.
        """
        if not positions:
            raise ValueError("no servo to move")
        for k, p in positions.items():
            if check_range:
                self.check_position(k, p)
            elif not 0 <= p <= 0xFFFF:
                raise ValueError(f"ICS {k}: position {p} is not 16 bits")
        speed = self.frames_for(duration)
        self.client.run_const_frame_servo(speed, dict(positions))
        if wait:
            self.wait_interpolation(
                positions, timeout=duration + 1.0 if timeout is None else timeout
            )

    def move_angles(
        self,
        angles: Mapping[int, float],
        duration: float = 0.0,
        *,
        wait: bool = False,
        timeout: float | None = None,
    ) -> None:
        """Like :meth:`move` with angles in degrees (host calibration applied)."""
        self.move(
            {k: self.to_position(k, a) for k, a in angles.items()},
            duration,
            wait=wait,
            timeout=timeout,
        )

    def free(self, ics: Iterable[int] | None = None) -> None:
        """Torque off (position 8000h) for the selected servos (default: all known)."""
        sel = self._select(ics)
        self.client.run_const_frame_servo(1, {k: POSITION_FREE for k in sel})

    def hold(self, ics: Iterable[int] | None = None) -> None:
        """Torque on at the current position (7FFFh) for the selected servos."""
        sel = self._select(ics)
        self.client.run_const_frame_servo(1, {k: POSITION_HOLD for k in sel})

    def neutral(
        self, ics: Iterable[int] | None = None, duration: float = 1.0, *, wait: bool = False
    ) -> None:
        """Every selected servo to 0 degrees (centre plus host trim) over ``duration``."""
        sel = self._select(ics)
        self.move_angles(dict.fromkeys(sel, 0.0), duration, wait=wait)

    def interpolating(self, ics: Iterable[int] | None = None) -> list[int]:
        """ICS numbers whose interpolation is still running (speed byte +8 non-zero)."""
        sel = self._select(ics)
        raw = self._read_field(sel, SERVO.SPEED, 1)
        return [k for k in sel if raw[k][0]]

    def wait_interpolation(
        self, ics: Iterable[int] | None = None, *, timeout: float = 5.0, poll: float | None = None
    ) -> None:
        """Wait until the selected servos finish their moves; Rcb4TimeoutError after
        ``timeout`` seconds. Polls once per output period by default."""
        sel = self._select(ics)
        interval = self.output_period() if poll is None else poll
        deadline = time.monotonic() + timeout
        while True:
            busy = self.interpolating(sel)
            if not busy:
                return
            if time.monotonic() >= deadline:
                raise Rcb4TimeoutError(f"servos {busy} still moving after {timeout:g} s")
            time.sleep(min(interval, max(0.0, deadline - time.monotonic())))

    def _stretch_values(
        self,
        what: str,
        values: Mapping[int, int] | int,
        ics: Iterable[int] | None,
        check_range: bool,
    ) -> dict[int, int]:
        vals = (
            dict(values)
            if isinstance(values, Mapping)
            else dict.fromkeys(self._select(ics), values)
        )
        for k, v in vals.items():
            check_documented_ics(k)
            if check_range:
                check_documented_stretch(what, k, v)
        return vals

    def set_stretch(
        self,
        values: Mapping[int, int] | int,
        ics: Iterable[int] | None = None,
        *,
        check_range: bool = True,
    ) -> None:
        """Stretch (holding gain) 1-127: a mapping, or one value for the selected servos.

        Values outside the documented 1-127 raise ValueError unless ``check_range=False``
        (the wire carries any byte; real projects send 0)."""
        self.client.set_stretch(self._stretch_values("stretch", values, ics, check_range))

    def set_speed(
        self,
        values: Mapping[int, int] | int,
        ics: Iterable[int] | None = None,
        *,
        check_range: bool = True,
    ) -> None:
        """Servo speed parameter 1-127: a mapping, or one value for the selected servos
        (``check_range`` as for :meth:`set_stretch`)."""
        self.client.set_speed(self._stretch_values("speed", values, ics, check_range))

    # ------------------------------------------------------------------ motions

    def motion_status(self) -> MotionStatus:
        """PC, call depth and update flags (one frame), and the motion being played."""
        raw = self.client.read_ram(ADDR.PC, 10)
        pc = int.from_bytes(raw[0:3], "little")
        depth, flags = raw[3], bytes(raw[5:10])
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
        word = self._system_word()
        self.client.write_ram(
            ADDR.SYSTEM,
            (word & ~(SYS.ICS_OUTPUT | SYS.ROM_RUN | SYS.VECTOR_JUMP)).to_bytes(2, "little"),
        )
        self._reset_program()
        self.client.call(address)
        self.client.write_ram(
            ADDR.SYSTEM,
            (word | SYS.ICS_OUTPUT | SYS.ROM_RUN | SYS.VECTOR_JUMP).to_bytes(2, "little"),
        )
        log.info("playing motion %d at %06X", motion, address)
        if wait:
            self.wait_motion(timeout=timeout)

    def _reset_program(self) -> None:
        pc = self.layout.main_loop.to_bytes(3, "little")
        self.client.write_ram(ADDR.PC, pc + bytes(7))

    def stop_motion(self, *, reset: bool = True) -> None:
        """Stop the ROM program. With ``reset`` (default) the PC goes back to the main loop
        and the program runs on there (the board's idle state); without it the program is
        only paused (:meth:`resume_motion` continues it)."""
        word = self._system_word()
        self.client.write_ram(ADDR.SYSTEM, (word & ~SYS.ROM_RUN).to_bytes(2, "little"))
        if reset:
            self._reset_program()
            self.client.write_ram(ADDR.SYSTEM, (word | SYS.ROM_RUN).to_bytes(2, "little"))

    def resume_motion(self) -> None:
        """Let the ROM program run again (sets ROM_F)."""
        word = self._system_word()
        self.client.write_ram(ADDR.SYSTEM, (word | SYS.ROM_RUN).to_bytes(2, "little"))

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

    # ------------------------------------------------------------------ remote, sensors, I/O

    def buttons(self) -> Button:
        """The remote-control button word (0350h, high byte first)."""
        return Button.from_ram(self.client.read_ram(ADDR.BUTTONS, 2))

    def set_buttons(self, buttons: Button | int) -> None:
        """Write the button word: a virtual remote control."""
        value = int(buttons)
        if not 0 <= value <= 0xFFFF:
            raise ValueError("the button word is 16 bits")
        self.client.write_ram(ADDR.BUTTONS, value.to_bytes(2, "big"))

    def press_button(self, buttons: Button | int, duration: float = 0.2) -> None:
        """Hold ``buttons`` on the virtual remote for ``duration`` seconds, then release."""
        if duration < 0:
            raise ValueError("duration must be >= 0")
        self.set_buttons(buttons)
        try:
            time.sleep(duration)
        finally:
            self.set_buttons(Button.NONE)

    def pa_values(self) -> tuple[int, int, int, int]:
        """The four analogue remote values PA1-PA4 (0352h-0355h)."""
        raw = self.client.read_ram(ADDR.PA[0], 4)
        return (raw[0], raw[1], raw[2], raw[3])

    def set_pa(self, index: int, value: int) -> None:
        """Set PA``index`` (1-4) to ``value`` (0-255)."""
        if not 1 <= index <= 4:
            raise ValueError("PA inputs are 1-4")
        if not 0 <= value <= 0xFF:
            raise ValueError("PA values are 0-255")
        self.client.write_ram(ADDR.PA[index - 1], bytes((value,)))

    def ad_values(self) -> list[int]:
        """AD0-AD10 (10-bit) in one frame."""
        raw = self.client.read_ram(ADDR.AD_VALUES, 22)
        return [(raw[2 * i] | raw[2 * i + 1] << 8) & 0x3FF for i in range(11)]

    def battery_voltage(self) -> float:
        """Supply voltage from AD0: AD0 * 25 / 1024 volts."""
        raw = self.client.read_ram(ADDR.AD_VALUES, 2)
        return ((raw[0] | raw[1] << 8) & 0x3FF) * 25 / 1024

    def pio(self) -> tuple[int, int]:
        """(direction mask, data) of the 10 PIO pins (1 = output)."""
        raw = self.client.read_ram(ADDR.PIO_DIRECTION, 4)
        return (raw[0] | raw[1] << 8) & 0x3FF, (raw[2] | raw[3] << 8) & 0x3FF

    def set_pio_direction(self, mask: int) -> None:
        if not 0 <= mask <= 0x3FF:
            raise ValueError("PIO direction is 10 bits")
        self.client.write_ram(ADDR.PIO_DIRECTION, mask.to_bytes(2, "little"))

    def write_pio(self, value: int) -> None:
        if not 0 <= value <= 0x3FF:
            raise ValueError("PIO data is 10 bits")
        self.client.write_ram(ADDR.PIO_DATA, value.to_bytes(2, "little"))

    def timer(self, n: int) -> TimerState:
        """Timer ``n`` (0-3): count (100 ms steps) and whether it runs."""
        raw = self.client.read_ram(ADDR.timer(n), 2)
        word = raw[0] | raw[1] << 8
        return TimerState(word & 0x7FFF, not word & 0x8000)

    def set_timer(self, n: int, count: int, *, run: bool = True) -> None:
        """Load timer ``n`` with ``count`` (0-32767) and start it (or leave it stopped)."""
        if not 0 <= count <= 0x7FFF:
            raise ValueError("timer counts are 0..32767")
        word = count | (0 if run else 0x8000)
        self.client.write_ram(ADDR.timer(n), word.to_bytes(2, "little"))

    def stop_timer(self, n: int) -> None:
        state = self.timer(n)
        self.set_timer(n, state.count, run=False)

    def counter(self, n: int) -> int:
        """Counter ``n`` (0-10), one byte each from 0457h."""
        return self.client.read_ram(ADDR.counter(n), 1)[0]

    def set_counter(self, n: int, value: int) -> None:
        if not 0 <= value <= 0xFF:
            raise ValueError("counters are 0..255")
        self.client.write_ram(ADDR.counter(n), bytes((value,)))

    def variable(self, n: int) -> int:
        """User variable ``n`` (0-19), a signed 16-bit value."""
        return int.from_bytes(self.client.read_ram(ADDR.user_variable(n), 2), "little", signed=True)

    def variables(self) -> list[int]:
        """All 20 user variables in one frame."""
        raw = self.client.read_ram(ADDR.USER_VARIABLES, 2 * ADDR.USER_VARIABLE_COUNT)
        return [int.from_bytes(raw[i : i + 2], "little", signed=True) for i in range(0, 40, 2)]

    def set_variable(self, n: int, value: int) -> None:
        if not -0x8000 <= value <= 0xFFFF:
            raise ValueError("user variables are 16 bits")
        self.client.write_ram(ADDR.user_variable(n), (value & 0xFFFF).to_bytes(2, "little"))


_NO_CAL: Final = Calibration()
