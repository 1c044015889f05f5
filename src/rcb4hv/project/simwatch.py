"""What the simulator watches while a motion plays: exact recurrence of the board's state
(:class:`Watch`), progress between two looks (:func:`progress_state`) and the sensors that
servo mixing follows (:func:`mixed_sensors`).

A motion that makes progress - its servos or its loop counters and variables change between
two looks - is still doing what its program says, however long it takes in virtual time; one
that recurs exactly can never end; one that recurs while its servos are mixed from an AD
channel is holding a pose that the sensor corrects (a gyro balancing a wheeled robot).
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rcb4hv.emulator import Board
from rcb4hv.protocol import ICS_COUNT
from rcb4hv.protocol.memory import (
    ADDR,
    NO_BLOCK,
    SERVO,
    mix_rate,
    mix_source,
    read_alloc,
    read_u16,
)

__all__ = ["Watch", "mixed_sensors", "progress_state"]

_AD_FIRST = ADDR.AD_VALUES
_AD_END = ADDR.AD_VALUES + 2 * ADDR.AD_COUNT  # 11 channels, one 16-bit word each (spec 12)
_COUNTERS = slice(ADDR.COUNTERS, ADDR.COUNTERS + ADDR.COUNTER_COUNT)
_VARIABLES = slice(ADDR.USER_VARIABLES, ADDR.USER_VARIABLES + 2 * ADDR.USER_VARIABLE_COUNT)


@dataclass
class Watch:
    """Exact-state recurrence detector.

    Looks only on a grid of ``grid_us`` (a common multiple of the output period and the 100 ms
    timer period) from its start, so two equal looks are also at the same point of both
    cycles; reset when an input or the output period changes.
    """

    start_us: int
    grid_us: int
    seen: dict[int, tuple[int, int]] = field(default_factory=dict)
    """State hash -> (time, instructions executed) of the first look at it."""

    def next_look(self, t_us: int) -> int:
        """Microseconds from ``t_us`` to the next look (0 if ``t_us`` is one)."""
        return -(t_us - self.start_us) % self.grid_us

    def check(self, board: Board, t_us: int) -> tuple[int, int] | None:
        """The time and the board's instruction count of an earlier look at the same state,
        or None."""
        if (t_us - self.start_us) % self.grid_us:
            return None
        key = hash((bytes(board.ram), tuple(board.call_stack)))
        first = self.seen.get(key)
        if first is None:
            self.seen[key] = (t_us, board.instructions_executed)
        return first


def _blocks(board: Board) -> list[int]:
    ram = board.ram
    out = []
    for ics in range(ICS_COUNT):
        blk = read_alloc(ram, ics)
        if blk != NO_BLOCK and blk + SERVO.SIZE <= len(ram):
            out.append(blk)
    return out


def progress_state(board: Board) -> bytes:
    """What a motion changes as it makes progress: every allocated servo block (outputs,
    interpolation, mixing), the loop counters and the user variables. Two looks that differ
    mean progress."""
    ram = board.ram
    parts = [bytes(ram[b : b + SERVO.SIZE]) for b in _blocks(board)]
    parts += [bytes(ram[_COUNTERS]), bytes(ram[_VARIABLES])]
    return b"".join(parts)


def mixed_sensors(board: Board) -> tuple[str, ...]:
    """The AD channels (``AD0``..``AD10``) some allocated servo is mixed from (a RAM mixing
    source inside the AD values, with a non-zero rate), in channel order."""
    ram = board.ram
    channels: set[int] = set()
    for blk in _blocks(board):
        for src_off, method_off in SERVO.MIXES:
            src = read_u16(ram, blk + src_off)
            if src == NO_BLOCK or not mix_rate(ram[blk + method_off]):
                continue
            is_ics, _word, address = mix_source(src)
            if not is_ics and _AD_FIRST <= address < _AD_END:
                channels.add((address - _AD_FIRST) // 2)
    return tuple(f"AD{n}" for n in sorted(channels))
