"""Robot detection from a project's servo table, index checks, value<->angle, and the CLI."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.cli.main import cli
from rcb4hv.errors import ProtocolError, RobotModelError
from rcb4hv.hth4.project import load_project
from rcb4hv.hth4.trim import load_trim
from rcb4hv.protocol.commands import decode_command
from rcb4hv.protocol.servocmds import RunConstFrameServo
from rcb4hv.robot.builtin import (
    BUILTIN,
    check_indices,
    detect_robot,
    even_side,
    load_builtin,
    load_robot,
)
from rcb4hv.robot.kinematics import apply, forward
from rcb4hv.robot.model import side_of_name


def test_detects_the_fixture_robot(kxr_project_path: Path) -> None:
    project = load_project(kxr_project_path)
    table = {s.ics_number: s.name or "" for s in project.servos if s.in_use}
    assert detect_robot(table) == "kxr-l2-gripper"
    check_indices(load_builtin("kxr-l2-gripper"), table)
    with pytest.raises(RobotModelError, match=r"no servo at index 0 \(head_yaw\)"):
        check_indices(load_builtin("khr3hv"), table)


def test_fixture_trim_file_names_right_on_even(kxr_dir: Path) -> None:
    trim = load_trim(next(kxr_dir.glob("*.h4t")))
    model = load_builtin("kxr-l2-gripper")
    for e in trim.entries:
        if e.device_number in model.indices and e.name:
            side = model.joint(model.servo(e.device_number).joint).side
            assert e.name.startswith("右" if side == "right" else "左"), e


def test_fixture_motions_keep_knees_bending_forward(kxr_project_path: Path) -> None:
    """Every pose in the fixture's motions bends the knees the physical way (>= about 0) and
    keeps the ankles below the hips."""
    project = load_project(kxr_project_path)
    model = load_builtin("kxr-l2-gripper")
    poses = 0
    for motion in project.used_motions:
        for frame in motion.frame_list:
            try:
                cmd = decode_command(frame)
            except ProtocolError:  # a frame split over list entries (not a servo frame)
                continue
            if not isinstance(cmd, RunConstFrameServo):
                continue
            values = {i: v for i, v in cmd.positions if 3500 <= v <= 11500}
            angles = model.motion_angles(values)
            for side in ("l_", "r_"):
                if side + "knee_pitch" in angles:
                    assert angles[side + "knee_pitch"] > math.radians(-11), motion.name
            poses += 1
    assert poses > 300


@pytest.mark.parametrize("name", BUILTIN)
def test_detects_each_builtin_from_synthetic_names(name: str) -> None:
    model = load_builtin(name)
    sides = {s.index: model.joint(s.joint).side for s in model.servos}
    even = sides[min(i for i, side in sides.items() if i % 2 == 0 and side != "centre")]
    # every side word read alike: the Japanese prefix, and the joint's own l_/r_ prefix alone
    for mark in (lambda side: "左" if side == "left" else "右", lambda side: ""):
        names = {s.index: mark(model.joint(s.joint).side) + s.joint
                 for s in model.servos if model.joint(s.joint).side != "centre"}  # fmt: skip
        assert even_side(names) == even
        assert detect_robot({**names, **{i: "x" for i in model.indices if i not in names}}) == name
    # without side words the index set alone decides (all four sets differ)
    assert detect_robot({i: f"servo {i}" for i in model.indices}) == name


def test_a_side_word_is_read_where_it_stands() -> None:
    """``shoulder_pitch`` holds ``r_`` but names no side: only a word at either end counts."""
    assert side_of_name("l_shoulder_pitch") == "left"
    assert side_of_name("r_shoulder_pitch") == "right"
    assert side_of_name("shoulder_pitch") is None
    assert side_of_name("右肩（ピッチ）") == "right" and side_of_name("左膝") == "left"
    assert side_of_name("Left-Elbow") == "left" and side_of_name("elbow_R") == "right"
    assert side_of_name("rear left leg roll") == "left"  # "rear" starts with r, names no side
    assert side_of_name("leg roll") is None and side_of_name("lKnee") == "left"
    assert side_of_name("bright") is None and side_of_name("左右") is None
    assert even_side({2: "l_shoulder_pitch", 3: "r_shoulder_pitch"}) == "left"
    assert even_side({2: "r_shoulder_pitch", 3: "l_shoulder_pitch"}) == "right"


def test_names_that_disagree_say_no_side() -> None:
    """No vote: one name against the others leaves the side open (the index set decides)."""
    assert even_side({2: "右肩", 3: "左肩", 4: "右肘", 5: "左肘", 6: "左膝"}) is None
    assert even_side({2: "head", 3: "waist"}) is None


def test_detection_is_none_when_ambiguous_or_unknown() -> None:
    assert detect_robot({}) is None
    assert detect_robot({i: "x" for i in range(7)}) is None
    # the KHR-3HV index set but named as a KXR (right on even): contradicts the KHR side rule
    khr = load_builtin("khr3hv")
    assert detect_robot({i: ("右" if i % 2 == 0 else "左") + "x" for i in khr.indices}) is None
    # a slot list with names for unused slots: only `indices` count
    kxr = load_builtin("kxr-l2")
    names = {i: f"s{i}" for i in range(36)}
    assert detect_robot(names, kxr.indices) == "kxr-l2"


@given(
    name=st.sampled_from(BUILTIN),
    data=st.data(),
)
def test_value_angle_value_round_trip(name: str, data: st.DataObject) -> None:
    model = load_builtin(name)
    servo = data.draw(st.sampled_from(model.servos))
    trim = data.draw(st.integers(-3000, 3000))
    value = data.draw(st.integers(3500, 11500))
    angle = model.angle(servo.index, value, trim)
    assert model.value(servo.index, angle, trim) == value
    assert model.angles({servo.index: value}, {servo.index: trim}) == {servo.joint: angle}
    # motion space (before the board adds the trim): the trim does not enter
    motion = value - trim
    assert model.motion_angle(servo.index, motion) == angle
    assert model.motion_value(servo.index, angle) == motion
    assert model.motion_angles({servo.index: motion}) == {servo.joint: angle}
    assert model.values({servo.joint: angle}, {servo.index: trim}) == {servo.index: value}
    assert model.motion_values({servo.joint: angle}) == {servo.index: motion}


def test_kxr_home_values_give_home_pose() -> None:
    model = load_builtin("kxr-l2-gripper")
    # the fixture's home pose values (XL2G_291), before trim
    home = {2: 7900, 3: 7100, 4: 7500, 5: 7500, 6: 6300, 7: 6300, 8: 7500, 9: 7500,
            10: 7650, 11: 7650, 12: 7800, 13: 7800, 14: 7650, 15: 7650, 16: 7500,
            17: 7500, 18: 6850, 19: 6850}  # fmt: skip
    angles = model.motion_angles(home)
    for joint, a in model.home.items():
        assert angles[joint] == pytest.approx(a)
    frames = forward(model, angles)
    # arms slightly back, hands in front of the elbows (elbows bent forward)
    for side in ("l_", "r_"):
        elbow = apply(frames[side + "forearm"], (0.0, 0.0, 0.0))
        hand = apply(frames[side + "forearm"], (0.0, 0.0, -0.05))
        assert hand[0] > elbow[0]


def test_cli_list_show_export(tmp_path: Path) -> None:
    runner = CliRunner()
    out = runner.invoke(cli, ["robot", "list", "--json"])
    assert out.exit_code == 0, out.output
    rows = json.loads(out.output)
    assert [r["name"] for r in rows if r["family"] is None] == list(BUILTIN)
    assert {r["family"] for r in rows} >= {"humanoid", "L4D", "L4N", "L4R", "L4T", "L6", "R4LL"}
    out = runner.invoke(cli, ["robot", "show", "khr3hv", "--json"])
    data = json.loads(out.output)
    assert data["servos"] == 17 and data["mass_kg"] == pytest.approx(1.493)
    knee = next(j for j in data["joints"] if j["joint"] == "l_knee_pitch")
    assert (knee["index"], knee["sign"], knee["lower_deg"], knee["upper_deg"]) == (16, 1, -180, 180)
    assert knee["advisory_deg"] == [-60, 135]  # robotlearn's software limits
    out = runner.invoke(cli, ["robot", "show", "kxr-l2-gripper"])
    assert out.exit_code == 0 and "r_gripper" in out.output
    urdf, jmap = tmp_path / "k.urdf", tmp_path / "k.toml"
    out = runner.invoke(
        cli, ["robot", "export", "kxr-l2", "-o", str(urdf), "--joint-map", str(jmap)]
    )
    assert out.exit_code == 0, out.output
    out = runner.invoke(cli, ["robot", "show", str(jmap), "--json"])
    assert json.loads(out.output)["indices"] == list(range(2, 18))
    out = runner.invoke(cli, ["robot", "show", "pepper"])
    assert out.exit_code == 1 and "unknown robot 'pepper'" in out.output


def test_cli_mjcf_export(tmp_path: Path) -> None:
    out = CliRunner().invoke(
        cli, ["robot", "export", "khr3hv", "--format", "mjcf", "-o", str(tmp_path / "k.xml")]
    )
    try:
        import rcb4hv.robot.mjcf  # noqa: F401
    except ModuleNotFoundError:
        assert out.exit_code == 1 and "MJCF export is not available" in out.output
    else:
        assert out.exit_code == 0, out.output
        assert "<mujoco" in (tmp_path / "k.xml").read_text(encoding="utf-8")


def test_cli_mjcf_export_refuses_a_joint_map(tmp_path: Path) -> None:
    """A joint map points a `--robot FILE` at a URDF: with --format mjcf it named the MJCF
    file, which `--robot` then could not read. Refused before anything is written."""
    out = CliRunner().invoke(
        cli,
        ["robot", "export", "kxr-l2", "--format", "mjcf", "-o", str(tmp_path / "k.xml"),
         "--joint-map", str(tmp_path / "k.toml")],
    )  # fmt: skip
    assert out.exit_code == 2 and "--joint-map names a URDF file" in out.output
    assert not (tmp_path / "k.xml").exists() and not (tmp_path / "k.toml").exists()


def test_cli_detect_refuses_a_named_model_that_does_not_fit(kxr_project_path: Path) -> None:
    """``robot detect --robot NAME`` checks the model against the project's servos, as every
    other command does: a KHR-3HV on the fixture's KXR-L2 says which servos are missing."""
    runner = CliRunner()
    r = runner.invoke(cli, ["robot", "detect", str(kxr_project_path), "--robot", "khr3hv"])
    assert r.exit_code == 1
    assert "no servo at index 0 (head_yaw)" in r.output
    r = runner.invoke(
        cli, ["robot", "detect", str(kxr_project_path), "--robot", "kxr-l2-gripper", "--json"]
    )
    assert r.exit_code == 0, r.output
    assert json.loads(r.output)["notes"] == ["chosen with --robot kxr-l2-gripper"]


@pytest.mark.parametrize("code", ["kxr:L6", "kxr:L4T", "kxr:L4D", "kxr:R4LL"])
def test_a_kit_code_the_servo_names_contradict_is_refused_for_every_family(
    kxr_project_path: Path, code: str
) -> None:
    """``--robot kxr:L6`` on the fixture's KXR-L2 humanoid: its ICS numbers 2-19 are also a
    stock KXR-L6's, and the L6 was built on them in silence (右肩（ピッチ） on r_front_yaw,
    hexapod legs in `project poses`, a wrong mirror) where ``kxr:L4T`` was refused. Every
    family is refused alike, naming the servo and the joint, and says how to use it anyway;
    the project's own model is still taken."""
    if not kxr_project_path.is_file():
        pytest.skip("the HeartToHeart4 fixture project is missing")
    from rcb4hv.errors import NoRobotModelError
    from rcb4hv.hth4.robotpick import project_model

    project = load_project(kxr_project_path)
    family = code.removeprefix("kxr:")
    with pytest.raises(NoRobotModelError, match=f"servo names do not fit a KXR-{family}") as e:
        project_model(project, code)
    assert f"右肩（ピッチ）: no {family} joint" in str(e.value)
    assert f"rcb4hv robot export {code} -o X.urdf --joint-map X.toml" in str(e.value)
    if code == "kxr:L6":
        assert "(ICS 2 is the stock r_front_yaw)" in str(e.value)
    r = CliRunner().invoke(cli, ["robot", "detect", str(kxr_project_path), "--robot", code])
    assert r.exit_code == 1 and "右肩（ピッチ）" in r.output
    assert project_model(project, "kxr:L2L5A3G").name == "kxr:L2L5A3G"


def test_the_escape_from_the_name_check_is_a_joint_map(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """The refusal's way out: the kit exported with its joint map, then ``--robot X.urdf``."""
    if not kxr_project_path.is_file():
        pytest.skip("the HeartToHeart4 fixture project is missing")
    runner = CliRunner()
    urdf, jmap = tmp_path / "X.urdf", tmp_path / "X.toml"
    out = runner.invoke(
        cli, ["robot", "export", "kxr:L6", "-o", str(urdf), "--joint-map", str(jmap)]
    )
    assert out.exit_code == 0, out.output
    r = runner.invoke(cli, ["robot", "detect", str(kxr_project_path), "--robot", str(urdf)])
    assert r.exit_code == 0, r.output
    assert "r_front_yaw" in r.output


def test_a_humanoid_code_on_a_hexapod_is_refused_too() -> None:
    """The other way round: a KXR-L6's servo names on the stock KXR-L2's ICS numbers."""
    from rcb4hv.errors import NoRobotModelError
    from rcb4hv.hth4.robotpick import detect_project
    from tests.robot.kit_names import names_for, stock

    _, l6 = stock("kxr:L6")
    names = names_for(l6)
    assert detect_project(names, "kxr:L6")[0].name == "kxr:L6"
    with pytest.raises(NoRobotModelError, match=r"右前脚（元）: no humanoid joint \(ICS 2 is"):
        detect_project(names, "kxr:L2L5A3G")


@pytest.mark.parametrize("blank", ["", "spare"])
def test_servo_names_that_say_nothing_take_any_kit_code(kxr_project_path: Path, blank: str) -> None:
    """Blank or spare servo names contradict no model: any kit code whose stock build's limbs
    the project has is taken on its stock ICS numbers, the other servos left out."""
    if not kxr_project_path.is_file():
        pytest.skip("the HeartToHeart4 fixture project is missing")
    from rcb4hv.hth4.robotpick import detect_project, project_model

    project = load_project(kxr_project_path)
    mute = dataclasses.replace(
        project,
        servos=tuple(
            dataclasses.replace(s, name=f"右拡張{s.device_number}" if blank else "")
            for s in project.servos
        ),
    )
    for code in ("kxr:L6", "kxr:L4T", "kxr:L2", "kxr:R4LL", "kxr:L2L5A3G"):
        assert project_model(mute, code).name.startswith(code), code
    _, det = detect_project(mute, "kxr:L4T")
    assert det is not None and any("left out" in n for n in det.notes)
    assert project_model(mute, "kxr:L6").servo(2).joint == "r_front_yaw"


def test_detect_says_where_the_model_differs_from_its_stock_code() -> None:
    """A kit model whose servo names give it more or fewer joints than the stock build of the
    code printed says so (``robot show`` of that code is the stock build); the stock build
    itself says nothing."""
    from rcb4hv.cli.robot_cmd import _against_stock

    assert _against_stock(load_robot("kxr:L2L6A4H2")) == []
    wheeled = dataclasses.replace(load_robot("kxr:L2W2L6A4H2"), name="kxr:L2L6A4H2")
    (note,) = _against_stock(wheeled)
    assert "stock kxr:L2L6A4H2 has 22" in note and "add l_ankle_wheel, r_ankle_wheel" in note
