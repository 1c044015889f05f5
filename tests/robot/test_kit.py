"""The KXR kit builder and project -> model detection, on synthetic servo tables."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from rcb4hv.errors import AmbiguousRobotError, NoRobotModelError
from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
from rcb4hv.hth4.project import load_project
from rcb4hv.hth4.robotpick import (
    detect_project,
    home_pose,
    motion_extremes,
    project_model,
    servo_table,
)
from rcb4hv.robot.builtin import load_robot
from rcb4hv.robot.kit import detect_kit, parse_kit_code, parse_servo_name
from rcb4hv.robot.kit.figures import FIGURES, SOURCES
from tests.robot.kit_names import home_values, names_for, stock


@pytest.mark.parametrize(
    ("title", "family", "legs", "arms", "head", "gripper", "wheels"),
    [
        ("Hello_KXR-L2GH(V1.0)", "humanoid", None, None, 2, True, False),
        ("Hello_KXR-L2W2L6A4H2", "humanoid", 6, 4, 2, False, True),
        ("Hello_KXR-L4D(V1.0)", "L4D", None, None, None, False, False),
        ("Hello_KXR-L4R(V1.1)", "L4R", None, None, None, False, False),
        ("Hello_KXR-L4T(V1.1)", "L4T", None, None, None, False, False),
        ("Hello_KXR-L6(V1.0)", "L6", None, None, None, False, False),
        ("KXR-R4LL(V1.2)", "R4LL", None, None, None, False, False),
        ("kxr:l2gl6a7h2w", "humanoid", 6, 7, 2, True, False),
        ("Hello_kxra6g", "humanoid", 2, 6, None, True, False),
    ],
)
def test_kit_codes_in_titles(
    title: str, family: str, legs: int | None, arms: int | None, head: int | None,
    gripper: bool, wheels: bool,
) -> None:  # fmt: skip
    code = parse_kit_code(title)
    assert code is not None
    assert (code.family, code.legs, code.arms, code.head, code.gripper, code.wheels) == (
        family, legs, arms, head, gripper, wheels,
    )  # fmt: skip
    assert parse_kit_code("Hello_KHR3(V2.3)") is None
    assert parse_kit_code("HAC-KXR") is None


@pytest.mark.parametrize(
    ("name", "side", "part", "axis", "position", "segment"),
    [
        ("右肩（ピッチ）", "right", "shoulder", "pitch", None, None),
        ("左膝", "left", "knee", None, None, None),
        ("首ヨー", "centre", "neck", "yaw", None, None),
        ("右前脚（ロール）", "right", "leg", "roll", "front", None),
        ("右後足車輪", "right", "wheel", None, "rear", None),
        ("右中脚（先）", "right", "leg", None, "middle", "tip"),
        ("左前足 元", "left", "leg", None, "front", "root"),
        ("R shoulder pitch", "right", "shoulder", "pitch", None, None),
        ("left knee", "left", "knee", None, None, None),
        ("neck yaw", "centre", "neck", "yaw", None, None),
        ("right front leg roll", "right", "leg", "roll", "front", None),
        ("right rear wheel", "right", "wheel", None, "rear", None),
        ("right middle leg tip", "right", "leg", None, "middle", "tip"),
        ("rear left leg roll", "left", "leg", "roll", "rear", None),  # robot.model.side_of_name
        ("leg roll", "centre", "leg", "roll", None, None),
    ],
)
def test_servo_names(
    name: str, side: str, part: str, axis: str | None, position: str | None, segment: str | None
) -> None:
    role = parse_servo_name(name)
    assert role is not None
    assert (role.side, role.part, role.axis, role.position, role.segment) == (
        side, part, axis, position, segment,
    )  # fmt: skip


def test_spares_carry_no_joint() -> None:
    assert parse_servo_name("右拡張3") is None
    assert parse_servo_name("spare 2") is None
    assert parse_servo_name("") is None


# home poses (degrees) that stand each legged family on its feet or wheels
STAND = {
    "kxr:L6": {f"{s}_{p}_knee": d for s in "lr" for p, d in (("front", 70), ("rear", -70))}
    | {"r_middle_knee": 70, "l_middle_knee": -70},
    "kxr:L4T": {"r_front_roll": 60, "l_front_roll": -60, "r_rear_roll": 60, "l_rear_roll": -60},
    "kxr:L4N": {"r_front_roll": 60, "l_front_roll": -60, "r_rear_roll": 60, "l_rear_roll": -60},
    "kxr:L4R2A3G": {"r_arm_roll": 15, "l_arm_roll": -15},
}
CODES = ["kxr:L2GH", "kxr:L2W2L6A4H2", "kxr:A6G", "kxr:L2GL6A7H2W", "kxr:L6", "kxr:L4T",
         "kxr:L4N", "kxr:L4R", "kxr:L4R2A3G", "kxr:L4D", "kxr:R4LL"]  # fmt: skip


@pytest.mark.parametrize("text", CODES)
def test_each_family_is_detected_from_its_names_and_stands_at_home(text: str) -> None:
    from rcb4hv.physics.world import PhysicsWorld

    code, model = stock(text)
    names = names_for(model)
    home = home_values(model, STAND.get(text, {}))
    det = detect_kit(f"Hello_KXR-{code.code}(V1.0)", names, home)
    assert det.model.name == model.name
    assert {(s.index, s.joint, s.sign) for s in det.model.servos} == {
        (s.index, s.joint, s.sign) for s in model.servos
    }
    assert all(ok for _, ok, _ in det.checks), det.checks
    world = PhysicsWorld(det.model)
    world.place(dict(det.model.home))
    for index, servo in world.servos.items():
        world.drive(index, det.model.home.get(servo.joint, 0.0), world.stiffness(index, None))
    torso_bottom = min(g.pos[2] - g.size[2] / 2 for g in det.model.link("torso").geoms)
    world.step(500)  # 1 s
    base = world.base()
    assert base.tilt < math.radians(10)
    assert base.z + torso_bottom > 0.005  # the torso is off the floor


def test_a_six_legged_project_is_never_the_l2_with_grippers(kxr_project_path: Path) -> None:
    project = load_project(kxr_project_path)
    _, l6 = stock("kxr:L6")
    names = names_for(l6)
    servos = tuple(
        dataclasses.replace(s, name=names[s.device_number]) if s.device_number in names else s
        for s in project.servos
    )
    six = dataclasses.replace(project, servos=servos, project_title="")
    assert sorted(names) == sorted(load_robot("kxr-l2-gripper").indices)  # same ICS numbers
    assert project_model(six).name == "kxr:L6"
    titled = dataclasses.replace(six, project_title="Hello_KXR-L6(V1.0)")
    model, det = detect_project(titled)
    assert model.name == "kxr:L6" and det is not None
    assert det.servos[0][2:] == ("r_front_yaw", -1)


def test_the_fixture_keeps_its_builtin_model_with_a_kit_title(kxr_project_path: Path) -> None:
    project = load_project(kxr_project_path)
    assert project_model(project).name == "kxr-l2-gripper"
    titled = dataclasses.replace(project, project_title="Hello_KXR-L2G(V1.0)")
    model, det = detect_project(titled)
    assert model.name == "kxr-l2-gripper" and det is not None
    assert [c for c, ok, _ in det.checks if not ok] == []


def test_home_pose_is_where_the_home_motion_leaves_the_servos(kxr_project_path: Path) -> None:
    """A home motion whose last pose moves only two servos (as Kondo's Hello_kxrl4nh4 does):
    the others stay where its earlier poses put them."""
    project = load_project(kxr_project_path)
    poses = [
        Keyframe(0.3, {10: 7650, 11: 7350, 12: 7800, 13: 7200}),
        Keyframe(0.6, {12: 7900, 13: 7100}),
    ]
    motion = motion_from_keyframes(poses, slot=1, name="ホームポジション", changed_only=True)
    home = home_pose(add_motion(project, motion, replace_used=True))
    assert home == {10: 7650, 11: 7350, 12: 7900, 13: 7100}


def test_home_pose_symmetry_turns_a_reversed_left_sign(kxr_project_path: Path) -> None:
    """A project whose left knee is mounted the other way: its home pose bends the left knee
    with the opposite value, so detection turns the left sign and says so."""
    project = load_project(kxr_project_path)
    project = dataclasses.replace(  # the fixture's own home motion out of the way
        project,
        motions=tuple(
            dataclasses.replace(m, name="old") if "ホーム" in (m.name or "") else m
            for m in project.motions
        ),
    )
    home = {13: 7200, 12: 7800, 10: 7650, 11: 7650, 14: 7650, 15: 7650}
    motion = motion_from_keyframes([Keyframe(0.5, home)], slot=120, name="ホームポジション")
    titled = add_motion(
        dataclasses.replace(project, project_title="Hello_KXR-L2G(V1.0)"), motion,
        replace_used=True,
    )  # fmt: skip
    model, det = detect_project(titled)
    assert det is not None
    assert model.servo(13).sign == -model.servo(12).sign
    assert any("l_knee_pitch" in n for n in det.notes)


def test_an_ambiguous_project_lists_candidates() -> None:
    _, l4t = stock("kxr:L4T")
    names = {i: n for i, n in names_for(l4t).items() if "首" not in n}  # legs only
    with pytest.raises(AmbiguousRobotError) as err:
        detect_kit("my turtle", names)
    assert set(err.value.candidates) == {"kxr:L4T", "kxr:L4N"}
    assert detect_kit("my turtle", names, force=parse_kit_code("kxr:L4N")).model.name == "kxr:L4N"
    model, _ = detect_project(names, "kxr:L4T")
    assert model.name == "kxr:L4T"
    with pytest.raises(NoRobotModelError):
        detect_kit("", {2: "servo 2", 3: "servo 3"})


def test_title_and_names_disagree_names_win_and_say_so() -> None:
    _, model = stock("kxr:L2L5A3H2G")
    det = detect_kit("Hello_KXR-L2L6A4H2G", names_for(model))
    assert det.model.name == "kxr:L2L5A3H2G"
    assert any("legs 6" in n for n in det.notes) and any("arms 4" in n for n in det.notes)


def test_every_figure_names_a_known_source() -> None:
    assert FIGURES
    for key, f in FIGURES.items():
        assert f.source in SOURCES, key
        assert f.where, key


def test_cli_detect_list_show(kxr_project_path: Path, tmp_path: Path) -> None:
    import json

    from click.testing import CliRunner

    from rcb4hv.cli.main import cli
    from rcb4hv.hth4 import dump_project

    project = load_project(kxr_project_path)
    _, l6 = stock("kxr:L6")
    names = names_for(l6)
    servos = tuple(
        dataclasses.replace(s, name=names[s.device_number]) if s.device_number in names else s
        for s in project.servos
    )
    path = tmp_path / "six.h4p"
    path.write_bytes(
        dump_project(dataclasses.replace(project, servos=servos, project_title="Hello_KXR-L6"))
    )
    runner = CliRunner()
    out = runner.invoke(cli, ["robot", "detect", str(path), "--json"])
    assert out.exit_code == 0, out.output
    data = json.loads(out.output)
    assert data["model"] == "kxr:L6" and data["family"] == "L6"
    assert {"index": 19, "name": "左後脚（先）", "joint": "l_rear_knee", "sign": -1} in data[
        "servos"
    ]
    out = runner.invoke(cli, ["robot", "detect", str(path)])
    assert out.exit_code == 0 and "kxr:L6" in out.output
    out = runner.invoke(cli, ["robot", "list"])
    assert out.exit_code == 0 and "kxr:L4T" in out.output and "R4LL" in out.output
    out = runner.invoke(cli, ["robot", "show", "kxr:L2W2L6A4H2", "--json"])
    assert out.exit_code == 0
    shown = json.loads(out.output)
    assert shown["name"] == "kxr:L2W2L6A4H2"
    assert {j["joint"] for j in shown["joints"]} >= {"r_ankle_wheel", "l_hip_yaw", "neck_pitch"}
    mjcf = tmp_path / "l6.xml"
    out = runner.invoke(cli, ["robot", "export", "kxr:L6", "--format", "mjcf", "-o", str(mjcf)])
    assert out.exit_code == 0 and "<mujoco" in mjcf.read_text()


def test_names_for_the_other_side_follow_the_wiring_and_say_so() -> None:
    _, l4t = stock("kxr:L4T")
    swapped = {
        i: n.replace("右", "X").replace("左", "右").replace("X", "左")
        for i, n in names_for(l4t).items()
    }
    det = detect_kit("Hello_KXR-L4T(V1.1)", swapped)
    assert det.model.servo(2).joint == "r_front_yaw"  # even ICS = right, whatever the name
    assert any("named for the other side" in n for n in det.notes)


def test_the_editor_offers_the_candidates_of_an_ambiguous_project(kxr_project_path: Path) -> None:
    from rcb4hv.hth4 import dump_project
    from rcb4hv.ui.editor_state import Editor

    project = load_project(kxr_project_path)
    _, l4t = stock("kxr:L4T")
    names = {i: n for i, n in names_for(l4t).items() if "首" not in n}  # legs only: L4T or L4N
    servos = tuple(
        dataclasses.replace(s, name=names.get(s.device_number, s.name or ""),
                            mode="Normal" if s.device_number in names else "None")
        for s in project.servos
    )  # fmt: skip
    ed = Editor()
    ed.open(dump_project(dataclasses.replace(project, servos=servos, project_title="turtle")))
    assert ed.model is None and set(ed.model_candidates) == {"kxr:L4T", "kxr:L4N"}
    ed.pick_robot("kxr:L4T")
    assert ed.model is not None and ed.model.name == "kxr:L4T" and ed.model_candidates == ()


def test_docs_render_the_provenance_table() -> None:
    from rcb4hv.robot.kit.figures import provenance_markdown

    docs = (Path(__file__).resolve().parents[2] / "docs" / "robots.md").read_text("utf-8")
    assert provenance_markdown() in docs


def test_cli_detect_lists_the_candidates_of_an_ambiguous_project(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    import json

    from click.testing import CliRunner

    from rcb4hv.cli.main import cli
    from rcb4hv.hth4 import dump_project

    project = load_project(kxr_project_path)
    _, l4t = stock("kxr:L4T")
    names = {i: n for i, n in names_for(l4t).items() if "首" not in n}
    servos = tuple(
        dataclasses.replace(s, name=names.get(s.device_number, s.name or ""),
                            mode="Normal" if s.device_number in names else "None")
        for s in project.servos
    )  # fmt: skip
    path = tmp_path / "turtle.h4p"
    path.write_bytes(dump_project(dataclasses.replace(project, servos=servos, project_title="")))
    out = CliRunner().invoke(cli, ["robot", "detect", str(path), "--json"])
    assert out.exit_code != 0
    data = json.loads(out.output[: out.output.rindex("}") + 1])
    assert data["model"] is None and set(data["candidates"]) == {"kxr:L4T", "kxr:L4N"}
    out = CliRunner().invoke(cli, ["robot", "detect", str(path), "--robot", "kxr:L4T"])
    assert out.exit_code == 0 and "kxr:L4T" in out.output


def test_an_arm_yaw_name_is_the_shoulder_yaw() -> None:
    _, model = stock("kxr:L2W2L6A4H2")
    names = names_for(model)
    names[22], names[23] = "右腕ヨー", "左腕ヨー"  # Kondo's name for the upper arm's yaw
    names[20], names[21] = "右車輪", "左車輪"
    det = detect_kit("Hello_KXR-L2W2L6A4h2", names)
    assert det.model.name == "kxr:L2W2L6A4H2"
    assert det.model.servo(22).joint == "r_shoulder_yaw"
    assert det.model.servo(20).joint == "r_ankle_wheel"


def test_the_l4r2a3g_front_rolls_on_free_wheels() -> None:
    """kxreus's L4R2A3G has a passive wheel beside each arm (``:passive-wheel :shoulder``):
    no servo drives it, and the robot stands on it and its two driven rear wheels."""
    from rcb4hv.robot.balance import rigid_balance

    _, model = stock("kxr:L4R2A3G")
    wheels = ("l_arm_wheel", "r_arm_wheel")
    assert all(model.joint(w).kind == "wheel" for w in wheels)
    assert all(model.servo_for_joint(w) is None for w in wheels)
    # its home (kxreus's Hello_KXR-l4r2a3g, counts from 7500): the arms turned forward on the
    # front yaw joints (∓2667) and raised (arm roll ∓3300, elbow ∓2500)
    deg = {"front_yaw": 90.0, "arm_roll": -111.4, "arm_elbow": 84.4}
    home = {j.name: 0.0 for j in model.joints}
    for base, d in deg.items():
        home["r_" + base], home["l_" + base] = math.radians(d), math.radians(-d)
    b = rigid_balance(model, home)
    assert b.balanced
    assert set(b.contacts) == {f"{w}_link" for w in (*wheels, "l_rear_wheel", "r_rear_wheel")}
    _, plain = stock("kxr:L4R2A3")
    assert not any(j.name.endswith("arm_wheel") for j in plain.joints)


def test_the_l4r2a3_front_yaw_is_an_arm_bracket_whatever_the_title_says() -> None:
    """Kondo's Hello_KXR-l4r2a3 is titled ``Hello_KXR-L4R``: its servo names make it the
    L4R2A3, and its front yaw joints then carry arms, not the L4R's wheel legs (kxreus's
    kxrl4r2a3 rarm-shoulder-y: a bracket out to the shoulder roll, nothing below the joint)."""
    _, arms = stock("kxr:L4R2A3")
    det = detect_kit("Hello_KXR-L4R", names_for(arms))
    _, legs = stock("kxr:L4R")
    for model, lowest in ((det.model, -0.0131), (legs, -0.0236)):
        link = model.link("l_front_yaw_link")
        bottom = min(g.pos[2] - g.size[2] / 2 for g in link.geoms)
        assert bottom == pytest.approx(lowest, abs=1e-3), model.name
    assert det.model.name == "kxr:L4R2A3"


def test_motions_past_the_mechanical_limits_turn_a_pair_of_signs(kxr_project_path: Path) -> None:
    """kxreus's seven-axis arm maps the shoulder rolls +1 / -1 (ICS 4 / 5), the basic arm -1 /
    +1. Kondo's motions, copied into the seven-axis builds' projects, raise both arms
    sideways with 10300 on ICS 4 and 5 (the goalkeeper): with the seven-axis signs that is
    94.5° inward, 64.5° past the 30° where the arm meets the body. The motions are valid on
    the real robot, so detection turns both signs and says so; the home pose (both at 7500)
    cannot tell."""
    code, model = stock("kxr:L2L6A7H2G")
    assert (model.servo(4).sign, model.servo(5).sign) == (1, -1)
    names, home = names_for(model), home_values(model, {})
    title = f"Hello_KXR-{code.code}(V1.0)"
    extremes = {4: (7500, 10300), 5: (7500, 10300), 12: (7500, 8700), 13: (7500, 8700)}
    det = detect_kit(title, names, home, extremes=extremes)
    assert (det.model.servo(4).sign, det.model.servo(5).sign) == (-1, 1)
    assert math.degrees(det.model.motion_angle(4, 10300)) == pytest.approx(-94.5, abs=0.1)
    assert det.notes == (
        "shoulder_roll: both signs turned: the project's motions go 64° past its mechanical "
        "limits with the kit's convention and stay inside them so",
    )
    assert ("motions within the mechanical limits", True, "every joint") in det.checks
    # without the motions, or with motions inside the limits, the kit's convention stands
    assert detect_kit(title, names, home).model.servo(4).sign == 1
    inside = detect_kit(title, names, home, extremes={4: (7000, 7800), 5: (7200, 8000)})
    assert inside.model.servo(4).sign == 1 and inside.notes == ()
    # a pair no sign keeps inside is left as it is and reported
    both = detect_kit(title, names, home, extremes={4: (3500, 11500), 5: (3500, 11500)})
    assert both.model.servo(4).sign == 1
    assert ("motions within the mechanical limits", False, "shoulder_roll (105° past)") in (
        both.checks
    )
    # the fixture (three-axis arms): its motions fit the kit's convention; values past the
    # servo's travel (2100, 12900: pushing a joint to its end) are not counted
    project = load_project(kxr_project_path)
    ext = motion_extremes(project)
    assert ext[2][0] >= 3500 and ext[3][1] <= 11500
    det_f = detect_kit(None, servo_table(project), home_pose(project), extremes=ext)
    assert det_f.model.name == "kxr:L2L5A3G" and det_f.notes == ()
    assert ("motions within the mechanical limits", True, "every joint") in det_f.checks


@pytest.mark.parametrize("code", ["kxr:R4LL", "kxr:L2W2L6A4H2"])
def test_an_exported_wheeled_kit_reads_back(code: str, tmp_path: Path) -> None:
    """`robot export --joint-map` of a kit with wheels, then `--robot FILE`: the same joint
    map, wheels included (reading it back failed: "kind must be one of pitch, roll, yaw,
    grip")."""
    from click.testing import CliRunner

    from rcb4hv.cli.main import cli

    urdf, jmap = tmp_path / "robot.urdf", tmp_path / "robot.toml"
    r = CliRunner().invoke(
        cli, ["robot", "export", code, "-o", str(urdf), "--joint-map", str(jmap)]
    )
    assert r.exit_code == 0, r.output
    kit, back = load_robot(code), load_robot(str(jmap))
    assert {(s.index, s.joint, s.sign) for s in back.servos} == {
        (s.index, s.joint, s.sign) for s in kit.servos
    }
    wheels = {j.name for j in kit.joints if j.kind == "wheel"}
    assert wheels and wheels == {j.name for j in back.joints if j.kind == "wheel"}


@pytest.mark.parametrize("code", ["kxr:L4T", "kxr:L4N", "kxr:L4R", "kxr:L4D"])
def test_the_head_sits_on_the_body(code: str) -> None:
    """The neck joint is kxreus's, 28.5 mm above the model's body box: the head floated over
    the body in the 3D view until the body carried its neck servo's case up to the joint."""
    from rcb4hv.robot.builtin import load_robot
    from rcb4hv.robot.kinematics import forward

    model = load_robot(code)
    frames = forward(model, {j.name: 0.0 for j in model.joints})

    def boxes(link: str) -> list[tuple[list[float], list[float]]]:
        out = []
        for g in next(k for k in model.links if k.name == link).geoms:
            t = frames[link]
            c = [sum(t[i][j] * g.pos[j] for j in range(3)) + t[i][3] for i in range(3)]
            half = [sum(abs(t[i][j]) * g.size[j] / 2 for j in range(3)) for i in range(3)]
            out.append(([c[i] - half[i] for i in range(3)], [c[i] + half[i] for i in range(3)]))
        return out

    neck = next(j for j in model.joints if j.name.startswith("neck"))
    gap = min(
        max(max(a0[i] - b1[i], b0[i] - a1[i], 0.0) for i in range(3))
        for a0, a1 in boxes(neck.child)
        for b0, b1 in boxes(neck.parent)
    )
    assert gap < 0.001
