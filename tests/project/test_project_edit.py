"""Edited projects end to end: ``project mirror`` / ``project diff`` on the fixture, and the
saved file reloads, round-trips, builds, simulates and checks as well as the original."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv import hth4
from rcb4hv.cli.main import cli
from rcb4hv.hth4.edit import set_pose
from rcb4hv.hth4.poses import motion_poses
from rcb4hv.hth4.session import EditSession
from rcb4hv.project.check import check_project
from rcb4hv.project.image import build_project_image
from rcb4hv.project.run import run_motions

WALK, TURN_LEFT, TURN_RIGHT, FREE = 66, 69, 70, 73


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
    # the robot is detected from the servo table: the fixture is a KXR-L2 with grippers
    assert (
        f"motion {TURN_LEFT} mirrored slot {FREE} as 'TURN_RIGHT_MIRROR' (kxr-l2-gripper)"
        in r.output
    )
    return out


def test_edit_diff_build_simulate(kxr_project_path: Path, tmp_path: Path) -> None:
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
    run = run_motions(image, (WALK, FREE, TURN_RIGHT))
    assert run.boot.status == "completed"
    results = run.results
    assert [r.status for r in results] == ["completed"] * 3, results
    # the mirror takes as long as the fixture's own turn right, within one 15 ms output
    # period (where the play starts in the period differs)
    assert results[1].duration == pytest.approx(results[2].duration, abs=0.015)
    errors = [f for f in check_project(project) if f.severity == "error"]
    assert len(errors) <= len([f for f in check_project(original) if f.severity == "error"])


def test_mirror_cli_refuses_without_model(kxr_project_path: Path, tmp_path: Path) -> None:
    # a project whose servo table matches no built-in model (one servo less) and whose servo
    # names say nothing (with Kondo's names it is a KXR kit model: rcb4hv.robot.kit)
    p = hth4.load_project(kxr_project_path)
    odd = tmp_path / "odd.h4p"
    servos = tuple(replace(s, name="") for s in p.servos if s.device_number != 19)
    hth4.save_project(replace(p, servos=servos), odd)
    kxr_project_path = odd
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


def test_mirror_cli_with_a_named_robot_and_in_place(kxr_project_path: Path, tmp_path: Path) -> None:
    once, twice = tmp_path / "once.h4p", tmp_path / "twice.h4p"
    for src, dst in ((kxr_project_path, once), (once, twice)):
        r = CliRunner().invoke(
            cli,
            ["project", "mirror", str(src), "--motion", "42", "--robot", "kxr-l2-gripper",
             "--force", "-o", str(dst)],
        )  # fmt: skip
        assert r.exit_code == 0, r.output
    assert once.read_bytes() != kxr_project_path.read_bytes()
    assert twice.read_bytes() == kxr_project_path.read_bytes()
    r = CliRunner().invoke(
        cli, ["project", "mirror", str(once), "--motion", "42", "--robot", "nao", "-o", str(twice)]
    )
    assert r.exit_code == 1 and "unknown robot 'nao'" in r.output


def test_mirrored_motions_move_the_other_way_in_physics(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """The judged behaviour: a mirrored side step steps to the other side and a mirrored
    turn turns the other way, on the MuJoCo KXR-L2 (rcb4hv[sim])."""
    step, turn = tmp_path / "step.h4p", tmp_path / "turn.h4p"
    for src, slot, to, out in ((kxr_project_path, 67, 74, step), (step, TURN_LEFT, FREE, turn)):
        r = CliRunner().invoke(
            cli, ["project", "mirror", str(src), "--motion", str(slot), "--to", str(to),
                  "-o", str(out)],
        )  # fmt: skip
        assert r.exit_code == 0, r.output
    args = ["project", "simulate", str(turn), "--physics", "--json"]
    for slot in (67, 74, TURN_LEFT, FREE):
        args += ["--motion", str(slot)]
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 0, r.output
    ph = {m["slot"]: m["physics"] for m in json.loads(r.output)["motions"]}
    walk_left, walk_mirror = ph[67], ph[74]
    assert walk_left["dy_m"] > 0.05  # HAC_KXR_WALK_LEFT moves to the left (+y)...
    assert walk_mirror["dy_m"] == pytest.approx(
        -walk_left["dy_m"], abs=0.002
    )  # ...its mirror right
    assert walk_mirror["dx_m"] == pytest.approx(walk_left["dx_m"], abs=0.002)
    left, right = ph[TURN_LEFT], ph[FREE]
    assert not left["fell"] and not right["fell"]
    assert left["dyaw_deg"] > 5  # counter-clockwise...
    assert right["dyaw_deg"] == pytest.approx(-left["dyaw_deg"], abs=0.5)  # ...and clockwise
