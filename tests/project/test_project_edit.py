"""Edited projects end to end: ``project mirror`` / ``project diff`` on the fixture, and the
saved file reloads, round-trips, builds, simulates and checks as well as the original."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv import hth4
from rcb4hv.cli import edit_cmd
from rcb4hv.cli.main import cli
from rcb4hv.hth4.edit import set_pose
from rcb4hv.hth4.poses import motion_poses
from rcb4hv.hth4.session import EditSession
from rcb4hv.project.check import check_project
from rcb4hv.project.image import build_project_image
from rcb4hv.project.simulate import Simulator
from tests.hth4._model import kxr_like

WALK, TURN_LEFT, TURN_RIGHT, FREE = 66, 69, 70, 73


@pytest.fixture
def model(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(edit_cmd, "project_model", lambda project, name=None: kxr_like())


def _edit(src: Path, out: Path) -> Path:
    """Change one pose of WALK (API), then mirror TURN_LEFT into FREE (CLI)."""
    s = EditSession.open(src)
    s.apply(set_pose, WALK, 1, {10: 7700})
    edited = s.save(out.with_name("step1.h4p"))
    r = CliRunner().invoke(
        cli,
        [
            "project",
            "mirror",
            str(edited),
            "--motion",
            str(TURN_LEFT),
            "--to",
            str(FREE),
            "--name",
            "TURN_RIGHT_MIRROR",
            "-o",
            str(out),
        ],
    )
    assert r.exit_code == 0, r.output
    assert f"motion {TURN_LEFT} mirrored slot {FREE}" in r.output
    return out


def test_edit_diff_build_simulate(kxr_project_path: Path, tmp_path: Path, model: None) -> None:
    out = _edit(kxr_project_path, tmp_path / "edited.h4p")
    r = CliRunner().invoke(cli, ["project", "diff", str(kxr_project_path), str(out), "--json"])
    assert r.exit_code == 1, r.output
    changes = json.loads(r.output)["changes"]
    assert [(c["kind"], c["slot"], c.get("pose"), c.get("ics")) for c in changes] == [
        ("pose-servo", WALK, 2, 10),
        ("motion-added", FREE, None, None),
    ]
    text = CliRunner().invoke(cli, ["project", "diff", str(kxr_project_path), str(out)])
    assert text.exit_code == 1
    assert text.output.splitlines() == [c["text"] for c in changes]
    same = CliRunner().invoke(cli, ["project", "diff", str(out), str(out), "--json"])
    assert same.exit_code == 0 and json.loads(same.output) == {"changes": []}

    data = out.read_bytes()
    project = hth4.parse_project(data)
    assert hth4.dump_project(project) == data
    original = hth4.load_project(kxr_project_path)
    assert motion_poses(project.motion(FREE)) == motion_poses(original.motion(TURN_RIGHT))
    image = build_project_image(project)
    sim = Simulator(image)
    assert sim.boot().status == "completed"
    results = sim.play_all([(s, project.motion(s).name or "") for s in (WALK, FREE, TURN_RIGHT)])
    assert [r.status for r in results] == ["completed"] * 3, results
    # the mirror takes as long as the fixture's own turn right, within one 15 ms output
    # period (where the play starts in the period differs)
    assert results[1].duration == pytest.approx(results[2].duration, abs=0.015)
    errors = [f for f in check_project(project) if f.severity == "error"]
    assert len(errors) <= len([f for f in check_project(original) if f.severity == "error"])


def test_mirror_cli_refuses_without_model(
    kxr_project_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from rcb4hv.errors import NoRobotModelError

    def none(project: hth4.Project, name: str | None = None) -> None:
        raise NoRobotModelError("no built-in robot model matches this project's servos")

    monkeypatch.setattr(edit_cmd, "project_model", none)
    out = tmp_path / "x.h4p"
    r = CliRunner().invoke(
        cli,
        [
            "project",
            "mirror",
            str(kxr_project_path),
            "--motion",
            "69",
            "--to",
            "73",
            "-o",
            str(out),
        ],
    )
    assert r.exit_code == 1 and "no built-in robot model" in r.output
    assert not out.exists()
