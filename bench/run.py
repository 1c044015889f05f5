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
)

RESULTS = Path(__file__).resolve().parent / "results.json"


def main() -> int:
    results: list[dict[str, Any]] = []
    for name in MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name == name:
                print(f"(skipping {name}: not present)")
                continue
            raise
        results.extend(module.run())
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
