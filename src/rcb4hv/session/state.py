"""What a :class:`~rcb4hv.session.BoardSession` knows about the board: immutable snapshots.

One poll reads the head of RAM (system register, PC, call depth, update flags, the AD
references and measured values) in one
frame, the servo blocks in the fewest frames (:func:`~rcb4hv.client.plan_reads`) and the
remote's button word and PA1-PA4 in one frame.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from rcb4hv.client import MotionLayout, Robot, ServoInfo
from rcb4hv.protocol import ADDR, POSITION_FREE, POSITION_HOLD, SystemRegister
from rcb4hv.protocol.memory import (
    AD_READINGS,
    PA_VALUES,
    AdReadings,
    ProgramState,
    ad_readings,
    ad_volts,
    read_buttons,
    read_u16,
)

__all__ = ["AngleHistory", "BoardState", "ServoRow", "poll_state"]

HEAD_SIZE = ADDR.AD_REFERENCE + AD_READINGS.size
"""Bytes 0000h..0037h: system register, PC, depth, update flags, AD references, measured."""
REMOTE_SIZE = ADDR.PA[-1] + 1 - ADDR.BUTTONS
"""Button word (2) and PA1-PA4 at 0350h."""


@dataclass(frozen=True, slots=True)
class ServoRow:
    """One line of the servo table."""

    ics: int
    id: int
    port: str
    trim: int
    measured: int
    degrees: float
    output: int
    state: str

    @classmethod
    def from_info(cls, robot: Robot, info: ServoInfo) -> ServoRow:
        m = info.block.measured
        special = m in (POSITION_FREE, POSITION_HOLD)
        deg = math.nan if special else robot.to_degrees(info.ics, m)
        return cls(
            info.ics, info.servo_id, info.port, info.trim, m, deg, info.block.output, info.state
        )


@dataclass(frozen=True, slots=True)
class BoardState:
    """A snapshot of the board (``connected`` False until the first poll succeeds)."""

    url: str
    connected: bool = False
    error: str | None = None
    t: float = 0.0
    baudrate: int = 0
    version: str = ""
    system: SystemRegister | None = None
    battery: float = 0.0
    pc: int = 0
    call_depth: int = 0
    update_flags: bytes = bytes(5)
    motion: int | None = None
    buttons: int = 0
    pa: tuple[int, int, int, int] = (0, 0, 0, 0)
    servos: tuple[ServoRow, ...] = ()
    polls: int = 0
    ad: AdReadings | None = None
    """AD0-AD10: references, measured values (input - reference) and inputs."""
    fault: str | None = None
    """The last unexpected error inside the session's worker (a move or a poll that raised
    something other than a link error); the worker logged it and runs on."""

    @property
    def rom_running(self) -> bool:
        return self.system is not None and self.system.rom_run

    @property
    def playing(self) -> bool:
        return self.motion is not None

    def servo(self, ics: int) -> ServoRow | None:
        for s in self.servos:
            if s.ics == ics:
                return s
        return None

    def describe(self) -> dict[str, object]:
        """A JSON-friendly view (the Board page shows it)."""
        return {
            "url": self.url,
            "connected": self.connected,
            "error": self.error,
            "fault": self.fault,
            "baud": self.baudrate,
            "version": self.version,
            "system_register": None if self.system is None else self.system.describe(),
            "battery_v": round(self.battery, 2),
            "pc": f"{self.pc:06X}",
            "call_depth": self.call_depth,
            "update_flags": self.update_flags.hex(),
            "motion": self.motion,
            "rom_program": "running" if self.rom_running else "stopped",
            "buttons": f"{self.buttons:04X}",
            "pa": list(self.pa),
            "ad": None
            if self.ad is None
            else {
                "input": list(self.ad.inputs),
                "reference": list(self.ad.references),
                "measured": list(self.ad.measured),
            },
        }


def poll_state(
    robot: Robot, base: BoardState, t: float, between: Callable[[], None] = lambda: None
) -> BoardState:
    """Read one snapshot through ``robot`` (whose servo table is already discovered).

    ``between()`` runs between the reads (the session sends pending servo moves there, so a
    poll never delays a slider by more than one read).
    """
    head = robot.read_ram(ADDR.SYSTEM, HEAD_SIZE)
    between()
    remote = robot.read_ram(ADDR.BUTTONS, REMOTE_SIZE)
    between()
    servos = robot.servo_states() if robot.servo_ids() else []
    program = ProgramState.unpack(head, 0)
    pc, depth, flags = program.pc, program.call_depth, program.update_flags
    layout: MotionLayout = robot.board_layout()
    motion = layout.motion_at(pc)
    running = motion is not None and (depth != 0 or program.waiting) and program.running
    return BoardState(
        url=base.url,
        connected=True,
        error=None,
        t=t,
        baudrate=base.baudrate,
        version=base.version,
        system=SystemRegister.from_word(program.system),
        battery=ad_volts(read_u16(head, ADDR.ad(0) - ADDR.SYSTEM)),
        pc=pc,
        call_depth=depth,
        update_flags=flags,
        motion=motion if running else None,
        buttons=int(read_buttons(remote, 0)),
        pa=PA_VALUES.unpack_from(remote, ADDR.PA[0] - ADDR.BUTTONS),
        servos=tuple(ServoRow.from_info(robot, s) for s in servos),
        polls=base.polls + 1,
        ad=ad_readings(head, ADDR.AD_REFERENCE - ADDR.SYSTEM),
        fault=base.fault,
    )


@dataclass
class AngleHistory:
    """Servo angles over the last ``seconds`` (for the live plot)."""

    seconds: float = 10.0
    samples: deque[tuple[float, dict[int, float]]] = field(default_factory=deque)

    def add(self, state: BoardState) -> None:
        self.samples.append((state.t, {s.ics: s.degrees for s in state.servos}))
        while self.samples and state.t - self.samples[0][0] > self.seconds:
            self.samples.popleft()

    def series(self, ics: Iterable[int], now: float) -> dict[int, list[tuple[float, float]]]:
        """``{ics: [(seconds before now (negative), degrees), ...]}``; NaN points dropped."""
        out: dict[int, list[tuple[float, float]]] = {k: [] for k in ics}
        for t, angles in list(self.samples):
            for k, pts in out.items():
                v = angles.get(k)
                if v is not None and not math.isnan(v):
                    pts.append((round(t - now, 3), round(v, 2)))
        return out
