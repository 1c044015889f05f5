"""Generated walks on the built-in KXR-L2 in physics: they go the commanded way, at least
60 % of the commanded distance, without falling; the CLI stores them in a project."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.errors import RobotModelError
from rcb4hv.gait.generate import default_params, walk
from rcb4hv.gait.motion import walk_motion
from rcb4hv.hth4 import load_project
from rcb4hv.hth4.keyframes import add_motion
from rcb4hv.hth4.newproject import new_project
from rcb4hv.project.relocate import project_image
from rcb4hv.project.run import run_motions
from rcb4hv.robot.builtin import load_builtin, load_robot
from rcb4hv.robot.kinematics import forward

KXR = load_builtin("kxr-l2")


def test_every_pose_puts_the_feet_where_the_pattern_says() -> None:
    w = walk(KXR, default_params(KXR, "forward", steps=2))
    assert w.missed == 0
    i = len(w.poses) // 2
    frames = forward(KXR, w.poses[i])
    lift = w.pattern.left[i, 2] - w.pattern.right[i, 2]
    zl, zr = frames["l_foot"][2][3], frames["r_foot"][2][3]
    assert zl - zr == pytest.approx(lift, abs=1e-3)


@pytest.mark.parametrize(("direction", "axis", "sign"), [("forward", 0, 1), ("left", 1, 1)])
def test_a_generated_walk_goes_the_commanded_way_without_falling(
    direction: str, axis: int, sign: int
) -> None:
    params = default_params(KXR, direction, steps=2)  # type: ignore[arg-type]
    motion = walk_motion(KXR, walk(KXR, params), slot=2, name="walk").motion
    image, layout = project_image(add_motion(new_project(KXR), motion))
    (run,) = run_motions(image, [2], motion_layout=layout, robot=KXR).motions
    out = run.outcome
    assert out is not None and not out.fell and out.end_pose == "upright"
    travel = (out.dx_m, out.dy_m)
    assert sign * travel[axis] >= 0.6 * params.commanded
    assert abs(travel[1 - axis]) < 0.5 * abs(travel[axis])


@pytest.mark.parametrize(("direction", "sign"), [("turn-right", -1)])
def test_a_generated_turn_turns_the_commanded_way_without_falling(
    direction: str, sign: int
) -> None:
    """On the KHR-3HV's 22-servo build (hip yaw joints): 2 steps of 10°."""
    khr = load_builtin("khr3hv-22")
    params = default_params(khr, direction, steps=2)  # type: ignore[arg-type]
    motion = walk_motion(khr, walk(khr, params), slot=2, name="turn").motion
    image, layout = project_image(add_motion(new_project(khr), motion))
    (run,) = run_motions(image, [2], motion_layout=layout, robot=khr).motions
    out = run.outcome
    assert out is not None and not out.fell and out.end_pose == "upright"
    assert sign * out.dyaw_deg >= 0.6 * params.commanded
    assert math.hypot(out.dx_m, out.dy_m) < 0.03


def test_a_leg_without_hip_yaw_does_not_pretend_to_turn() -> None:
    with pytest.raises(RobotModelError, match="no hip yaw"):
        walk(KXR, default_params(KXR, "turn-left", steps=2))


def test_the_defaults_scale_with_the_leg() -> None:
    small = default_params(KXR, "forward")
    big = default_params(load_builtin("khr3hv"), "forward")
    assert big.stride / small.stride == pytest.approx(0.2057 / 0.116, rel=0.05)
    assert big.lift > small.lift
    assert math.isclose(default_params(KXR, "turn-left").turn, 10.0)


def test_the_cli_writes_a_new_project_and_adds_to_it(tmp_path: Path) -> None:
    out = tmp_path / "walks.h4p"
    args = ["gait", "--robot", "kxr-l2", "--steps", "2", "--into", str(out)]
    r = CliRunner().invoke(cli, [*args, "--slot", "3", "--button", "UP"])
    assert r.exit_code == 0, r.output
    r = CliRunner().invoke(cli, [*args, "--direction", "back", "--slot", "4"])
    assert r.exit_code == 0, r.output
    project = load_project(out)
    assert project.motion(3).name == "gait forward" and project.motion(3).button_data != 0
    assert project.motion(4).name == "gait back"
    r = CliRunner().invoke(cli, [*args, "--slot", "3"])
    assert r.exit_code != 0 and "slot 3" in r.output


def test_tune_keeps_the_best_candidate_and_writes_it(tmp_path: Path) -> None:
    """gait tune with a stand-in for the trials (scored by the lift alone): CMA-ES keeps the
    best candidate it tried and the CLI's path stores a walk."""
    from typing import Any

    import cma  # noqa: F401  (the [scale] extra, which `make test` installs)

    from rcb4hv.gait.tune import BOUNDS, tune

    def fake(*_a: Any, **_k: Any) -> list[dict[str, Any]]:
        return [{"fall_probability": 0.0, "dx_m": {"median": 0.05}}]

    base = default_params(KXR, "forward", steps=1)
    result = tune(KXR, base, trials=1, evaluations=4, run=fake)
    best, tried = result.best, result.tried
    assert best is not None and not result.interrupted
    assert len(tried) >= 4
    assert best.score == min(c.score for c in tried)
    assert best.fall_probability == 0.0 and best.progress == pytest.approx(0.05)
    for c in tried:  # every candidate inside the documented ranges
        p = c.params
        assert BOUNDS["lift"][0] - 1e-9 <= p.lift / base.lift <= BOUNDS["lift"][1] + 1e-9
        assert BOUNDS["step_time"][0] - 1e-9 <= p.step_time / base.step_time
        assert p.step_time / base.step_time <= BOUNDS["step_time"][1] + 1e-9
        assert BOUNDS["double_support"][0] - 1e-9 <= p.double_support
        assert p.double_support <= BOUNDS["double_support"][1] + 1e-9
        assert p.stride == base.stride and p.steps == base.steps
    assert len({c.params for c in tried}) == len(tried)  # the search moves


def test_play_sends_every_pose_and_waits_out_each_move() -> None:
    from collections.abc import Mapping

    from rcb4hv.gait.motion import play_motion

    sent: list[tuple[int, dict[int, int]]] = []
    waited: list[float] = []

    class Client:
        def run_const_frame_servo(self, speed: int, positions: Mapping[int, int]) -> None:
            sent.append((speed, dict(positions)))

    w = walk(KXR, default_params(KXR, "forward", steps=1))
    motion, every, _, _ = walk_motion(KXR, w, slot=2, name="walk")
    n = play_motion(Client(), motion, 15, waited.append)
    assert n == len(sent) > 10
    assert len(sent[0][1]) == len(KXR.servos)  # the first pose names every servo
    # a pose ``every`` samples on is stored with speed every - 1: the board takes N + 1
    # output periods for a move of speed N (spec 9), and the host waits as long
    assert all(speed == every - 1 for speed, _ in sent[1:-1])
    assert sum(waited) == pytest.approx(0.51 + (len(w.poses) - 1) * 0.015, abs=1e-9)


@pytest.mark.parametrize("name", ["khr3hv", "khr3hv-22", "kxr-l2"])
def test_a_walk_bends_the_knees_the_way_knees_bend(name: str) -> None:
    """Every joint of a generated walk inside its advisory range: a robot whose home stands on
    straight legs (the KHR-3HV) had its knees bent backwards, -72 to -113 deg, on every walk."""
    model = load_builtin(name)
    w = walk(model, default_params(model, "forward", steps=2))
    for pose in w.poses:
        for joint, angle in pose.items():
            lo, hi = model.joint(joint).advisory_range
            assert lo - 1e-6 <= angle <= hi + 1e-6, (joint, math.degrees(angle))


def test_a_walk_for_one_robot_is_not_added_to_another_robots_project(tmp_path: Path) -> None:
    """`gait --robot khr3hv --into` a KXR-L2 project wrote KHR-3HV values onto the KXR's
    servos with exit 0; it is refused as every other command refuses a model that does not
    fit (and `gait tune` refuses it before its search)."""
    kxr = tmp_path / "kxr.h4p"
    r = CliRunner().invoke(cli, ["gait", "--robot", "kxr-l2", "--into", str(kxr)])
    assert r.exit_code == 0, r.output
    before = kxr.read_bytes()
    for args in (["gait"], ["gait", "tune", "--evaluations", "1"]):
        r = CliRunner().invoke(cli, [*args, "--robot", "khr3hv", "--into", str(kxr)])
        assert r.exit_code == 1, r.output
        assert "the project has no servo at index 0 (head_yaw)" in r.output
    assert kxr.read_bytes() == before


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["--stride", "5"], "stride 5 m is more than kxr-l2's legs can make"),
        (["--stride", "inf"], "stride inf m is more than"),
        (["--width", "0.5"], "width 0.5 m is more than"),
        (["--lift", "1"], "lift 1 m is more than"),
        (["--direction", "turn-left", "--turn", "-10"], "the direction says which way"),
    ],
)
def test_a_walk_no_robot_can_make_is_refused(tmp_path: Path, args: list[str], said: str) -> None:
    """Absurd parameters: a one-line error naming the parameter, nothing written (a 5 m stride
    was written with every pose out of reach; a negative turn-left turned right)."""
    out = tmp_path / "w.h4p"
    r = CliRunner().invoke(cli, ["gait", "--robot", "kxr-l2", *args, "--into", str(out)])
    assert r.exit_code == 1 and said in r.output, r.output
    assert not out.exists()


def test_a_biped_with_a_wheel_behind_each_ankle_walks_on_its_feet() -> None:
    """The KXR-L2W2L6A4H2 (a wheel on each ankle) was refused: the wheel made the ankle a
    branch, so the legs ended nowhere ("a walk needs two legs, found feet []")."""
    model = load_robot("kxr:L2W2L6A4H2")
    w = walk(model, default_params(model, "forward", steps=2))
    assert w.missed == 0
    with pytest.raises(RobotModelError, match="walks are generated for two-legged robots"):
        walk(load_robot("kxr:L6"), default_params(load_robot("kxr-l2"), "forward"))


def test_a_long_walk_loops_its_settled_cycle_and_goes_its_distance() -> None:
    """40 steps stored as one chain kept a pose every 21 output periods (under two a step)
    and went 0.81 m of 1.16 commanded, 0.11 m sideways. The settled cycle of two steps is
    stored once and looped in COUNTER10, as Kondo's walks loop."""
    from rcb4hv.gait.motion import CYCLE_TOLERANCE, LOOP_COUNTER, steady_loop
    from rcb4hv.hth4.blocks import motion_program

    params = default_params(KXR, "forward", steps=40)
    w = walk(KXR, params)
    values = [KXR.motion_values(p) for p in w.poses]
    stored = walk_motion(KXR, w, slot=2, name="walk")
    loop = stored.loop
    assert loop is not None and loop == steady_loop(w, values)
    assert stored.every <= 5 and loop.repeats >= 15
    # the unrolled moves last the walk, and each stored cycle pose is the walk's own sample
    # wherever the loop plays it (within the tolerance that makes the cycles one)
    assert sum(m.speed + 1 for m in stored.moves[1:]) == len(w.poses) - 1
    for k in range(loop.repeats):
        here = loop.start + k * loop.length + stored.every
        assert all(abs(values[here][i] - values[loop.start + stored.every][i])
                   <= CYCLE_TOLERANCE for i in values[here])  # fmt: skip
    project = add_motion(new_project(KXR), stored.motion)
    kinds = [b.kind for b in motion_program(project, 2).blocks]
    assert kinds.count("counter_set") == 1 and "counter_loop" in kinds and "jump" in kinds
    program = motion_program(project, 2).blocks
    assert program[kinds.index("counter_set")].fields == {
        "counter": LOOP_COUNTER, "value": loop.repeats
    }  # fmt: skip
    image, layout = project_image(project)
    (run,) = run_motions(image, [2], motion_layout=layout, robot=KXR).motions
    out = run.outcome
    # on the board's clock the walk lasts as long as its samples (it took 27.3 s of 21.8 when
    # each pose cost one period more than the walk's own spacing)
    assert run.result.duration == pytest.approx(0.51 + (len(w.poses) - 1) * 0.015, abs=0.05)
    assert out is not None and not out.fell and out.end_pose == "upright"
    assert out.dx_m >= 0.9 * params.commanded and abs(out.dy_m) < 0.05


def test_a_short_walk_has_no_cycle_to_loop() -> None:
    from rcb4hv.gait.motion import steady_loop

    w = walk(KXR, default_params(KXR, "forward", steps=2))
    assert steady_loop(w, [KXR.motion_values(p) for p in w.poses]) is None
    assert walk_motion(KXR, w, slot=2, name="walk").loop is None


def test_walk_errors_are_typed_and_said_at_once() -> None:
    """Gait parameter errors were builtin ValueErrors; 300 steps ran 18 s before refusing,
    a 1e9 s step asked for 124 GiB and ``period_s=0`` divided by zero."""
    from rcb4hv.errors import GaitError, Rcb4Error

    assert issubclass(GaitError, Rcb4Error) and issubclass(GaitError, ValueError)
    with pytest.raises(GaitError, match=r"1\.\.200 steps, not 300"):
        default_params(KXR, "forward", steps=300)
    with pytest.raises(GaitError, match="at most 5 s"):
        default_params(KXR, "forward", steps=2, step_time=1e9)
    with pytest.raises(GaitError, match="period_s"):
        walk(KXR, default_params(KXR, "forward", steps=2), period_s=0)
    w = walk(KXR, default_params(KXR, "forward", steps=1))
    with pytest.raises(GaitError, match="output period"):
        walk_motion(KXR, w, slot=2, name="w", period=13)
    with pytest.raises(ValueError, match="motion slot must be") as info:
        walk_motion(KXR, w, slot=0, name="w")
    assert "servo's travel" not in str(info.value)  # said of every ValueError before
    khr = load_builtin("khr3hv")
    with pytest.raises(GaitError, match="a walk of another robot"):
        walk_motion(khr, w, slot=2, name="w")  # the KXR-L2's walk on the KHR-3HV's servos


def test_a_walk_is_not_played_on_another_robots_board(tmp_path: Path) -> None:
    """`gait --port` played the KXR-L2's walk on the emulator's default board, whose servos
    are another robot's (its legs' values on other joints); `--json` named slot 2 though
    nothing was stored."""
    r = CliRunner().invoke(
        cli, ["gait", "--robot", "kxr-l2", "--steps", "1", "--port", "rcb4emu://", "--json"]
    )
    assert r.exit_code == 1 and "the board has no servo at ICS 8, 9" in r.output
    rom = tmp_path / "kxr.rom"  # a board holding a KXR-L2 project
    rom.write_bytes(project_image(new_project(KXR))[0])
    r = CliRunner().invoke(
        cli, ["gait", "--robot", "kxr-l2", "--steps", "1", "--port",
              f"rcb4emu://?speed=50&rom={rom}", "--json"],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert json.loads(r.output)["slot"] is None
