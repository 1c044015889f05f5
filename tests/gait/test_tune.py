"""`gait tune`'s progress and Ctrl-C: the library reports each candidate and keeps the best
so far when interrupted; the CLI draws a bar on a terminal only, and on Ctrl-C stores the
best walk so far, reports it as interrupted and exits with 130. The trials are stand-ins
(no physics, no clock): only the walks are generated."""

from __future__ import annotations

import io
import json
import multiprocessing
import signal
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.gait.generate import default_params
from rcb4hv.gait.tune import TuneProgress, tune
from rcb4hv.hth4 import load_project
from rcb4hv.project import robust as robust_module
from rcb4hv.robot.builtin import load_builtin

pytest.importorskip("cma")  # the [scale] extra, which `make test` installs

KXR = load_builtin("kxr-l2")
BASE = default_params(KXR, "forward", steps=1)
FALLS = [0.5, 0.125, 0.25, 0.75, 0.5, 0.5, 0.5, 0.5]
"""The stand-in's fall probability of the 1st, 2nd, ... candidate (the 2nd is the best)."""


def trials(
    falls: list[float], interrupt_at: int | None = None
) -> Callable[..., list[dict[str, Any]]]:
    """A stand-in for ``robust``: candidate i falls with ``falls[i]`` and travels the command;
    the call for candidate ``interrupt_at`` (0-based) raises KeyboardInterrupt (Ctrl-C)."""
    calls = iter(range(len(falls)))

    def run(*_a: Any, **_k: Any) -> list[dict[str, Any]]:
        i = next(calls)
        if i == interrupt_at:
            raise KeyboardInterrupt
        return [{"fall_probability": falls[i], "dx_m": {"median": BASE.commanded}}]

    return run


def test_progress_is_told_each_candidate_with_the_best_so_far() -> None:
    seen: list[TuneProgress] = []
    result = tune(KXR, BASE, trials=1, evaluations=1, run=trials(FALLS), progress=seen.append)
    assert [p.done for p in seen] == [1, 2, 3, 4]  # one generation: the smallest budget
    assert {p.total for p in seen} == {4} and result.planned == 4
    assert [p.latest for p in seen] == result.tried
    assert [p.best.fall_probability for p in seen] == [0.5, 0.125, 0.125, 0.125]
    assert not result.interrupted and result.best is result.tried[1]


def test_ctrl_c_in_the_callback_returns_the_best_so_far_marked_interrupted() -> None:
    def progress(p: TuneProgress) -> None:
        if p.done == 3:
            raise KeyboardInterrupt

    result = tune(KXR, BASE, trials=1, evaluations=8, run=trials(FALLS), progress=progress)
    assert result.interrupted and len(result.tried) == 3 and result.planned == 8
    assert result.best is result.tried[1] and result.best.fall_probability == 0.125


def test_ctrl_c_before_any_candidate_returns_no_best() -> None:
    result = tune(KXR, BASE, trials=1, evaluations=4, run=trials(FALLS, interrupt_at=0))
    assert result.interrupted and result.tried == [] and result.best is None


@pytest.fixture
def ctrl_c_at(monkeypatch: pytest.MonkeyPatch) -> Callable[[int | None], None]:
    """Make the CLI's trials the stand-in, Ctrl-C at that candidate (None: never)."""

    def at(candidate: int | None) -> None:
        monkeypatch.setattr(robust_module, "robust", trials(FALLS, candidate))

    return at


TUNE = ["gait", "tune", "--robot", "kxr-l2", "--steps", "1", "--trials", "1"]


def test_the_cli_on_ctrl_c_stores_and_reports_the_best_so_far_and_exits_130(
    tmp_path: Path, ctrl_c_at: Callable[[int | None], None]
) -> None:
    out, report = tmp_path / "t.h4p", tmp_path / "t.json"
    ctrl_c_at(2)
    r = CliRunner().invoke(
        cli, [*TUNE, "--evaluations", "8", "--into", str(out), "--report", str(report)]
    )
    assert r.exit_code == 130, r.output
    assert "motion 2: best of 2 (interrupted after 2 of 8 evaluations): falls 0.12" in r.stdout
    assert load_project(out).motion(2).name == "tuned forward"
    doc = json.loads(report.read_text())
    assert doc["interrupted"] is True and doc["evaluations"] == 2
    assert doc["best"]["fall_probability"] == 0.125 and len(doc["candidates"]) == 2


def test_the_cli_on_ctrl_c_before_any_walk_writes_nothing(
    tmp_path: Path, ctrl_c_at: Callable[[int | None], None]
) -> None:
    out, report = tmp_path / "t.h4p", tmp_path / "t.json"
    args = ["--evaluations", "1", "--into", str(out), "--report", str(report)]
    ctrl_c_at(0)
    r = CliRunner().invoke(cli, [*TUNE, *args])
    assert r.exit_code == 130, r.output
    assert "interrupted after 0 of 4 evaluations: no walk evaluated" in r.stderr
    assert not out.exists() and not report.exists()
    ctrl_c_at(None)  # a project that exists is left as it was
    assert CliRunner().invoke(cli, [*TUNE, *args]).exit_code == 0
    before = out.read_bytes()
    ctrl_c_at(0)
    assert CliRunner().invoke(cli, [*TUNE, *args]).exit_code == 130
    assert out.read_bytes() == before


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("terminal", [True, False])
def test_a_bar_on_a_terminal_none_in_a_log(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    ctrl_c_at: Callable[[int | None], None],
    terminal: bool,
) -> None:
    """The rule of `project robust`'s bar: on stderr when it is a terminal, else nothing."""
    err = Terminal() if terminal else io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    ctrl_c_at(None)
    args = [*TUNE, "--evaluations", "1", "--into", str(tmp_path / "t.h4p")]
    cli.main(args, prog_name="rcb4hv", standalone_mode=False)
    drawn = "0/4 [" in err.getvalue() and "walk" in err.getvalue()
    assert drawn == terminal, err.getvalue()


def _sigint_ignored(_job: int) -> bool:
    return signal.getsignal(signal.SIGINT) == signal.SIG_IGN


def _nap(mark: Path) -> None:
    time.sleep(0.05)
    mark.touch()


def test_pool_workers_leave_ctrl_c_to_the_parent() -> None:
    """A terminal's Ctrl-C reaches every process of the group: an idle pool worker printed
    a KeyboardInterrupt traceback under the report."""
    assert robust_module._run_pool(_sigint_ignored, [0, 1], 2, None) == [True, True]


def test_ctrl_c_stops_the_pool_and_joins_its_processes(tmp_path: Path) -> None:
    """(A guard: the pool did this before, through the map's clean-up.)"""
    done: list[int] = []

    def progress(_n: int) -> None:
        done.append(1)
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        robust_module._run_pool(_nap, [tmp_path / f"{i}" for i in range(40)], 2, progress)
    assert done == [1] and multiprocessing.active_children() == []
    assert len(list(tmp_path.iterdir())) < 10  # the queued trials were dropped


def test_ctrl_c_cancels_the_ray_tasks_not_yet_done(monkeypatch: pytest.MonkeyPatch) -> None:
    """A stand-in for Ray (a real one takes seconds to start): Ctrl-C after the first result
    cancels the other tasks (they ran on, on the cluster, until the driver exited)."""
    from types import SimpleNamespace

    from rcb4hv.project import robust_ray

    cancelled: list[int] = []

    def remote(fn: Callable[[int], int]) -> Any:
        return SimpleNamespace(remote=lambda job: job)  # a task's ref: its job

    fake = SimpleNamespace(
        is_initialized=lambda: True,
        remote=remote,
        wait=lambda refs, num_returns: (refs[:num_returns], refs[num_returns:]),
        get=lambda ref: ref,
        cancel=cancelled.append,
    )
    monkeypatch.setattr(robust_ray, "require_ray", lambda: fake)

    def progress(_n: int) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        robust_ray.run_ray(lambda j: j, [0, 1, 2, 3], None, progress)
    assert cancelled == [1, 2, 3]
