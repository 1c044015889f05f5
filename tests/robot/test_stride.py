"""A motion's no-slip travel (rcb4hv.robot.stride): the fixture's own walks go where their
names say, mirrored motions go mirrored ways, standing still goes nowhere, and `project
simulate` reports it with and without --physics (no MuJoCo needed without)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import assume, given
from hypothesis import strategies as st

from rcb4hv.cli.main import cli
from rcb4hv.cli.project_common import load_image
from rcb4hv.project.run import run_motions
from rcb4hv.robot.builtin import load_builtin, load_robot
from rcb4hv.robot.stride import Stride, StrideTracker, has_stride, stride_of
from tests.conftest import KXR_PROJECT_DIR

PROJECT = KXR_PROJECT_DIR / "HAC_KXR_HTH4_project.h4p"
KXR = load_builtin("kxr-l2-gripper")
SLOW_FORWARD, SLOW_BACK = 5, 6  # XL2G_105/106: five slow steps forward / back
CARRY_LEFT, CARRY_RIGHT = 44, 45  # XL2G_304/305: walk left / right carrying in the left hand


def strides(*slots: int) -> dict[int, Stride]:
    image, layout, names = load_image(Path(PROJECT))
    run = run_motions(image, list(slots), names=names, motion_layout=layout, stride=KXR)
    out = {}
    for m in run.motions:
        assert m.stride is not None and m.result.slot is not None
        out[m.result.slot] = m.stride
    return out


def test_kondos_walks_go_where_their_names_say() -> None:
    s = strides(SLOW_FORWARD, SLOW_BACK, CARRY_LEFT, CARRY_RIGHT)
    fwd, back, left, right = s[SLOW_FORWARD], s[SLOW_BACK], s[CARRY_LEFT], s[CARRY_RIGHT]
    assert fwd.dx_m > 0.2 and abs(fwd.dy_m) < 0.05 and abs(fwd.dyaw_deg) < 10
    assert back.dx_m < -0.2 and abs(back.dy_m) < 0.05
    assert left.dy_m > 0.05 and abs(left.dx_m) < 0.02
    assert right.dy_m < -0.05 and abs(right.dx_m) < 0.02
    # the right-hand step is the left-hand one mirrored: the same travel, the other way
    assert right.dy_m == pytest.approx(-left.dy_m, abs=0.005)
    assert fwd.steps >= 8  # five steps each way: the standing foot changes at every one


def test_standing_still_goes_nowhere() -> None:
    s = stride_of(KXR, [KXR.home, dict(KXR.home), {"l_elbow_pitch": 0.5}])
    assert (s.dx_m, s.dy_m, s.dyaw_deg, s.steps) == (0.0, 0.0, 0.0, 0)
    assert StrideTracker(KXR).stride == Stride(0.0, 0.0, 0.0, 0)


def test_a_swinging_leg_moves_nothing() -> None:
    """Lifting one leg and swinging it forward and back leaves the body where it stands
    (on the other foot, which holds): no travel, however far the leg swings."""
    tracker = StrideTracker(KXR)
    tracker.update(KXR.home)
    for hip in (-0.2, -0.5, -0.8, -0.3, 0.2):  # knee bent 0.8 rad, the sole kept level
        tracker.update({"r_hip_pitch": hip, "r_knee_pitch": 0.8, "r_ankle_pitch": -hip - 0.8})
        assert abs(tracker.stride.dx_m) < 1e-9 and abs(tracker.stride.dy_m) < 1e-9
    assert tracker.stride.steps <= 1


def test_robots_on_wheels_get_no_stride() -> None:
    assert has_stride(KXR) and has_stride(load_builtin("khr3hv"))
    assert has_stride(load_robot("kxr:L6")) and has_stride(load_robot("kxr:L4T"))
    wheels = load_robot("kxr:L2W2L6A4H2")  # wheels behind the ankles
    assert not has_stride(wheels)
    with pytest.raises(ValueError, match="no wheels"):
        StrideTracker(wheels)


@pytest.mark.parametrize("code", ["kxr:L6", "kxr:L4T"])
def test_legs_twisting_on_the_floor_turn_the_body_the_other_way(code: str) -> None:
    """Every leg's yaw joint turned by +0.2 rad (counter-clockwise) while every foot stands on
    the floor: the feet hold, so the body turns clockwise under them, by no more than that
    (the hips are not at the body's centre, so no turn keeps every foot exactly in place)."""
    robot = load_robot(code)
    yaws = [j.name for j in robot.joints if j.kind == "yaw" and "neck" not in j.name]
    assert len(yaws) >= 4
    tracker = StrideTracker(robot)
    tracker.update(robot.home)
    for k in range(1, 11):
        tracker.update({name: robot.home.get(name, 0.0) + 0.02 * k for name in yaws})
    turned = tracker.stride.dyaw_deg
    assert -11.5 <= turned < -3.0, turned  # 0.2 rad = 11.5 degrees
    assert tracker.base is not None


def test_project_simulate_no_slip_reports_it_without_physics() -> None:
    args = ["project", "simulate", str(PROJECT), "--motion", str(CARRY_LEFT)]
    plain = json.loads(CliRunner().invoke(cli, [*args, "--json"]).output)
    assert "stride" not in plain["motions"][0]  # asked for with --no-slip only
    args.append("--no-slip")
    data = json.loads(CliRunner().invoke(cli, [*args, "--json"]).output)
    stride = data["motions"][0]["stride"]
    assert set(stride) == {"dx_m", "dy_m", "dyaw_deg", "steps"} and stride["dy_m"] > 0.05
    text = CliRunner().invoke(cli, args).output
    assert "no slip" in text and f"{stride['dy_m']:+.3f}" in text


def test_a_bare_image_plays_without_a_stride(tmp_path: Path) -> None:
    """No servo table, no model: the motions play as before, with no stride and no error."""
    image = tmp_path / "robot.bin"
    built = CliRunner().invoke(cli, ["project", "build", str(PROJECT), "-o", str(image)])
    assert built.exit_code == 0, built.output
    args = ["project", "simulate", str(image), "--motion", str(CARRY_LEFT), "--no-slip"]
    res = CliRunner().invoke(cli, [*args, "--json"])
    assert res.exit_code == 0, res.output
    assert "stride" not in json.loads(res.output)["motions"][0]
    assert "no slip" not in CliRunner().invoke(cli, args).output


def test_project_simulate_reports_it_beside_physics() -> None:
    pytest.importorskip("mujoco")
    args = ["project", "simulate", str(PROJECT), "--physics", "--motion", str(SLOW_FORWARD)]
    plain = json.loads(CliRunner().invoke(cli, [*args, "--json"]).output)
    assert "stride" not in plain["motions"][0]  # asked for with --no-slip only
    data = json.loads(CliRunner().invoke(cli, [*args, "--no-slip", "--json"]).output)
    motion = data["motions"][0]
    assert motion["stride"] == strides(SLOW_FORWARD)[SLOW_FORWARD].to_dict()
    assert motion["stride"]["dx_m"] > 0.2 and motion["physics"]["dx_m"] > 0.2
    assert motion["physics"] == plain["motions"][0]["physics"]  # following it changes nothing
    assert "no slip" in CliRunner().invoke(cli, [*args, "--no-slip"]).output


def test_a_mirrored_motion_is_built_to_go_the_mirrored_way(tmp_path: Path) -> None:
    """Issue 24's rule "mirrored walks, steps and turns go the other way", checked on the
    motions' design with no physics: `hth4.edit.mirror_motion` on the fixture's slow walk
    left (slot 7) and carrying step left (slot 44) gives travels mirrored in y."""
    from rcb4hv.hth4 import load_project, save_project
    from rcb4hv.hth4.edit import mirror_motion

    slots = (7, CARRY_LEFT)
    project = load_project(PROJECT)
    for slot in slots:
        project = mirror_motion(project, slot, KXR)
    mirrored = tmp_path / "mirrored.h4p"
    save_project(project, mirrored)
    image, layout, names = load_image(mirrored)
    run = run_motions(image, list(slots), names=names, motion_layout=layout, stride=KXR)
    before = strides(*slots)
    for m in run.motions:
        assert m.stride is not None and m.result.slot is not None
        was = before[m.result.slot]
        assert abs(was.dy_m) > 0.05
        assert m.stride.dy_m == pytest.approx(-was.dy_m, abs=0.01)
        assert m.stride.dx_m == pytest.approx(was.dx_m, abs=0.01)


@given(
    st.lists(
        st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2), st.floats(0.1, 10.0)),
        min_size=3,
        max_size=12,
    ),
    st.floats(-3.0, 3.0),
    st.floats(-0.5, 0.5),
    st.floats(-0.5, 0.5),
)
def test_the_least_friction_fit_finds_a_rigid_move(
    points: list[tuple[float, float, float]], turn: float, x: float, y: float
) -> None:
    """Contact points carried by one rigid move on the floor: the fit gives that move back,
    whatever each point's force."""
    from rcb4hv.robot.stride import _fit

    spread = max(abs(a - b) + abs(c - d) for a, c, _ in points for b, d, _ in points)
    assume(spread > 0.02)  # points that fix a turn
    c, s = math.cos(turn), math.sin(turn)
    pairs = [((px, py), (c * px - s * py + x, s * px + c * py + y), w) for px, py, w in points]
    got_turn, got_x, got_y = _fit(pairs, 0.0)
    assert math.remainder(got_turn - turn, 2 * math.pi) == pytest.approx(0.0, abs=1e-6)
    assert (got_x, got_y) == pytest.approx((x, y), abs=1e-6)
