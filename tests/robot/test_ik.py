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
    center_of_mass,
    forward,
    link_pose,
    position,
    translation,
)
from rcb4hv.robot.model import RobotModel
from rcb4hv.robot.wholebody import solve_balanced


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
    assert not model.out_of_limits(result.angles)


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
    assert not model.out_of_limits(result.angles)
    got = position(link_pose(model, "r_forearm", result.angles))
    assert math.dist(got, far) == pytest.approx(result.position_error, abs=1e-9)
    assert result.position_error < math.dist(home, far) - 0.05  # it reached out toward it


def test_a_limit_holds_the_limb_and_says_so() -> None:
    # the IK keeps the hard (mechanical) limits: the KXR frame stops the shoulder roll at
    # -30 deg, so the arm cannot swing in across the body (an advisory range never holds it)
    model = load_builtin("kxr-l2")
    roll = model.joint("l_shoulder_roll")
    assert math.degrees(roll.lower) == pytest.approx(-30.0)
    home = position(link_pose(model, "l_forearm", {}))
    inward = (home[0], home[1] - 0.05, home[2] + 0.02)
    result = ik.solve(model, "l_forearm", inward, {}, orient="none")
    assert not result.reached
    assert result.at_limits == ("l_shoulder_roll",)
    assert "held at a limit: l_shoulder_roll" in result.message
    assert not model.out_of_limits(result.angles)  # held at the stop, not beyond it
    assert result.angles["l_shoulder_roll"] == pytest.approx(roll.lower)


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


def _over_feet(model: RobotModel, angles: dict[str, float]) -> float:
    """Horizontal distance (m) of the CoM from the feet's centre, the soles' normal as up."""
    frames = forward(model, angles)
    com = center_of_mass(model, frames)
    feet = [frames["l_foot"], frames["r_foot"]]
    up = (feet[0][0][2], feet[0][1][2], feet[0][2][2])
    d = [com[k] - (feet[0][k][3] + feet[1][k][3]) / 2 for k in range(3)]
    along = sum(d[k] * up[k] for k in range(3))
    return math.sqrt(sum((d[k] - along * up[k]) ** 2 for k in range(3)))


@pytest.mark.parametrize("name", ["kxr-l2", "khr3hv"])
def test_solve_balanced_keeps_the_com_over_the_feet_while_a_hand_reaches(name: str) -> None:
    model = load_builtin(name)
    point = ik.effector_point(model, "r_forearm")
    home = forward(model, model.home)
    hand = apply(home["r_forearm"], point)
    target = (hand[0] + 0.08, hand[1], hand[2] + 0.07)  # forward and up, within reach
    plain = ik.solve(model, "r_forearm", target, model.home, point=point)
    kept = solve_balanced(model, "r_forearm", target, model.home, point=point)
    assert plain.reached and kept.reached, kept.message
    assert _over_feet(model, kept.angles) < min(0.0005, _over_feet(model, plain.angles) / 2)
    before, after = forward(model, model.home), forward(model, kept.angles)
    # the feet keep their places relative to each other, soles flat: they did not move
    gap = [position(before["l_foot"])[k] - position(before["r_foot"])[k] for k in range(3)]
    gap2 = [position(after["l_foot"])[k] - position(after["r_foot"])[k] for k in range(3)]
    assert math.dist(gap, gap2) < 0.001
    assert after["l_foot"][2][2] > math.cos(math.radians(0.5))
    # the hand reached its target in the world: relative to the feet it moved as asked
    moved = [apply(after["r_forearm"], point)[k] - position(after["r_foot"])[k] for k in range(3)]
    wanted = [target[k] - position(before["r_foot"])[k] for k in range(3)]
    assert math.dist(moved, wanted) < 0.001


def test_cli_ik_balance_lifts_a_foot_over_the_other() -> None:
    model = load_builtin("kxr-l2")
    foot = position(link_pose(model, "r_foot", model.home))
    target = [f"{foot[0]:.5f}", f"{foot[1]:.5f}", f"{foot[2] + 0.02:.5f}"]  # lifted 2 cm
    out = CliRunner().invoke(
        cli, ["robot", "ik", "kxr-l2", "--link", "r_foot", "--pos", *target, "--balance", "--json"]
    )
    assert out.exit_code == 0, out.output
    data = json.loads(out.stdout)
    assert data["reached"] is True
    frames = forward(model, data["angles"])
    com, left = center_of_mass(model, frames), position(frames["l_foot"])
    assert math.hypot(com[0] - left[0], com[1] - left[1]) < 0.002  # over the standing foot
    # "pos" is where the foot went in the frame of --pos (the start pose's torso), not in
    # the torso frame of the shifted body, which put the foot 3 cm off a reached target
    assert math.dist(data["pos"], [float(t) for t in target]) < 0.001


def test_cli_ik_balance_reports_where_the_link_is_in_the_targets_frame() -> None:
    """Out of reach: the position printed and the distance to the target agree (they are in
    one frame; the position was in the moved torso's frame, 35 mm from the target beside
    "7.7 mm from the target")."""
    target = [0.0, 0.03, -0.15]
    out = CliRunner().invoke(
        cli,
        ["robot", "ik", "kxr-l2", "--link", "l_foot", "--pos", *map(str, target), "--balance",
         "--json"],
    )  # fmt: skip
    data = json.loads(out.stdout)
    assert data["reached"] is False
    assert math.dist(data["pos"], target) == pytest.approx(data["error_m"], abs=0.001)


def test_bad_solver_arguments_and_unknown_names_are_typed() -> None:
    """Was: AssertionError with no message (restarts=-1), KeyError 'nope' (effector_point),
    KeyError 99 (motion_angle), and orient="bogus" silently accepted."""
    from rcb4hv.errors import RobotLookupError, RobotModelError
    from rcb4hv.robot.builtin import load_builtin
    from rcb4hv.robot.ik import effector_point, solve

    m = load_builtin("kxr-l2")
    for kwargs, words in (
        ({"restarts": -1}, "restarts must be an int >= 0, not -1"),
        ({"max_iter": 0}, "max_iter must be an int >= 1, not 0"),
        ({"orient": "bogus"}, "orient must be one of auto, full, normal, none, not 'bogus'"),
    ):
        with pytest.raises(RobotModelError, match=words):
            solve(m, "r_foot", (0.0, -0.02, -0.12), **kwargs)  # type: ignore[arg-type]
    with pytest.raises(RobotModelError, match="has no link 'nope'; its links: "):
        effector_point(m, "nope")
    with pytest.raises(RobotLookupError, match=r"no servo at index 99 \(it has: ") as info:
        m.motion_angle(99, 7500)
    assert isinstance(info.value, KeyError)
    with pytest.raises(KeyError):
        m.joint("nope")
