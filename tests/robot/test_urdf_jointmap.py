"""URDF export -> import round trip, joint-map files, and their errors."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.builtin import BUILTIN, load_builtin, load_robot
from rcb4hv.robot.jointmap import build_model, load_urdf_robot, parse_joint_map, to_joint_map
from rcb4hv.robot.urdf import parse_urdf, to_urdf

TWO_LINKS = """<robot name="arm">
  <link name="base">
    <inertial><origin xyz="0 0 0.01" rpy="0 0 0"/><mass value="0.2"/>
      <inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>
    <collision><geometry><box size="0.05 0.05 0.02"/></geometry></collision>
  </link>
  <link name="l_upper">
    <inertial><mass value="0.05"/>
      <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
    <visual><geometry><cylinder radius="0.01" length="0.06"/></geometry></visual>
  </link>
  <link name="r_upper">
    <inertial><mass value="0.05"/>
      <inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
  </link>
  <link name="tip">
    <inertial><mass value="0.01"/>
      <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial>
    <visual><geometry><sphere radius="0.005"/></geometry></visual>
  </link>
  <joint name="l_shoulder" type="revolute"><parent link="base"/><child link="l_upper"/>
    <origin xyz="0 0.03 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="2" effort="1" velocity="5"/></joint>
  <joint name="r_shoulder" type="revolute"><parent link="base"/><child link="r_upper"/>
    <origin xyz="0 -0.03 0" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="2" effort="1" velocity="5"/></joint>
  <joint name="tip_fix" type="fixed"><parent link="l_upper"/><child link="tip"/>
    <origin xyz="0 0 -0.06"/></joint>
</robot>
"""

JOINT_MAP = """
title = "two-arm test robot"
[joints.l_shoulder]
index = 3
sign = -1
[joints.r_shoulder]
index = 2
offset = 12
"""


@pytest.mark.parametrize("name", BUILTIN)
def test_urdf_round_trip(name: str, tmp_path: Path) -> None:
    model = load_builtin(name)
    text = to_urdf(model)
    ET.fromstring(text)  # well-formed XML
    (tmp_path / "robot.urdf").write_text(text, encoding="utf-8")
    (tmp_path / "robot.toml").write_text(to_joint_map(model, urdf="robot.urdf"), encoding="utf-8")
    for path in (tmp_path / "robot.urdf", tmp_path / "robot.toml"):
        back = load_robot(path)
        assert back.root == model.root
        assert [link.name for link in back.links] == [link.name for link in model.links]
        for a, b in zip(back.links, model.links, strict=True):
            assert a.inertial.mass == pytest.approx(b.inertial.mass, rel=1e-8)
            assert a.inertial.com == pytest.approx(b.inertial.com, abs=1e-9)
            assert a.inertial.inertia == pytest.approx(b.inertial.inertia, rel=1e-7, abs=1e-12)
            assert len(a.geoms) == len(b.geoms)
            for ga, gb in zip(a.geoms, b.geoms, strict=True):
                assert ga.shape == gb.shape
                assert ga.size == pytest.approx(gb.size, abs=1e-9)
                assert ga.pos == pytest.approx(gb.pos, abs=1e-9)
        for a, b in zip(back.joints, model.joints, strict=True):
            assert (a.name, a.parent, a.child, a.kind, a.side, a.mirror) == (
                b.name, b.parent, b.child, b.kind, b.side, b.mirror)  # fmt: skip
            assert a.xyz == pytest.approx(b.xyz, abs=1e-9)
            assert a.axis == pytest.approx(b.axis)
            assert (a.lower, a.upper) == pytest.approx((b.lower, b.upper), abs=1e-8)
            # the advisory range travels as <safety_controller>'s soft limits
            assert a.advisory_range == pytest.approx(b.advisory_range, abs=1e-8)
            assert (a.advisory is None) == (b.advisory is None)
        assert [(s.index, s.joint, s.sign, s.offset) for s in back.servos] == [
            (s.index, s.joint, s.sign, s.offset) for s in model.servos
        ]
        s0, m0 = back.servos[0].servo, model.servos[0].servo
        assert s0 is not None and m0 is not None
        assert s0.stall_torque == pytest.approx(m0.stall_torque)


def test_urdf_with_fixed_joint_and_inference(tmp_path: Path) -> None:
    urdf = parse_urdf(TWO_LINKS)
    assert [link.name for link in urdf.links] == ["base", "l_upper", "r_upper"]
    upper = next(link for link in urdf.links if link.name == "l_upper")
    # the fixed tip merged in: mass added, centre of mass moved towards it
    assert upper.inertial.mass == pytest.approx(0.06)
    assert upper.inertial.com[2] == pytest.approx(-0.01)
    assert [g.shape for g in upper.geoms] == ["cylinder", "sphere"]
    model = build_model(urdf, parse_joint_map(JOINT_MAP), "arm")
    left = model.joint("l_shoulder")
    assert (left.kind, left.side, left.mirror) == ("pitch", "left", "r_shoulder")
    assert model.joint("r_shoulder").side == "right"
    assert model.servo(3).sign == -1 and model.servo(2).offset == 12
    assert model.title == "two-arm test robot"
    # servo figures come from the URDF limits when the map gives none
    spec = model.servo(2).servo
    assert spec is not None and spec.stall_torque == 1.0
    assert model.motion_angle(2, 7500 + 12) == 0.0


def test_joint_map_errors(tmp_path: Path) -> None:
    urdf = parse_urdf(TWO_LINKS)
    with pytest.raises(RobotModelError, match="lacks: elbow"):
        build_model(urdf, parse_joint_map("[joints.elbow]\nindex = 4\n"), "arm")
    with pytest.raises(RobotModelError, match="index must be"):
        parse_joint_map("[joints.l_shoulder]\nindex = 40\n")
    with pytest.raises(RobotModelError, match="sign must be"):
        parse_joint_map("[joints.l_shoulder]\nindex = 4\nsign = 2\n")
    with pytest.raises(RobotModelError, match="not TOML"):
        parse_joint_map("[joints")
    with pytest.raises(RobotModelError, match="mirrors unknown"):
        build_model(urdf, parse_joint_map('[joints.l_shoulder]\nindex = 4\nmirror = "x"\n'), "a")
    path = tmp_path / "arm.urdf"
    path.write_text(TWO_LINKS, encoding="utf-8")
    with pytest.raises(RobotModelError, match=r"needs a joint map.*--joint-map FILE. writes one"):
        load_urdf_robot(path)


def test_urdf_errors() -> None:
    no_inertia = TWO_LINKS.replace(
        '<inertial><mass value="0.01"/>\n      <inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" '
        'iyz="0" izz="1e-6"/></inertial>',
        "",
    )
    with pytest.raises(RobotModelError, match="link 'tip': link has no <inertial>"):
        parse_urdf(no_inertia)
    with pytest.raises(RobotModelError, match="not XML"):
        parse_urdf("<robot")
    with pytest.raises(RobotModelError, match="not <robot>"):
        parse_urdf("<sdf/>")
    with pytest.raises(RobotModelError, match="'prismatic' joints are not supported"):
        parse_urdf(TWO_LINKS.replace('type="revolute"', 'type="prismatic"', 1))


def test_inertia_origin_rotation_is_applied() -> None:
    # a rod along x described in a frame turned 90° about z is a rod along y
    text = TWO_LINKS.replace(
        '<origin xyz="0 0 0.01" rpy="0 0 0"/><mass value="0.2"/>\n      <inertia ixx="1e-4" '
        'ixy="0" ixz="0" iyy="1e-4"',
        f'<origin xyz="0 0 0.01" rpy="0 0 {math.pi / 2}"/><mass value="0.2"/>\n      '
        '<inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-4"',
    )
    base = parse_urdf(text).links[0]
    ixx, iyy, izz = base.inertial.inertia[:3]
    assert ixx == pytest.approx(1e-4) and iyy == pytest.approx(1e-5) and izz == pytest.approx(1e-4)
