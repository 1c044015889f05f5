"""`make bench` keeps working: every module under bench/ imports, `bench.run` lists every
benchmark module, and one quick pass of all of them runs (``python -m bench.run --quick``:
the shortest run of each figure, results.json untouched). The figures of a quick pass mean
nothing; what is checked is that every benchmark still runs and reports well-formed rows."""

from __future__ import annotations

import importlib
import math
from pathlib import Path
from typing import Any

import bench.run
import pytest

BENCH = Path(bench.run.__file__).resolve().parent


def _modules() -> list[str]:
    return sorted(f"bench.{p.stem}" for p in BENCH.glob("*.py") if p.stem != "__init__")


@pytest.mark.parametrize("name", _modules())
def test_every_bench_module_imports(name: str) -> None:
    importlib.import_module(name)


def test_the_runner_lists_every_benchmark_module() -> None:
    benchmarks = {n for n in _modules() if n.startswith("bench.bench_")}
    assert benchmarks == set(bench.run.MODULES)


def test_a_quick_pass_of_every_benchmark_runs(
    monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    rows: list[dict[str, Any]] = []

    def measure(quick: bool = False) -> list[dict[str, Any]]:
        assert quick
        rows.extend(real(quick=quick))
        return rows

    real = bench.run.measure
    monkeypatch.setattr(bench.run, "measure", measure)
    before = bench.run.RESULTS.read_bytes()
    assert bench.run.main(["--quick"]) == 0
    assert bench.run.RESULTS.read_bytes() == before
    out = capsys.readouterr().out
    assert f"quick pass: {len(rows)} results" in out
    names = [r["name"] for r in rows]
    assert len(names) == len(set(names))
    # every benchmark that needs nothing optional reports (physics, the peer and the browser
    # may be skipped where MuJoCo, rcb4 or Chromium are missing)
    for prefix in (
        "protocol:",
        "emulator in-process:",
        "emulator pty",
        "client/pty:",
        "project:",
        "ui polling:",
    ):
        assert any(n.startswith(prefix) for n in names), prefix
    for r in rows:
        assert r["name"] in out
        for key in ("ours_us", "wire_us", "ratio"):
            assert isinstance(r[key], float | int) and not math.isnan(r[key]), (r["name"], key)
        assert r["wire_us"] > 0, r["name"]


FIXTURE = BENCH.parents[1] / "shared/fixtures/hth4/kxr-l2-hac/HAC_KXR_HTH4_project.h4p"


@pytest.mark.skipif(not FIXTURE.exists(), reason="needs ../shared/fixtures/hth4 beside the repo")
def test_the_sensitivity_study_runs(capsys: pytest.CaptureFixture[str]) -> None:
    """`make sensitivity` plays real motions on the detected model (it once called the robot
    picker with a path where a project goes, and nothing noticed): one figure, two motions."""
    pytest.importorskip("mujoco")
    import bench.sensitivity as sensitivity

    assert sensitivity.main(["--figure", "torque", "--factors", "0.5", "--motion", "21"]) == 0
    out = capsys.readouterr().out
    assert "| 21 | XL2G_201_挨拶 | upright |" in out
    assert "| servo stall torque" in out
