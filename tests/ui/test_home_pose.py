"""Every view of the fixture's home pose agrees on the joint angles: the plain preview, the
live view (servo positions polled from the board), the editor and physics' joint targets.

The fixture's knees have a trim of -1980 counts (-66.8 degrees): a view that subtracted the
trim from a motion-space value (one the board reports before adding the trim) would show the
knee at about 77 degrees instead of 10."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from rcb4hv.client import Robot
from rcb4hv.emulator import emulator_url
from rcb4hv.hth4 import Project, dump_project, load_project
from rcb4hv.project.relocate import project_image
from rcb4hv.project.simulate import Simulator
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.session.state import BoardState, poll_state
from rcb4hv.ui.editor_state import Editor
from rcb4hv.ui.live3d import servo_pose
from rcb4hv.ui.playback import simulated_playback

MODEL = load_builtin("kxr-l2-gripper")
KNEES = ("r_knee_pitch", "l_knee_pitch")
# XL2G_291 holds the knees at 7800: +300 counts = 10.125 degrees of bend (model docstring)
HOME_KNEE_DEG = 300 * 270 / 8000


def _knees(angles: dict[str, float]) -> list[float]:
    return [math.degrees(angles[k]) for k in KNEES]


def test_the_fixture_home_pose_is_the_same_in_every_view(kxr_project_path: Path) -> None:
    project = load_project(kxr_project_path)
    assert project.servos_by_ics[12].trim == -1980  # the trim the bug counted twice
    home = project.startup_motion
    assert home is not None and home.name == "XL2G_291_ホームポジション"

    # the plain preview: the board's sent values (output + trim) through the trims
    preview = simulated_playback(project, home.slot, MODEL).frames[-1].angles
    assert _knees(preview) == pytest.approx([HOME_KNEE_DEG] * 2, abs=0.05)

    # the live view: the positions a host polls from the board after boot
    sim = Simulator(project_image(project)[0])
    sim.boot()
    robot = Robot.open(emulator_url(sim.board))
    try:
        robot.discover_servos()
        state = poll_state(robot, BoardState("test"), 0.0)
    finally:
        robot.close()
    assert {s.ics: s.trim for s in state.servos}[12] == -1980
    live = MODEL.motion_angles(servo_pose(state))
    assert live == pytest.approx(preview, abs=1e-9)

    # the editor: the home motion's last pose
    ed = Editor()
    ed.open(dump_project(project))
    assert ed.model is not None and ed.model.name == MODEL.name
    ed.select(home.slot, len(ed.poses()) - 1)
    assert ed.pose_angles() == pytest.approx(preview, abs=1e-9)


def test_physics_targets_the_preview_pose(kxr_project_path: Path) -> None:
    from rcb4hv.project.physics_sim import PhysicsSimulator
    from rcb4hv.project.relocate import project_layout

    project = load_project(kxr_project_path)
    home = project.startup_motion
    assert home is not None
    preview = simulated_playback(project, home.slot, MODEL).frames[-1].angles
    sim = PhysicsSimulator(project_image(project)[0], MODEL, motion_layout=project_layout(project))
    sim.boot()
    assert sim.backend is not None
    targets = {
        sim.world.servos[i].joint: a for i, a in sim.backend.commanded.items() if a is not None
    }
    assert _knees(targets) == pytest.approx([HOME_KNEE_DEG] * 2, abs=0.05)
    assert targets == pytest.approx(preview, abs=1e-9)
    assert sim.board_pose() == pytest.approx(preview, abs=1e-9)


def _free_knee(kxr_project_path: Path) -> tuple[Project, int]:
    """The fixture with a motion in slot 18 whose second pose frees ICS 12 (trim -1980)."""
    from rcb4hv.hth4.edit import set_pose
    from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
    from rcb4hv.protocol import POSITION_FREE

    project = load_project(kxr_project_path)
    slot = 18  # empty in the fixture
    keyframes = [Keyframe(0.1, {12: 7800, 13: 7800}), Keyframe(0.1, {12: 7800, 13: 7800})]
    motion = motion_from_keyframes(keyframes, slot=slot, name="free knee", date="2026/01/01")
    return set_pose(add_motion(project, motion), slot, 1, {12: POSITION_FREE}), slot


def test_the_preview_leaves_out_a_freed_servo_whatever_its_trim(kxr_project_path: Path) -> None:
    """The board sends free (8000h) plus the trim (its default ``free_hold_base``): the plain
    preview takes the trim off before it recognises free, so the freed knee (trim -1980) is
    not drawn at an angle of its own."""
    project, slot = _free_knee(kxr_project_path)
    frames = simulated_playback(project, slot, MODEL).frames
    assert math.degrees(frames[0].angles["r_knee_pitch"]) == pytest.approx(HOME_KNEE_DEG, abs=0.05)
    assert "r_knee_pitch" not in frames[-1].angles
    assert math.degrees(frames[-1].angles["l_knee_pitch"]) == pytest.approx(HOME_KNEE_DEG, abs=0.05)


def test_the_simulation_plot_leaves_out_a_freed_servo_whatever_its_trim(
    kxr_project_path: Path,
) -> None:
    """The Project page's angle plot asks the board whether a servo is free (it compared the
    sent value, trim included, with 8000h and drew the freed knee at 8000h - 1980)."""
    from rcb4hv.ui.project_actions import simulate_motion

    project, slot = _free_knee(kxr_project_path)
    trace = simulate_motion(project, slot)
    assert trace.result.status == "completed"
    knee, other = trace.series[12], trace.series[13]
    assert knee[-1][0] < other[-1][0]  # the freed knee's line ends where it is freed
    assert all(abs(deg) < 135 for _, deg in knee)  # never at the free word's "angle"
