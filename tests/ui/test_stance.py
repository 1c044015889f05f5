"""Where the 3D view stands a robot: feet, ground contact, support polygon, centre of mass;
and a motion's playback from the plain simulator."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.robot import RobotModel, forward
from rcb4hv.robot.geometry import Stance, convex_hull, feet, geom_points, inside, stance
from rcb4hv.robot.kinematics import from_xyz_rpy
from rcb4hv.ui.playback import Playback, TimedPose, simulated_playback
from tests.ui.toy_robot import LEG, SOLE, SOLE_DROP, toy_model

MODEL = toy_model()
SOLE_Z = 2 * LEG + SOLE_DROP + SOLE[2]  # hip line above the ground when standing straight


def _lowest(st_frames: dict, link: str) -> float:
    return min(p[2] for g in MODEL.link(link).geoms for p in geom_points(g, st_frames[link]))


def test_the_feet_are_the_lowest_leaf_links() -> None:
    assert feet(MODEL) == ("l_foot", "r_foot")


def test_standing_straight_puts_the_soles_on_the_ground_and_the_com_over_both_feet() -> None:
    s = stance(MODEL, {})
    assert s.frames["torso"][2][3] == pytest.approx(SOLE_Z)
    assert _lowest(s.frames, "l_foot") == pytest.approx(0.0, abs=1e-12)
    # both soles: x from 0.01 - 0.04 to 0.01 + 0.04, y from -(0.025 + 0.02) to +(0.025 + 0.02)
    xs = sorted({round(x, 9) for x, _ in s.support})
    ys = sorted({round(y, 9) for _, y in s.support})
    assert xs == [-0.03, 0.05] and ys == [-0.045, 0.045] and len(s.support) == 4
    assert s.com_inside


def test_a_lifted_leg_leaves_one_foot_and_the_com_outside_it() -> None:
    lift = {"l_hip_pitch": -0.5, "l_knee": 1.0, "l_ankle_pitch": -0.5}  # left sole stays level
    s = stance(MODEL, lift)
    assert _lowest(s.frames, "r_foot") == pytest.approx(0.0, abs=1e-12)
    assert _lowest(s.frames, "l_foot") > 0.01
    assert max(y for _, y in s.support) == pytest.approx(-0.005)  # the right sole only
    assert not s.com_inside  # the com stays near y = 0, over the lifted foot's side


def test_bending_both_knees_lowers_the_body_not_the_feet() -> None:
    crouch = {
        n: a
        for s in "lr"
        for n, a in ((f"{s}_hip_pitch", -0.4), (f"{s}_knee", 0.8), (f"{s}_ankle_pitch", -0.4))
    }
    s = stance(MODEL, crouch)
    assert s.frames["torso"][2][3] == pytest.approx(2 * LEG * math.cos(0.4) + SOLE_DROP + SOLE[2])
    assert len(s.support) == 4 and s.com_inside


def test_a_given_base_pose_is_used_as_is() -> None:
    base = from_xyz_rpy((0.1, 0.2, SOLE_Z + 0.05), (0.0, 0.0, 0.3))  # 5 cm in the air
    s = stance(MODEL, {}, base)
    assert s.frames == forward(MODEL, {}, base)
    assert s.support == [] and not s.com_inside


points = st.lists(st.tuples(st.integers(-50, 50), st.integers(-50, 50)), min_size=1, max_size=40)


@given(points)
def test_the_hull_holds_every_point_and_is_made_of_them(pts: list[tuple[int, int]]) -> None:
    fpts = [(float(x), float(y)) for x, y in pts]
    hull = convex_hull(fpts)
    assert set(hull) <= set(fpts)
    if len(hull) >= 3:
        assert all(inside(hull, p) for p in fpts)
        area = sum(
            hull[i - 1][0] * hull[i][1] - hull[i][0] * hull[i - 1][1] for i in range(len(hull))
        )
        assert area > 0  # counter-clockwise


def test_a_point_outside_the_hull_is_outside() -> None:
    square = convex_hull([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.5, 0.5)])
    assert len(square) == 4
    assert inside(square, (0.5, 0.5)) and inside(square, (1.0, 0.5))
    assert not inside(square, (1.01, 0.5)) and not inside(square, (0.5, -0.01))


def test_playback_picks_the_frame_at_or_before_a_time() -> None:
    pb = Playback(
        1,
        "m",
        (TimedPose(0.0, {"a": 0.0}), TimedPose(0.5, {"a": 1.0}), TimedPose(1.0, {"a": 2.0})),
        "completed",
    )
    assert [pb.at(t).angles["a"] for t in (-1.0, 0.0, 0.49, 0.5, 0.99, 5.0)] == [0, 0, 0, 1, 1, 2]
    assert pb.duration == 1.0 and not pb.fallen(0.9)
    fell = Playback(1, "m", pb.frames, "completed", fell_at=0.7)
    assert not fell.fallen(0.69) and fell.fallen(0.7)
    with pytest.raises(ValueError, match="time order"):
        Playback(1, "m", (pb.frames[1], pb.frames[0]), "completed")
    with pytest.raises(ValueError, match="one frame"):
        Playback(1, "m", (), "completed")


def test_the_plain_simulator_gives_every_output_period_of_a_motion(kxr_project_path: Path) -> None:
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.relocate import project_image
    from rcb4hv.project.simulate import Simulator

    project = load_project(kxr_project_path)
    slot = 21  # XL2G_201 greeting
    pb = simulated_playback(project, slot, MODEL)
    sim = Simulator(project_image(project)[0])
    sim.boot()
    period = sim.board.output_period
    result = sim.play(project.motion(slot).address, slot=slot)
    assert pb.status == result.status == "completed"
    assert pb.frames[0].t == 0.0
    assert pb.duration == pytest.approx(result.duration, abs=period)
    steps = [b - a for a, b in zip(pb.times, pb.times[1:], strict=False)]
    assert all(s == pytest.approx(period, abs=1e-5) for s in steps[1:])
    # the last frame is the pose the board holds at the end, through the joint map
    from rcb4hv.protocol.memory import SERVO

    b = sim.board
    trims = {k: SERVO.F_BASE.get(b.ram, b.alloc(k)) for k in b.servo_outputs()}
    assert pb.frames[-1].angles == MODEL.angles(b.servo_outputs(), trims)
    assert len({tuple(sorted(f.angles.items())) for f in pb.frames}) > 10  # it moves


def test_a_bow_leans_the_body_over_flat_feet() -> None:
    s = stance(MODEL, {"l_hip_pitch": 0.5, "r_hip_pitch": 0.5})
    for foot in ("l_foot", "r_foot"):  # all four sole corners on the ground
        corners = geom_points(MODEL.link(foot).geoms[0], s.frames[foot])
        assert sorted(p[2] for p in corners)[:4] == pytest.approx([0.0] * 4, abs=1e-12)
    torso_up = [s.frames["torso"][k][2] for k in range(3)]
    assert math.acos(torso_up[2]) == pytest.approx(0.5)  # the body leans by the hip angle
    assert len(s.support) == 4


def test_the_physics_playback_is_the_physics_run(kxr_project_path: Path) -> None:
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.physics_sim import PhysicsSimulator
    from rcb4hv.project.relocate import project_image, project_layout
    from rcb4hv.project.run import HOLD_S, bound_buttons
    from rcb4hv.robot.builtin import load_builtin
    from rcb4hv.ui.playback import physics_playback

    project = load_project(kxr_project_path)
    robot = load_builtin("kxr-l2-gripper")
    slot = 1  # a few small steps forward
    pb = physics_playback(project, slot, robot)
    image, layout = project_image(project)[0], project_layout(project)
    sim = PhysicsSimulator(image, robot, motion_layout=layout)
    sim.boot()
    # played as the dashboard plays it: the walk loops on UP, held for HOLD_S (run_motions)
    hold = bound_buttons(image, layout)[slot]
    result = sim.play(project.motion(slot).address, slot=slot, hold=hold, hold_for=HOLD_S)
    outcome = sim.outcomes[-1]
    assert pb.source == "physics" and pb.status == result.status
    assert pb.fell_at == outcome.fell_at_s
    assert pb.duration > result.duration  # it goes on while the robot settles
    start, end = pb.frames[0].base, pb.frames[-1].base
    assert start is not None and end is not None
    yaw0 = math.atan2(start[1][0], start[0][0])  # the robot's heading at the start
    ex, ey = end[0][3] - start[0][3], end[1][3] - start[1][3]
    dx = math.cos(yaw0) * ex + math.sin(yaw0) * ey
    assert dx == pytest.approx(outcome.dx_m, abs=1e-9)
    assert pb.frames[-1].angles == sim.world.joint_angles()
    # standing on the floor in physics: the soles are on the ground as in the plain view
    first = stance(robot, pb.frames[0].angles, start)
    assert min(p[2] for p in _world_pts(robot, first)) == pytest.approx(0.0, abs=0.003)


def _world_pts(model: RobotModel, s: Stance) -> list[tuple[float, float, float]]:
    """Every sole corner of ``model`` placed by ``s``."""
    return [
        p for n in feet(model) for g in model.link(n).geoms for p in geom_points(g, s.frames[n])
    ]


def test_the_plain_preview_walks_a_biped_over_the_floor(kxr_project_path: Path) -> None:
    """A walk's preview moves the robot where its no-slip travel takes it (the KXR's slow
    walk forward: 0.4 m), feet on the floor; the toy robot's bow stays where it stood."""
    from rcb4hv.hth4 import load_project
    from rcb4hv.robot.builtin import load_builtin

    project = load_project(kxr_project_path)
    kxr = load_builtin("kxr-l2-gripper")
    walk = simulated_playback(project, 5, kxr)  # XL2G_105: five slow steps forward
    first, last = walk.frames[0].base, walk.frames[-1].base
    assert first is not None and last is not None
    assert last[0][3] - first[0][3] > 0.3 and abs(last[1][3] - first[1][3]) < 0.05
    s = stance(kxr, walk.frames[-1].angles, last)
    assert min(
        p[2] for g in kxr.link("l_foot").geoms for p in geom_points(g, s.frames["l_foot"])
    ) == pytest.approx(0.0, abs=1e-9)
    bow = simulated_playback(project, 21, MODEL)
    assert bow.frames[-1].base is not None
    assert bow.frames[-1].base[0][3] == pytest.approx(bow.frames[0].base[0][3], abs=1e-9)
