"""Static balance and servo load per pose (rcb4hv.robot.balance, rcb4hv.project.posebalance,
``project poses`` and ``project check --balance``)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.robot.balance import (
    GRAVITY,
    PoseBalance,
    pose_balance,
    rigid_balance,
    signed_margin,
)
from rcb4hv.robot.builtin import BUILTIN, load_builtin
from rcb4hv.robot.geometry import convex_hull
from rcb4hv.robot.ik import limb
from rcb4hv.robot.kinematics import apply, forward
from rcb4hv.robot.model import RobotModel


def lean(model: RobotModel, degrees: float) -> dict[str, float]:
    out = dict(model.home)
    for side in ("l", "r"):
        out[f"{side}_ankle_pitch"] = model.home.get(f"{side}_ankle_pitch", 0.0) - math.radians(
            degrees
        )
    return out


def test_hull_and_margin() -> None:
    square = convex_hull([(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5), (0.5, 0)])
    assert square == [(0, 0), (1, 0), (1, 1), (0, 1)]
    assert signed_margin(square, (0.5, 0.5)) == pytest.approx(0.5)
    assert signed_margin(square, (0.5, 0.9)) == pytest.approx(0.1)
    assert signed_margin(square, (1.5, 0.5)) == pytest.approx(-0.5)
    assert signed_margin(((0.0, 0.0), (1.0, 0.0)), (0.5, 0.2)) == pytest.approx(-0.2)
    assert signed_margin((), (0.0, 0.0)) == -math.inf


@pytest.mark.parametrize("name", BUILTIN)
def test_the_home_pose_stands_on_both_feet(name: str) -> None:
    model = load_builtin(name)
    b = pose_balance(model, model.home)
    assert b.balanced
    assert b.contacts == ("l_foot", "r_foot")
    assert b.tipped_deg == 0.0
    assert 0.025 < b.margin_m < 0.06
    assert max(b.torque_ratio.values()) < 0.3
    assert b.com[2] > 0.1


def test_the_fixture_robot_s_home_margin_is_the_one_physics_measures() -> None:
    # bench/balance_vs_physics.py: MuJoCo's contacts give the KXR-L2 with grippers 46.8 mm
    b = pose_balance(load_builtin("kxr-l2-gripper"), load_builtin("kxr-l2-gripper").home)
    assert b.margin_m == pytest.approx(0.0468, abs=0.002)


def test_a_forward_lean_stops_standing_and_loads_the_ankles() -> None:
    model = load_builtin("kxr-l2-gripper")
    upright, leant, over = (pose_balance(model, lean(model, d)) for d in (0, 15, 30))
    assert upright.balanced and leant.balanced and not over.balanced
    assert upright.margin_m > leant.margin_m > 0 > over.margin_m
    assert leant.torque_ratio["l_ankle_pitch"] > 3 * upright.torque_ratio["l_ankle_pitch"]

    def ahead(b: PoseBalance) -> float:  # the CoM ahead of the support's centre
        return b.com[0] - sum(x for x, _ in b.support) / len(b.support)

    assert ahead(leant) > ahead(upright) + 0.02  # the ground follows the soles: leant forward


def test_one_foot_lifted_stands_on_the_other() -> None:
    model = load_builtin("kxr-l2")
    pose = dict(model.home)
    pose.update(l_hip_pitch=-0.6, l_knee_pitch=1.2, l_ankle_pitch=-0.6)
    b = pose_balance(model, pose)
    assert b.contacts == ("r_foot",)
    # the CoM stays between the feet, outside the standing one; the lifted foot is too high
    # to tip onto within MAX_TIP_DEG: it cannot stand still
    assert not b.balanced
    assert b.margin_m < 0


def test_an_arm_s_static_torque_is_the_gradient_of_its_potential_energy() -> None:
    model = load_builtin("khr3hv")
    pose = {"r_shoulder_pitch": -1.2, "r_elbow_pitch": -0.7}
    b = rigid_balance(model, pose)
    arm = {j.child for j in limb(model, "r_forearm")}

    def energy(q: float) -> float:
        frames = forward(model, {**pose, "r_shoulder_pitch": q})
        ground = b.ground
        assert ground is not None
        return sum(
            GRAVITY * lk.inertial.mass * apply(ground, apply(frames[lk.name], lk.inertial.com))[2]
            for lk in model.links
            if lk.name in arm
        )

    h = 1e-6
    q0 = pose["r_shoulder_pitch"]
    gradient = (energy(q0 + h) - energy(q0 - h)) / (2 * h)
    assert b.torque["r_shoulder_pitch"] == pytest.approx(gradient, rel=1e-4)
    stall = model.servo_for_joint("r_shoulder_pitch").servo.stall_torque  # type: ignore[union-attr]
    assert b.torque_ratio["r_shoulder_pitch"] == pytest.approx(abs(gradient) / stall, rel=1e-4)


def test_compliance_sags_a_loaded_pose_toward_the_edge() -> None:
    model = load_builtin("kxr-l2")
    rigid = pose_balance(model, lean(model, 20), compliant=False)
    soft = pose_balance(model, lean(model, 20))
    assert 0 < soft.margin_m < rigid.margin_m


def test_cli_project_poses_json(kxr_project_path: Path) -> None:
    out = CliRunner().invoke(
        cli, ["project", "poses", str(kxr_project_path), "--motion", "11", "--json"]
    )
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    assert data["robot"] == "kxr-l2-gripper"
    poses = data["poses"]
    assert [p["pose"] for p in poses] == [1, 2, 3, 4, 5]
    assert poses[0]["balanced"] is True and poses[0]["margin_m"] > 0.03
    assert poses[1]["balanced"] is False and poses[1]["contacts"] == ["r_foot"]
    assert set(poses[0]["torque_ratio"]) == {s.joint for s in load_builtin("kxr-l2-gripper").servos}
    text = CliRunner().invoke(cli, ["project", "poses", str(kxr_project_path), "--motion", "11"])
    assert "NO" in text.output and "most loaded servo" in text.output


def test_cli_check_balance_reports_poses_that_cannot_stand(kxr_project_path: Path) -> None:
    out = CliRunner().invoke(
        cli, ["project", "check", str(kxr_project_path), "--balance", "--json"]
    )
    assert out.exit_code == 0, out.output
    found = [f for f in json.loads(out.output)["findings"] if f["code"] == "pose-cannot-stand"]
    assert any(f["slot"] == 11 and "pose 2: cannot stand" in f["reason"] for f in found)
    assert not any(f["slot"] == 39 for f in found)  # the home position stands
    # a pose inside the support but short of the reserve was "-5 mm outside the support"
    edge = [f["reason"] for f in found if "pose 5:" in f["reason"] and f["slot"] == 1]
    assert edge == ["motion 1 pose 5: at the edge: centre of mass only 5 mm inside the "
                    "support; standing still takes 6 mm (r_foot)"]  # fmt: skip


@pytest.mark.parametrize("build", ["R4LL", "L6", "L4T", "L4N", "L4D"])
def test_the_view_places_a_pose_as_the_balance_line_does(build: str) -> None:
    """The 3D view's placement (:func:`placed`) is the balance line's (:func:`rigid_balance`):
    the same centre of mass, support and ground frame, so the view's mark is over the support
    exactly when the margin is positive. Kondo's home poses of the multi-legged kits, where
    levelling the soles' mean normal (``geometry.stance``) stood the KXR-R4LL on two diagonal
    wheels with its centre of mass outside, while the balance line said 4 wheels, inside."""
    from rcb4hv.robot.balance import placed, rigid_balance
    from rcb4hv.robot.builtin import load_robot
    from rcb4hv.robot.kit.stockhome import with_stock_home

    model = with_stock_home(load_robot(f"kxr:{build}"))
    angles = {j.name: 0.0 for j in model.joints} | dict(model.home)
    st, b = placed(model, angles), rigid_balance(model, angles)
    assert st.com == pytest.approx(b.com) and st.support == list(b.support)
    assert b.margin_m > 0 and st.com_inside  # Kondo's home stands, and the view says so


def test_the_view_and_the_balance_line_agree_on_every_fixture_pose(kxr_project_path: Path) -> None:
    """Every pose of the fixture's motions: the view's mark is over the support exactly when
    the balance line's margin is positive. The view levelled the soles' mean normal instead
    (``geometry.stance``) and disagreed on 192 of the 472 poses (slot 1's eighth: 50 mm
    inside by the line, outside in the view)."""
    from rcb4hv.hth4 import load_project
    from rcb4hv.hth4.poses import motion_poses
    from rcb4hv.hth4.robotpick import project_model
    from rcb4hv.robot.balance import placed, rigid_balance
    from rcb4hv.robot.geometry import stance

    project = load_project(kxr_project_path)
    model = project_model(project)
    was = 0
    for motion in project.used_motions:
        for pose in motion_poses(motion):
            values = {i: v for i, v in pose.values.items() if 3500 <= v <= 11500}
            angles = {j.name: 0.0 for j in model.joints} | model.motion_angles(values)
            inside = rigid_balance(model, angles).margin_m > 0
            assert placed(model, angles).com_inside == inside
            was += stance(model, angles).com_inside != inside
    assert was == 192
