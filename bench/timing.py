"""Side-by-side timing: several callables measured in interleaved rounds, medians reported.

The machine running the benchmarks may be busy (2 cores shared with other jobs), so one
tight loop per callable would compare figures taken minutes apart under different loads.
:func:`interleaved` instead runs every callable once per round, in a rotating order, for many
rounds, and reports the median per-call time of each: a load burst hits all of them alike.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable, Mapping

BAUD = 1_250_000
BITS_PER_BYTE = 11


def wire_us(nbytes: int, baud: int = BAUD) -> float:
    """Time ``nbytes`` take on the link: 11 bits a byte (8E1)."""
    return nbytes * BITS_PER_BYTE / baud * 1e6


def _calls_for(fn: Callable[[], object], budget_s: float) -> int:
    """How many calls of ``fn`` take about ``budget_s`` (at least 1)."""
    fn()
    n = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        elapsed = time.perf_counter() - t0
        if elapsed >= budget_s / 4 or n >= 1 << 20:
            return max(1, int(n * budget_s / max(elapsed, 1e-9)))
        n *= 4


QUICK_ROUND_S = 0.001
"""The round length of a quick pass (``python -m bench.run --quick``, run by the tests): the
figures mean nothing, the pass only shows that every benchmark still runs."""


def interleaved(
    fns: Mapping[str, Callable[[], object]],
    rounds: int = 15,
    round_s: float = 0.02,
    *,
    quick: bool = False,
) -> dict[str, float]:
    """Median µs per call of each of ``fns``, over ``rounds`` interleaved rounds.

    Each round runs every callable for about ``round_s`` seconds (a calibrated number of
    calls), the order rotating from round to round. ``quick``: one short round.
    """
    if quick:
        rounds, round_s = 1, QUICK_ROUND_S
    names = list(fns)
    counts = {name: _calls_for(fns[name], round_s) for name in names}
    samples: dict[str, list[float]] = {name: [] for name in names}
    for r in range(rounds):
        order = names[r % len(names) :] + names[: r % len(names)]
        for name in order:
            fn, n = fns[name], counts[name]
            t0 = time.perf_counter()
            for _ in range(n):
                fn()
            samples[name].append((time.perf_counter() - t0) / n * 1e6)
    return {name: statistics.median(v) for name, v in samples.items()}
