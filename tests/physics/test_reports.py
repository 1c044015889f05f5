"""Honest physics reports (issue 24 item 4): a robot that is down before a motion starts is
reported so, with the pose it lies in; ``fell`` and ``end_pose`` never contradict; the settle
after the boot is part of the report."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from rcb4hv.cli.project_physics import print_physics
from rcb4hv.hth4 import load_project
from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
from rcb4hv.project.relocate import project_image
from rcb4hv.project.run import run_motions
from rcb4hv.project.runresult import SimulationRun
from tests.physics.conftest import PROJECT, image_with, pose
from tests.physics.robots import biped

ROBOT = biped()
STAND = pose(ROBOT, {})
TIP = pose(ROBOT, {"r_hip_pitch": -90.0, "l_hip_pitch": -90.0})  # folds over: falls forward
TOES = pose(ROBOT, {"r_ankle_pitch": 40.0, "l_ankle_pitch": 40.0})  # cannot stand on its soles


def _consistent(run: SimulationRun) -> None:
    """``fell`` and ``end_pose`` agree: ending down means it fell or it started down."""
    for m in run.motions:
        o = m.outcome
        assert o is not None
        assert o.fell == (o.fell_at_s is not None)
        if o.fell:
            assert o.start_pose == "upright" and not o.fallen_at_start
        if o.end_pose != "upright" and not o.fell:
            assert o.start_pose != "upright"
        if o.fallen_at_start:
            assert o.start_pose != "upright"


def test_a_robot_left_lying_by_a_motion_is_down_at_the_next_start() -> None:
    image, layout, names = image_with([[Keyframe(0.2, STAND), Keyframe(0.3, TIP)],
                                       [Keyframe(0.5, STAND)]])  # fmt: skip
    run = run_motions(image, [18, 19], names=names, motion_layout=layout, robot=ROBOT,
                      sequence=True)  # fmt: skip
    tip, stand = (m.outcome for m in run.motions)
    assert tip is not None and stand is not None
    assert tip.start_pose == "upright" and not tip.fallen_at_start
    assert tip.fell and tip.end_pose == "on_front"
    # it cannot fall again: it was down from the start, and says so
    assert stand.start_pose == "on_front" and stand.fallen_at_start
    assert not stand.fell and stand.end_pose == "on_front"
    _consistent(run)


def test_a_robot_that_falls_while_settling_after_the_boot_is_down_before_the_motion() -> None:
    """As Kondo's KXR-L2 sample did under the emulator's old AD rule: the startup pose
    throws the robot over, so it lies down before the first motion starts."""
    project = load_project(PROJECT)
    for slot, frames in ((18, [Keyframe(0.2, STAND), Keyframe(0.3, TOES)]),
                         (19, [Keyframe(0.5, STAND)])):  # fmt: skip
        project = add_motion(
            project, motion_from_keyframes(frames, slot=slot, name=f"m{slot}", date="2026/01/01")
        )
    project = replace(project, startup_motion_address=project.motion(18).address)
    image, layout = project_image(project)
    run = run_motions(image, [19], motion_layout=layout, robot=ROBOT)
    assert run.physics is not None and run.physics.settled_pose == "on_back"
    (out,) = (m.outcome for m in run.motions)
    assert out is not None
    assert out.fallen_at_start and out.start_pose == "on_back"
    assert not out.fell and out.end_pose != "upright"
    _consistent(run)
    data = run.to_dict()
    assert data["physics"]["settled_pose"] == "on_back"  # type: ignore[index]


def test_a_robot_put_down_on_purpose_is_not_fallen() -> None:
    image, layout, names = image_with([[Keyframe(0.5, STAND)]])
    run = run_motions(image, [18], names=names, motion_layout=layout, robot=ROBOT,
                      start="on_back")  # fmt: skip
    (out,) = (m.outcome for m in run.motions)
    assert out is not None and out.start_pose == "on_back" and not out.fallen_at_start
    assert run.physics is not None and run.physics.start == "on_back"
    _consistent(run)


def test_the_text_and_json_reports_say_down_at_start(capsys: pytest.CaptureFixture[str]) -> None:
    image, layout, names = image_with([[Keyframe(0.2, STAND), Keyframe(0.3, TIP)],
                                       [Keyframe(0.5, STAND)]])  # fmt: skip
    run = run_motions(image, [18, 19], names=names, motion_layout=layout, robot=ROBOT,
                      sequence=True)  # fmt: skip
    print_physics(run, as_json=False)
    text = capsys.readouterr().out
    lines = [line for line in text.splitlines() if line.lstrip().startswith(("18", "19"))]
    assert "at 0." in lines[0] and "on_front" in lines[0]
    assert "down at start (on_front)" in lines[1]
    assert "settled upright" in text
    print_physics(run, as_json=True)
    data = json.loads(capsys.readouterr().out)
    assert [m["physics"]["fallen_at_start"] for m in data["motions"]] == [False, True]
    assert [m["physics"]["fell"] for m in data["motions"]] == [True, False]
    assert data["physics"]["settle_s"] == 1.0
