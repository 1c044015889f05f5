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

__all__ = [
    "FRAME_OVERHEAD_S",
    "READ_FRAME_BYTES",
    "LinkCost",
    "plan_cheapest",
    "plan_reads",
]

MAX_READ: Final = 128
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

    The union of the spans is cut into pieces of at most ``limit`` bytes; a read covers a run
    of consecutive pieces from the first needed byte of the first to the last of the last, if
    that fits ``limit``. Dynamic programming over the pieces gives the cheapest cover (ties:
    fewer frames).
    """
    if limit < 1:
        raise ValueError("limit must be >= 1")
    model = cost if cost is not None else LinkCost()
    pieces: list[tuple[int, int]] = []
    for a, b in _merged(spans):
        while b - a > limit:
            pieces.append((a, a + limit))
            a += limit
        pieces.append((a, b))
    n = len(pieces)
    per_frame = READ_FRAME_BYTES * model.bits_per_byte / model.baud + model.frame_overhead_s
    per_byte = model.bits_per_byte / model.baud
    best: list[tuple[float, int]] = [(0.0, 0)] + [(math.inf, 0)] * n  # (time, frames)
    back = [0] * (n + 1)
    for j in range(1, n + 1):
        end = pieces[j - 1][1]
        for i in range(j, 0, -1):
            extent = end - pieces[i - 1][0]
            if extent > limit:
                break
            t, f = best[i - 1]
            cand = (t + per_frame + extent * per_byte, f + 1)
            if cand < best[j]:
                best[j] = cand
                back[j] = i
    reads: list[tuple[int, int]] = []
    j = n
    while j > 0:
        i = back[j]
        start = pieces[i - 1][0]
        reads.append((start, pieces[j - 1][1] - start))
        j = i - 1
    reads.reverse()
    return reads
