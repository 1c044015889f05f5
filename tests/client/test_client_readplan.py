"""Read plans: plan_cheapest against brute force, its cost model, and the plans it picks."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv.client import FRAME_OVERHEAD_S, LinkCost, plan_cheapest, plan_reads
from rcb4hv.client.readplan import READ_FRAME_BYTES

BLOCKS17 = [0x90 + 20 * k for k in (0, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19)]


def _covers(reads: list[tuple[int, int]], spans: list[tuple[int, int]], limit: int) -> bool:
    return all(1 <= n <= limit for _, n in reads) and all(
        any(r <= b < r + m for r, m in reads) for a, n in spans for b in range(a, a + n)
    )


def _brute_force(spans: list[tuple[int, int]], cost: LinkCost, limit: int) -> float:
    """Cheapest cover by trying every way to cut the sorted needed bytes into windows."""
    needed = sorted({b for a, n in spans for b in range(a, a + n)})
    best = float("inf")
    for cuts in itertools.product((False, True), repeat=len(needed) - 1):
        groups: list[list[int]] = [[needed[0]]]
        for b, cut in zip(needed[1:], cuts, strict=True):
            if cut:
                groups.append([b])
            else:
                groups[-1].append(b)
        if any(g[-1] - g[0] + 1 > limit for g in groups):
            continue
        best = min(best, cost.read_seconds([(g[0], g[-1] - g[0] + 1) for g in groups]))
    return best


@settings(max_examples=150, deadline=None)
@given(
    st.lists(st.tuples(st.integers(0, 60), st.integers(1, 3)), min_size=1, max_size=5),
    st.integers(4, 40),
    st.sampled_from([0.0, 20e-6, FRAME_OVERHEAD_S, 1e-3]),
)
def test_plan_cheapest_is_optimal_against_brute_force(
    spans: list[tuple[int, int]], limit: int, overhead: float
) -> None:
    needed = {b for a, n in spans for b in range(a, a + n)}
    if len(needed) > 12:
        spans = spans[:2]
    cost = LinkCost(frame_overhead_s=overhead)
    reads = plan_cheapest(spans, cost, limit)
    assert _covers(reads, spans, limit)
    assert cost.read_seconds(reads) == pytest.approx(_brute_force(spans, cost, limit))


@settings(max_examples=150, deadline=None)
@given(
    st.lists(st.tuples(st.integers(0x90, 0x400), st.integers(1, 40)), min_size=1, max_size=30),
    st.integers(8, 128),
    st.floats(0, 2e-3),
)
def test_plan_cheapest_never_costs_more_than_the_simple_plans(
    spans: list[tuple[int, int]], limit: int, overhead: float
) -> None:
    cost = LinkCost(frame_overhead_s=overhead)
    reads = plan_cheapest(spans, cost, limit)
    assert _covers(reads, spans, limit)
    assert cost.read_seconds(reads) <= cost.read_seconds(plan_reads(spans, limit)) + 1e-12


def test_servo_positions_plan_follows_the_frame_overhead() -> None:
    spans = [(b + 4, 2) for b in BLOCKS17]
    # no board time per frame: one 2-byte read per servo (15 wire bytes each)
    free = plan_cheapest(spans, LinkCost(frame_overhead_s=0.0))
    assert free == spans
    # the reference's 150 µs per frame: windows over several blocks, cheaper than the fewest
    # frames (3 x 128-byte windows) and than one frame per servo
    default = LinkCost()
    plan = plan_cheapest(spans)
    assert plan == plan_cheapest(spans, default)
    assert len(spans) > len(plan) > len(plan_reads(spans))
    assert default.read_seconds(plan) < default.read_seconds(plan_reads(spans))
    assert default.read_seconds(plan) < default.read_seconds(spans)
    # a very slow board: the fewest frames
    assert len(plan_cheapest(spans, LinkCost(frame_overhead_s=0.01))) == len(plan_reads(spans))


def test_link_cost_model() -> None:
    cost = LinkCost(baud=1_250_000, frame_overhead_s=0.0)
    assert cost.seconds(125) == pytest.approx(125 * 11 / 1_250_000)
    assert cost.read_seconds([(0x92, 126)]) == pytest.approx((126 + READ_FRAME_BYTES) * 8.8e-6)
    assert LinkCost().seconds(0, 2) == pytest.approx(2 * FRAME_OVERHEAD_S)
    assert plan_cheapest([]) == []
    for bad in (
        {"baud": 0},
        {"bits_per_byte": 0},
        {"frame_overhead_s": -1.0},
        {"frame_overhead_s": float("nan")},
    ):
        with pytest.raises(ValueError):
            LinkCost(**bad)  # type: ignore[arg-type]
    with pytest.raises(ValueError):
        plan_cheapest([(0, 1)], limit=0)


def test_long_spans_are_cut_to_the_read_limit() -> None:
    reads = plan_cheapest([(0, 700)], LinkCost(frame_overhead_s=0.0))
    assert _covers(reads, [(0, 700)], 128)
    assert len(reads) == 6
