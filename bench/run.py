"""`make bench`: run every benchmark module, print a table of ratios, write bench/results.json.

Each module in MODULES defines ``run() -> list[dict]`` with keys ``name``, ``ours_us``,
``wire_us`` (the reference time the figure is compared with, e.g. the wire time at
1,250,000 baud or the real duration), ``ratio`` (ours / reference) and optionally
``target`` (the ratio we aim for) and ``note``. Rows measured against the peer library (PyPI
``rcb4`` 0.1.6, ``bench.bench_peer``) also carry ``peer_us`` (the peer's figure for the same
work), ``peer_ratio`` (ours / peer) and ``peer_target``; they are printed again as a peer
table. All figures come from one run, side by side.
"""

from __future__ import annotations

import argparse
import importlib
import json
import platform
import sys
from pathlib import Path
from typing import Any

MODULES = (
    "bench.bench_protocol",
    "bench.bench_emulator",
    "bench.bench_client",
    "bench.bench_project",
    "bench.bench_physics",
    "bench.bench_peer",
    "bench.bench_ui",
    "bench.bench_view3d",
    "bench.bench_ik",
    "bench.bench_robust",
)

RESULTS = Path(__file__).resolve().parent / "results.json"


def measure(quick: bool = False) -> list[dict[str, Any]]:
    """Every module's rows, in MODULES order. ``quick``: each module runs its shortest pass
    (a round or a few calls per figure; the figures mean nothing, the pass shows that every
    benchmark still runs: the test suite does it)."""
    results: list[dict[str, Any]] = []
    for name in MODULES:
        module = importlib.import_module(name)
        results.extend(module.run(quick=quick))
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.run", description=__doc__)
    parser.add_argument(
        "--quick",
        action="store_true",
        help="the shortest pass of every benchmark (figures meaningless; results.json untouched)",
    )
    args = parser.parse_args(argv)
    results = measure(quick=args.quick)
    print(f"\nrcb4hv benchmarks on Python {platform.python_version()} ({platform.machine()})\n")
    print(f"{'benchmark':<58} {'ours µs':>11} {'reference µs':>13} {'ratio':>9} {'target':>8}")
    failed = 0
    for r in results:
        target = r.get("target")
        mark = ""
        if target is not None:
            ok = r["ratio"] <= target if r.get("lower_is_better", True) else r["ratio"] >= target
            mark = "" if ok else "  (misses target)"
            failed += 0 if ok else 1
        tgt = (
            ""
            if target is None
            else f"{'<=' if r.get('lower_is_better', True) else '>='}{target:g}"
        )
        print(
            f"{r['name']:<58} {r['ours_us']:>11.2f} {r['wire_us']:>13.2f} {r['ratio']:>9.4g} "
            f"{tgt:>8}{mark}"
        )
    failed += _peer_table(results)
    if args.quick:
        print(f"\nquick pass: {len(results)} results, {RESULTS} left as it was")
        return 0
    RESULTS.write_text(json.dumps(results, indent=2) + "\n")
    print(f"\nwrote {RESULTS} ({len(results)} results; {failed} miss their target)")
    return 0


def _peer_table(results: list[dict[str, Any]]) -> int:
    """Print the rows measured against the peer library; return how many miss peer_target."""
    rows = [r for r in results if "peer_us" in r]
    if not rows:
        return 0
    print("\nagainst the peer library, rcb4 0.1.6 (same frames, same process, interleaved)\n")
    print(f"{'per call':<66} {'ours µs':>10} {'rcb4 µs':>10} {'ratio':>7} {'target':>8}")
    missed = 0
    for r in rows:
        target = r.get("peer_target")
        ok = target is None or r["peer_ratio"] <= target
        missed += 0 if ok else 1
        tgt = "" if target is None else f"<={target:g}"
        print(
            f"{r['name']:<66} {r['ours_us']:>10.2f} {r['peer_us']:>10.2f} "
            f"{r['peer_ratio']:>7.3f} {tgt:>8}{'' if ok else '  (misses target)'}"
        )
    return missed


if __name__ == "__main__":
    sys.exit(main())
