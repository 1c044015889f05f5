"""``project simulate --physics --trace FILE.csv``: the robot's state every output period of
each motion, agreeing with what the report says of it."""

from __future__ import annotations

import csv
import json
from pathlib import Path

from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.project.trace import TRACE_COLUMNS
from tests.physics.conftest import PROJECT

GREETING, STEP_LEFT = 21, 3  # the fixture's XL2G_201 (a bow) and XL2G_103 (fine step left)


def test_the_trace_follows_each_motion_as_the_report_does(tmp_path: Path) -> None:
    trace = tmp_path / "trace.csv"
    res = CliRunner().invoke(
        cli,
        ["project", "simulate", str(PROJECT), "--physics", "--motion", str(GREETING),
         "--motion", str(STEP_LEFT), "--json", "--trace", str(trace)],
    )  # fmt: skip
    assert res.exit_code == 0, res.output
    report = {m["slot"]: m["physics"] for m in json.loads(res.output)["motions"]}
    with trace.open(newline="") as f:
        rows = list(csv.DictReader(f))
    header = list(rows[0])
    assert header[: len(TRACE_COLUMNS)] == list(TRACE_COLUMNS)
    assert "l_knee_pitch_deg" in header and "r_ankle_roll_deg" in header
    by_slot = {s: [r for r in rows if r["slot"] == str(s)] for s in (GREETING, STEP_LEFT)}
    for slot, track in by_slot.items():
        times = [float(r["t_s"]) for r in track]
        assert times[0] < 0.05 and times == sorted(times) and times[-1] > 1.0, slot
        tilt = max(float(r["tilt_deg"]) for r in track)
        assert abs(tilt - report[slot]["max_tilt_deg"]) < 0.2, slot
    # a bow leans forward, not back or sideways
    bow = by_slot[GREETING]
    assert max(float(r["lean_forward_deg"]) for r in bow) > 30.0
    assert min(float(r["lean_forward_deg"]) for r in bow) > -5.0
    assert max(abs(float(r["lean_right_deg"])) for r in bow) < 1.0
    # the step left ends where the report says, left of where it started
    step = by_slot[STEP_LEFT]
    moved = float(step[-1]["y_m"]) - float(step[0]["y_m"])
    assert moved > 0.05 and abs(moved - report[STEP_LEFT]["dy_m"]) < 0.01
    # the bow stands on both feet throughout; the steps lift one foot, then the other
    assert {r["touching"] for r in bow} == {"l_foot r_foot"}
    stood_on = {r["touching"] for r in step}
    assert {"l_foot", "r_foot", "l_foot r_foot"} <= stood_on
    # the bow keeps its centre of mass well inside its feet (33-52 mm on this model); the
    # step shifts it over one foot and on past its edge as it tips onto the other
    assert all(float(r["com_margin_mm"]) > 20.0 for r in bow)
    assert all(0.12 < float(r["com_z_m"]) < 0.16 for r in bow)
    assert min(float(r["com_margin_mm"]) for r in step) < 0.0
    # each joint follows the angle the board commands it to, a servo's lag behind
    assert "l_knee_pitch_target_deg" in header
    for r in bow:
        for j in ("l_knee_pitch", "r_hip_pitch", "l_shoulder_pitch"):
            assert abs(float(r[f"{j}_deg"]) - float(r[f"{j}_target_deg"])) < 15.0, (j, r["t_s"])
    bent = min(float(r["l_hip_pitch_target_deg"]) for r in bow)
    assert bent < -40.0  # the bow bends at the hips (-50.6°): the targets are the board's


def test_a_trace_needs_the_simulated_robot(tmp_path: Path) -> None:
    res = CliRunner().invoke(
        cli, ["project", "simulate", str(PROJECT), "--motion", "21", "--trace", "t.csv"]
    )
    assert res.exit_code == 2 and "add --physics" in res.output


def test_the_filmstrip_counts_time_from_the_motions_start() -> None:
    """`--plot`'s filmstrip labelled motion 13's frames 2.93-7.27 s (board time, the boot and
    settling included) where `--trace` counts from the motion's start (0-4.34 s)."""
    from rcb4hv.cli.project_physics import draw_frames
    from rcb4hv.project.physicsresult import ShapeFrame

    class Axes:
        def __init__(self) -> None:
            self.labels: list[str] = []

        def annotate(self, text: str, *args: object, **kwargs: object) -> None:
            self.labels.append(text)

        def __getattr__(self, name: str) -> object:
            return lambda *a, **k: None

    ax = Axes()
    draw_frames(ax, (ShapeFrame(2.934, ()), ShapeFrame(3.184, ())), t0=2.934)
    assert ax.labels == ["0.00 s", "0.25 s"]
