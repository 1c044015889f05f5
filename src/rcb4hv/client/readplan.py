"""Read plans: which MOVE-to-COM frames fetch a set of RAM spans in the least link time.

Every read frame costs the same fixed wire bytes (a 10-byte request, 3 bytes of reply frame
around the data) plus the bytes of its window, and the board spends some time on each frame
whatever its size. :class:`LinkCost` is that model: wire bytes x 11 bits (8E1) at the COM baud,
plus :attr:`LinkCost.frame_overhead_s` per frame. :func:`plan_cheapest` picks the windows
that minimise it: one window over several servos' blocks (few frames, bytes between the fields
read for nothing) or one frame per servo of just the bytes needed (no wasted bytes, more
frames), or any mix. A window of one servo's field costs exactly what ``MOVE Ics(offset,
ics) -> COM`` of those bytes costs, so both plans of the issue are in the search space.

:func:`plan_reads` is the older rule kept for its callers: the fewest frames.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final

from rcb4hv.protocol import MAX_READ

__all__ = [
    "FRAME_OVERHEAD_S",
    "READ_FRAME_BYTES",
    "LinkCost",
    "plan_cheapest",
    "plan_reads",
]

READ_FRAME_BYTES: Final = 13
"""Wire bytes of one read besides its data: the 10-byte MOVE request, SIZE CMD ... SUM of
the reply."""
FRAME_OVERHEAD_S: Final = 150e-6
"""Default board time per frame: the COM timing of the firmware reference (COM section: a
command's bytes must follow each other within 150 µs, so the board may take that long to
see a frame as complete). The reference gives no other per-frame figure; measure a real board
and pass ``LinkCost(frame_overhead_s=...)`` for a better one."""


@dataclass(frozen=True, slots=True)
class LinkCost:
    """Time model of one exchange: ``bytes x bits_per_byte / baud + frame_overhead_s``."""

    baud: int = 1_250_000
    bits_per_byte: int = 11
    frame_overhead_s: float = FRAME_OVERHEAD_S

    def __post_init__(self) -> None:
        if not isinstance(self.baud, int) or self.baud <= 0:
            raise ValueError("baud must be a positive int")
        if not isinstance(self.bits_per_byte, int) or self.bits_per_byte <= 0:
            raise ValueError("bits_per_byte must be a positive int")
        if not math.isfinite(self.frame_overhead_s) or self.frame_overhead_s < 0:
            raise ValueError("frame_overhead_s must be a finite number >= 0")

    def seconds(self, wire_bytes: int, frames: int = 1) -> float:
        """Link time of ``frames`` exchanges moving ``wire_bytes`` in all."""
        return wire_bytes * self.bits_per_byte / self.baud + frames * self.frame_overhead_s

    def read_seconds(self, reads: Iterable[tuple[int, int]]) -> float:
        """Link time of a read plan (``(address, size)`` frames)."""
        sizes = [n for _, n in reads]
        return self.seconds(sum(sizes) + READ_FRAME_BYTES * len(sizes), len(sizes))


def _merged(spans: Iterable[tuple[int, int]]) -> list[list[int]]:
    merged: list[list[int]] = []
    for a, b in sorted((a, a + n) for a, n in spans if n > 0):
        if merged and a <= merged[-1][1]:
            merged[-1][1] = max(merged[-1][1], b)
        else:
            merged.append([a, b])
    return merged


def plan_reads(spans: Iterable[tuple[int, int]], limit: int = MAX_READ) -> list[tuple[int, int]]:
    """Cover the ``(address, size)`` spans with the fewest reads of at most ``limit`` bytes.

    Greedy sweep over the union of the spans: each read starts at the first needed byte not
    yet covered and ends at the last needed byte within ``limit`` (optimal for covering
    points with fixed-length windows).
    """
    if limit < 1:
        raise ValueError("limit must be >= 1")
    merged = _merged(spans)
    reads: list[tuple[int, int]] = []
    i, pos = 0, 0
    while i < len(merged):
        start = max(merged[i][0], pos)
        window_end = start + limit
        last = start
        while i < len(merged) and merged[i][0] < window_end:
            last = min(merged[i][1], window_end)
            if merged[i][1] > window_end:
                break
            i += 1
        reads.append((start, last - start))
        pos = last
    return reads


def plan_cheapest(
    spans: Iterable[tuple[int, int]], cost: LinkCost | None = None, limit: int = MAX_READ
) -> list[tuple[int, int]]:
    """Cover the ``(address, size)`` spans with the reads of least :class:`LinkCost` time.

    A read starts at a needed byte and either ends with the last byte of a run of needed
    bytes (the next read starts at the next run) or is ``limit`` bytes long and ends inside a
    run (the next read goes on from there: stopping earlier inside a run would only add a
    frame). Dynamic programming over those start points gives the cheapest cover (ties:
    fewer frames).
    """
    if limit < 1:
        raise ValueError("limit must be >= 1")
    model = cost if cost is not None else LinkCost()
    runs = _merged(spans)
    n = len(runs)
    per_frame = READ_FRAME_BYTES * model.bits_per_byte / model.baud + model.frame_overhead_s
    per_byte = model.bits_per_byte / model.baud
    # moves[(start, run)]: the reads that may start at byte ``start`` (inside run ``run``),
    # as (window end, next start, next run); every move goes to a later start
    moves: dict[tuple[int, int], list[tuple[int, int, int]]] = {}
    todo = [(runs[0][0], 0)] if runs else []
    while todo:
        state = todo.pop()
        if state in moves:
            continue
        start, j = state
        options = []
        k = j
        while k < n and runs[k][1] - start <= limit:  # ends with run k
            nxt = runs[k + 1][0] if k + 1 < n else runs[k][1]
            options.append((runs[k][1], nxt, k + 1))
            k += 1
        if k < n and runs[k][0] < start + limit:  # a full window ending inside run k
            options.append((start + limit, start + limit, k))
        moves[state] = options
        todo += [(nxt, k) for _, nxt, k in options if k < n]
    # best[state] = (time, frames, window end, next start, next run), latest starts first
    best: dict[tuple[int, int], tuple[float, int, int, int, int]] = {}
    for state in sorted(moves, reverse=True):
        start = state[0]
        choices = []
        for end, nxt, k in moves[state]:
            t, f = best[(nxt, k)][:2] if k < n else (0.0, 0)
            choices.append((t + per_frame + (end - start) * per_byte, f + 1, end, nxt, k))
        best[state] = min(choices)

    reads: list[tuple[int, int]] = []
    start, j = (runs[0][0], 0) if runs else (0, 0)
    while j < n:
        _, _, end, nxt, k = best[(start, j)]
        reads.append((start, end - start))
        start, j = nxt, k
    return reads
