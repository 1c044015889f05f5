"""Easing between poses (rcb4hv.hth4.ease, ``rcb4hv project ease``)."""

from __future__ import annotations

import itertools
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.errors import EditError
from rcb4hv.hth4 import load_project
from rcb4hv.hth4.ease import ease_pose, eased_poses
from rcb4hv.hth4.poses import motion_poses
from rcb4hv.project.check import check_project

SLOT = 21  # the bow: pose 3 bends over 100 frames


def test_eased_poses_keep_the_time_and_the_end_and_start_slowly(kxr_project_path: Path) -> None:
    motion = load_project(kxr_project_path).motion(SLOT)
    poses = motion_poses(motion)
    start, target = poses[1].values, poses[2].values
    steps = eased_poses(motion, 2, 5)
    # the board takes frames + 1 output periods a pose (spec 9): the five poses last as long
    # as the one they replace (with the same total frames they took 4 periods more)
    assert sum(f + 1 for f, _ in steps) == poses[2].frames + 1
    assert steps[-1][1] == target
    moving = [i for i in target if target[i] != start[i]]
    assert moving
    for i in moving:
        path = [start[i]] + [v[i] for _, v in steps]
        deltas = [abs(b - a) for a, b in itertools.pairwise(path)]
        assert sum(deltas) == abs(target[i] - start[i])  # monotone, no overshoot
        if abs(target[i] - start[i]) > 200:
            assert deltas[0] < deltas[2] > deltas[-1]  # slow, fast, slow


def test_out_only_starts_fast(kxr_project_path: Path) -> None:
    motion = load_project(kxr_project_path).motion(SLOT)
    start, target = motion_poses(motion)[1].values, motion_poses(motion)[2].values
    i = max(target, key=lambda k: abs(target[k] - start[k]))
    path = [start[i]] + [v[i] for _, v in eased_poses(motion, 2, 4, "out")]
    deltas = [abs(b - a) for a, b in itertools.pairwise(path)]
    assert deltas[0] > deltas[-1]


def test_ease_pose_writes_the_poses_and_keeps_the_project_valid(kxr_project_path: Path) -> None:
    project = load_project(kxr_project_path)
    before = motion_poses(project.motion(SLOT))
    eased = ease_pose(project, SLOT, 2, 5)
    after = motion_poses(eased.motion(SLOT))
    assert len(after) == len(before) + 4
    assert after[6].values == before[2].values
    assert sum(p.frames + 1 for p in after[2:7]) == before[2].frames + 1
    assert [p.values for p in after[7:]] == [p.values for p in before[3:]]
    errors = [f for f in check_project(eased) if f.severity == "error"]
    assert errors == [f for f in check_project(project) if f.severity == "error"]


def test_ease_refuses_the_first_pose_and_too_few_frames(kxr_project_path: Path) -> None:
    motion = load_project(kxr_project_path).motion(SLOT)
    with pytest.raises(EditError, match="no pose before it"):
        eased_poses(motion, 0, 3)
    with pytest.raises(EditError, match="cannot be split"):
        eased_poses(motion, 1, 6)  # pose 2 moves over 10 frames: 11 periods, 5 poses at most
    assert len(eased_poses(motion, 1, 5)) == 5
    with pytest.raises(EditError, match="no pose 99"):
        eased_poses(motion, 98, 3)


def test_cli_project_ease(kxr_project_path: Path, tmp_path: Path) -> None:
    out = tmp_path / "eased.h4p"
    r = CliRunner().invoke(
        cli,
        ["project", "ease", str(kxr_project_path), "--motion", str(SLOT), "--pose", "3",
         "--over", "4", "-o", str(out)],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert len(motion_poses(load_project(out).motion(SLOT))) == 5 + 3
    bad = CliRunner().invoke(
        cli,
        ["project", "ease", str(kxr_project_path), "--motion", str(SLOT), "--pose", "2",
         "--over", "40", "-o", str(out)],
    )  # fmt: skip
    assert bad.exit_code == 1
    assert "cannot be split" in bad.stderr


def test_an_eased_motion_lasts_as_long_on_the_board(kxr_project_path: Path) -> None:
    """Played by the emulated board (no physics), the bow eased over 5 poses ends when the
    bow does: with the same total frames it ended 4 output periods (60 ms) later."""
    from rcb4hv.project.relocate import project_image
    from rcb4hv.project.run import run_motions

    def duration(project: object) -> float:
        image, layout = project_image(project)  # type: ignore[arg-type]
        (run,) = run_motions(image, [SLOT], motion_layout=layout, hold=0).motions
        return run.result.duration

    project = load_project(kxr_project_path)
    assert duration(ease_pose(project, SLOT, 2, 5)) == pytest.approx(duration(project), abs=1e-9)


def test_an_unknown_curve_is_an_edit_error_listing_the_curves(kxr_project_path: Path) -> None:
    """Was: KeyError 'bogus' (a typo such as "inout" took the same path)."""
    project = load_project(kxr_project_path)
    for bad in ("bogus", "inout", None):
        with pytest.raises(EditError, match=r"unknown easing curve .* \(known: in-out, in, out\)"):
            ease_pose(project, 21, 2, 5, bad)  # type: ignore[arg-type]
