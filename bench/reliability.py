"""`make reliability`: the long versions of the reliability scenarios, with a table of figures.

Runs (bounded to a few minutes on 2 cores, loopback only): the fast mutation fuzzer over the
fixture project's real frames (``tests/reliability/fastfuzz.py``, a million inputs over every
CPU), the emulator fuzz properties (hypothesis), the link-fault matrix over TCP, SIGKILL
cycles of ``rcb4hv emulate --rom``, and load on the TCP and pty servers (sequential clients,
stalled and flooding clients, a soak of valid traffic). The scenario code is shared with the
test suite: tests/reliability/scenarios.py and tests/reliability/fastfuzz.py.

Environment overrides: RCB4HV_REL_MUTATIONS (fast fuzzer inputs), RCB4HV_REL_FUZZ (examples
per property), RCB4HV_REL_KILLS (kill cycles), RCB4HV_REL_SOAK (soak seconds),
RCB4HV_REL_FAULT_ROUNDS.
"""

from __future__ import annotations

import logging
import os
import sys
import tempfile
import time
from pathlib import Path

from tests.reliability import fastfuzz
from tests.reliability import scenarios as sc


def _env(name: str, default: int) -> int:
    return int(os.environ.get(name, str(default)))


def _row(rows: list[tuple[str, str, str]], what: str, value: object, verdict: str = "") -> None:
    rows.append((what, str(value), verdict))
    print(f"  {what:<44} {value!s:>16}  {verdict}", flush=True)


def _ok(flag: bool) -> str:
    return "ok" if flag else "FAIL"


def main() -> int:
    logging.basicConfig(level=logging.CRITICAL)  # the client logs discarded junk as warnings
    mutations = _env("RCB4HV_REL_MUTATIONS", 1_000_000)
    fuzz_examples = _env("RCB4HV_REL_FUZZ", 2000)
    kills = _env("RCB4HV_REL_KILLS", 25)
    soak_s = _env("RCB4HV_REL_SOAK", 30)
    fault_rounds = _env("RCB4HV_REL_FAULT_ROUNDS", 4)
    rows: list[tuple[str, str, str]] = []
    failed = False
    t_start = time.monotonic()

    print(f"fast fuzz: {mutations} mutated real frames ...", flush=True)
    ff = fastfuzz.fuzz_parallel(mutations, seed=1)
    _row(rows, "fast fuzz inputs (bytes)", f"{ff.inputs} ({ff.bytes_fed})")
    _row(rows, "fast fuzz inputs per second", f"{ff.rate:,.0f}")
    _row(
        rows,
        "fast fuzz decoded / frames / board replies",
        f"{ff.decoded} / {ff.frames} / {ff.replies}",
    )
    _row(rows, "fast fuzz crashes", len(ff.crashes), _ok(not ff.crashes))
    for crash in ff.crashes:
        print("    ", crash)
    failed |= bool(ff.crashes)

    print(f"fuzz: {fuzz_examples} examples per property ...", flush=True)
    fz = sc.run_fuzz_budget(fuzz_examples, memory_iterations=20000)
    _row(rows, "inputs fuzzed (bytes)", f"{fz.inputs} ({fz.bytes_fed})")
    _row(rows, "crashes / property failures", len(fz.crashes), _ok(not fz.crashes))
    _row(
        rows,
        "memory growth over 20000 inputs",
        f"{fz.memory_growth} B",
        _ok(fz.memory_growth < 64 * 1024),
    )
    for crash in fz.crashes:
        print("    ", crash)
    failed |= bool(fz.crashes) or fz.memory_growth >= 64 * 1024

    print(f"link faults: {fault_rounds} rounds of {len(sc.FAULT_SCENARIOS)} scenarios ...")
    outcomes = sc.run_fault_matrix(rounds=fault_rounds, seed=11)
    passed = sum(o.ok for o in outcomes)
    worst = max(o.elapsed for o in outcomes)
    _row(
        rows,
        "fault scenarios run / passed",
        f"{len(outcomes)} / {passed}",
        _ok(passed == len(outcomes)),
    )
    _row(
        rows,
        "slowest failing call (timeout 0.25 s)",
        f"{worst:.3f} s",
        _ok(worst <= 0.25 + sc.SLACK),
    )
    for o in outcomes:
        if not o.ok:
            print("    ", o.scenario, o.why)
    failed |= passed != len(outcomes)

    print(f"ROM crash safety: {kills} SIGKILL cycles ...", flush=True)
    with tempfile.TemporaryDirectory(prefix="rcb4hv-rel-") as tmp:
        ks = sc.run_kill_cycles(Path(tmp) / "board.rom", kills, seed=3, max_delay=1.0)
    _row(rows, "kill/restart cycles", ks.cycles)
    _row(rows, "64-byte pages checked / persisted", f"{ks.pages_checked} / {ks.pages_persisted}")
    _row(
        rows,
        "torn pages / bytes changed outside",
        f"{ks.torn_pages} / {ks.outside_changed}",
        _ok(ks.torn_pages == 0 and ks.outside_changed == 0),
    )
    _row(rows, "boot failures after restart", ks.boot_failures, _ok(ks.boot_failures == 0))
    _row(rows, "stale temp files left by kills", ks.stale_temp_files)
    for problem in ks.problems:
        print("    ", problem)
    failed |= bool(ks.problems) or ks.torn_pages > 0

    print(f"server load (soak {soak_s} s) ...", flush=True)
    connections = 0
    peak_rss = 0
    load_problems: list[str] = []
    with sc.EmulatorProcess("--tcp", "127.0.0.1:0", "--speed", "5") as emu:
        runs = [("tcp sequential", sc.tcp_sequential(emu, 1000))]
        runs += [("tcp stalled", sc.tcp_stalled_client(emu, 0.2)) for _ in range(5)]
        runs += [("tcp flood", sc.tcp_flooding_client(emu, 1.0, seed=i)) for i in range(3)]
        soak = sc.soak(emu, float(soak_s))
        runs.append(("soak", soak))
        fd_growth = emu.fd_count() - runs[0][1].fd_before
    with sc.EmulatorProcess("--pty", "--speed", "5") as pty_emu:
        runs.append(("pty sequential", sc.pty_sequential(pty_emu, 300)))
    for name, st in runs:
        connections += st.connections
        peak_rss = max(peak_rss, st.rss_peak_kb, st.rss_after_kb)
        load_problems += [f"{name}: {x}" for x in sc.check_load(st)]
    seq = runs[0][1]
    _row(rows, "connections served (TCP + pty)", connections, _ok(not load_problems))
    _row(rows, "sequential TCP connect+ACK p99", f"{seq.p99() * 1000:.2f} ms")
    _row(
        rows,
        "soak calls (frames) / failures",
        f"{len(soak.latencies)} / {soak.failures}",
        _ok(soak.failures == 0),
    )
    _row(
        rows,
        "soak p99 / max latency",
        f"{soak.p99() * 1000:.2f} / {max(soak.latencies) * 1000:.1f} ms",
        _ok(soak.p99() < 0.05),
    )
    _row(rows, "server fd growth (TCP run)", fd_growth, _ok(fd_growth <= 0))
    _row(
        rows,
        "server RSS soak start / end / peak",
        f"{soak.rss_before_kb} / {soak.rss_after_kb} / {peak_rss} kB",
    )
    for problem in load_problems:
        print("    ", problem)
    failed |= bool(load_problems) or fd_growth > 0

    total = time.monotonic() - t_start
    print(f"\nrcb4hv reliability, {total:.0f} s\n")
    print("| figure | value | verdict |")
    print("|---|---|---|")
    for what, value, verdict in rows:
        print(f"| {what} | {value} | {verdict} |")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
