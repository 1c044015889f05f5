"""Inverse kinematics (rcb4hv.robot.ik): IK then FK lands on the target, limits hold, an
unreachable target gives the nearest pose with a flag, and the CLI round trip."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv.cli.main import cli
from rcb4hv.robot import ik
from rcb4hv.robot.builtin import BUILTIN, load_builtin
from rcb4hv.robot.kinematics import (
    apply,
    forward,
    link_pose,
    position,
    translation,
)
from rcb4hv.robot.model import RobotModel


def _limb_angles(draw: st.DrawFn, model: RobotModel, link: str, spread: float) -> dict[str, float]:
    """In-limit angles of ``link``'s limb; ``spread`` < inf keeps them near the home pose."""
    out = dict(model.home)
    for j in ik.limb(model, link):
        home = model.home.get(j.name, 0.0)
        lo, hi = max(j.lower, home - spread), min(j.upper, home + spread)
        out[j.name] = draw(st.floats(lo, hi))
    return out


@st.composite
def reachable(
    draw: st.DrawFn, spread: float = math.inf
) -> tuple[RobotModel, str, dict[str, float]]:
    model = load_builtin(draw(st.sampled_from(BUILTIN)))
    link = draw(st.sampled_from(sorted(ik.effectors(model))))
    return model, link, _limb_angles(draw, model, link, spread)


def test_effectors_are_the_hands_and_feet() -> None:
    for name in BUILTIN:
        eff = ik.effectors(load_builtin(name))
        assert eff == {"l_forearm": "hand", "r_forearm": "hand", "l_foot": "foot", "r_foot": "foot"}
    arm = [j.name for j in ik.limb(load_builtin("khr3hv-22"), "l_forearm")]
    assert arm == ["l_shoulder_pitch", "l_shoulder_roll", "l_upper_arm_yaw", "l_elbow_pitch"]


@settings(max_examples=40)
@given(reachable())
def test_ik_then_fk_reaches_a_position_within_1mm(
    case: tuple[RobotModel, str, dict[str, float]],
) -> None:
    model, link, angles = case
    point = ik.effector_point(model, link)
    target = apply(link_pose(model, link, angles), point)
    result = ik.solve(model, link, target, point=point)
    assert result.reached, result.message
    got = apply(link_pose(model, link, result.angles), point)
    assert math.dist(got, target) < 1e-3
    assert not model.within_limits(result.angles)


@settings(max_examples=30)
@given(reachable(spread=0.6))
def test_ik_reaches_a_whole_pose_where_the_chain_has_the_axes(
    case: tuple[RobotModel, str, dict[str, float]],
) -> None:
    model, link, angles = case
    target = link_pose(model, link, angles)
    result = ik.solve(model, link, target)
    assert result.reached, result.message
    got = link_pose(model, link, result.angles)
    assert math.dist(position(got), position(target)) < 1e-3
    if len(ik.limb(model, link)) >= 5:  # the sole's normal at least
        normal = sum(got[i][2] * target[i][2] for i in range(3))
        assert normal > math.cos(math.radians(0.5))


@pytest.mark.parametrize("name", BUILTIN)
def test_an_unreachable_target_stops_at_the_nearest_pose(name: str) -> None:
    model = load_builtin(name)
    home = position(link_pose(model, "r_forearm", model.home))
    far = (home[0] + 0.6, home[1], home[2])
    result = ik.solve(model, "r_forearm", far)
    assert not result.reached
    assert "out of reach" in result.message
    assert not model.within_limits(result.angles)
    got = position(link_pose(model, "r_forearm", result.angles))
    assert math.dist(got, far) == pytest.approx(result.position_error, abs=1e-9)
    assert result.position_error < math.dist(home, far) - 0.05  # it reached out toward it


def test_a_limit_holds_the_limb_and_says_so() -> None:
    model = load_builtin("khr3hv")  # hip roll may only spread the leg outward (0..30°)
    home = position(link_pose(model, "l_foot", {}))
    inward = (home[0], home[1] - 0.06, home[2] + 0.01)
    result = ik.solve(model, "l_foot", inward, {}, orient="none")
    assert not model.within_limits(result.angles)
    assert result.angles["l_hip_roll"] >= 0.0


def test_solve_feet_puts_both_feet_at_world_poses_under_a_moved_torso() -> None:
    model = load_builtin("kxr-l2")
    frames = forward(model, model.home)
    torso = translation((0.01, 0.005, -0.012))  # the torso sinks and shifts
    feet = {"l_foot": frames["l_foot"], "r_foot": frames["r_foot"]}
    result = ik.solve_feet(model, feet, torso, model.home)
    assert result.reached, result.message
    world = forward(model, result.angles, torso)
    for link, want in feet.items():
        assert math.dist(position(world[link]), position(want)) < 1e-4
        assert world[link][2][2] > math.cos(math.radians(0.1))  # soles stay flat
    assert result.angles["l_knee_pitch"] > model.home["l_knee_pitch"]  # knees bend to sink


def test_cli_ik_then_fk(tmp_path: Path) -> None:
    runner = CliRunner()
    out = runner.invoke(
        cli,
        ["robot", "ik", "kxr-l2", "--link", "l_foot", "--pos", "0.02", "0.03", "-0.13", "--json"],
    )
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    assert data["reached"] is True
    assert {j.name for j in load_builtin("kxr-l2").joints} <= set(data["angles"])
    file = tmp_path / "pose.json"
    file.write_text(out.output)
    back = runner.invoke(
        cli, ["robot", "fk", "kxr-l2", "--link", "l_foot", "--angles", str(file), "--json"]
    )
    assert back.exit_code == 0, back.output
    assert math.dist(json.loads(back.output)["pos"], (0.02, 0.03, -0.13)) < 1e-3
    home = runner.invoke(cli, ["robot", "fk", "kxr-l2", "--link", "l_foot", "--json"])
    assert json.loads(home.output)["pos"] == pytest.approx([0.0, 0.0235, -0.1435], abs=1e-3)


def test_cli_ik_warns_out_of_reach_and_refuses_an_unknown_link() -> None:
    runner = CliRunner()
    out = runner.invoke(
        cli, ["robot", "ik", "kxr-l2", "--link", "l_foot", "--pos", "0.4", "0", "0", "--json"]
    )
    assert out.exit_code == 0
    assert "out of reach" in out.stderr
    assert json.loads(out.stdout)["reached"] is False
    bad = runner.invoke(cli, ["robot", "fk", "kxr-l2", "--link", "nope"])
    assert bad.exit_code == 1
    assert "has no link 'nope'" in bad.stderr
