"""The built-in robot models: structure, joint maps, limits, masses, mirror symmetry, FK."""

from __future__ import annotations

import math

import pytest

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.builtin import BUILTIN, load_builtin, load_robot
from rcb4hv.robot.ik import effector_point
from rcb4hv.robot.kinematics import apply, center_of_mass, forward
from rcb4hv.robot.kit import kit_model, parse_kit_code
from rcb4hv.robot.kit.figures import fig
from rcb4hv.robot.model import RobotModel

# FACTS.md: KHR-3HV index -> sign (kxreus "khr"/"khr20")
KHR_FACT_SIGNS = {0: -1, 2: -1, 3: 1, 4: 1, 5: 1, 8: 1, 9: -1, 12: 1, 13: 1, 14: -1, 15: 1,
                  16: 1, 17: -1, 18: 1, 19: -1, 20: -1, 21: -1, 1: -1, 10: 1, 11: 1}  # fmt: skip
KHR_STANDARD = {0, 2, 3, 4, 5, 8, 9, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21}
# FACTS.md: KHR-3HV index -> (lower, upper) servo degrees (robotlearn docs/limits.png),
# written out here so the model is checked against the source, not against itself
KHR_LIMITS_DEG = {0: (-135, 135), 2: (-90, 105), 3: (-105, 90), 4: (-30, 180), 5: (-180, 30),
                  8: (-130, 30), 9: (-30, 130), 12: (0, 30), 13: (-30, 0), 14: (-90, 90),
                  15: (-90, 90), 16: (-60, 135), 17: (-135, 60), 18: (-100, 120),
                  19: (-120, 100), 20: (-25, 90), 21: (-90, 25)}  # fmt: skip


def _model(name: str) -> RobotModel:
    return load_builtin(name)


@pytest.mark.parametrize(
    ("name", "servos", "links", "mass"),
    [
        ("khr3hv", 17, 18, 1.493),
        ("khr3hv-22", 22, 23, 1.493 + 5 * 0.0415),
        # kxrl2l5a3.json's total, every servo case a KRS-3304R2 (35.03 g, not kxreus's 27.73)
        ("kxr-l2", 16, 17, 1.13568 + 16 * (0.03503 - 0.02773)),
        # every link the weighed builds' (torso contents and legs, the A3 arm with its gripper)
        ("kxr-l2-gripper", 18, 19, 1.350472),
    ],
)
def test_model_counts_and_mass(name: str, servos: int, links: int, mass: float) -> None:
    m = _model(name)
    assert len(m.servos) == servos
    assert len(m.joints) == servos  # every joint is driven by one servo
    assert len(m.links) == links
    assert m.mass == pytest.approx(mass, abs=1e-6)
    for link in m.links:
        assert link.inertial.mass > 0
        ixx, iyy, izz = link.inertial.inertia[:3]
        # a physical inertia tensor: positive and obeys the triangle inequality
        assert ixx > 0 and iyy > 0 and izz > 0
        assert ixx + iyy >= izz and iyy + izz >= ixx and ixx + izz >= iyy
        assert link.geoms


def test_khr_joint_map_matches_facts() -> None:
    std = _model("khr3hv")
    full = _model("khr3hv-22")
    assert set(std.indices) == KHR_STANDARD
    assert set(full.indices) == set(range(22))
    for m in (std, full):
        for s in m.servos:
            if s.index in KHR_FACT_SIGNS:
                assert s.sign == KHR_FACT_SIGNS[s.index], s
            # side 0 (even index) is the KHR-3HV's left
            side = m.joint(s.joint).side
            if side != "centre":
                assert side == ("left" if s.index % 2 == 0 else "right")
            assert s.servo is not None and s.servo.name == "KRS-2552RHV"


def test_khr_limits_hard_is_generous_advisory_covers_robotlearn() -> None:
    for m in (_model("khr3hv"), _model("khr3hv-22")):
        for s in m.servos:
            j = m.joint(s.joint)
            # hard: no public bracket stops, so a generous +-180 deg
            assert math.degrees(j.lower) == pytest.approx(-180.0)
            assert math.degrees(j.upper) == pytest.approx(180.0)
            if s.index not in KHR_LIMITS_DEG:
                assert j.advisory is None
                continue
            # advisory: robotlearn's software limits (joint = sign x servo), widened to what
            # Kondo's own sample motions use
            lo, hi = sorted(s.sign * a for a in KHR_LIMITS_DEG[s.index])
            a_lo, a_hi = (math.degrees(a) for a in j.advisory_range)
            assert a_lo <= lo + 1e-9 and a_hi >= hi - 1e-9
    # the hip roll: robotlearn stops it at 0 deg inward; Kondo's walks go 2-4 deg past that
    lo, hi = _model("khr3hv").joint("l_hip_roll").advisory_range
    assert math.degrees(lo) < -3.4 and math.degrees(hi) == pytest.approx(30.0)


def test_kxr_joint_map_right_is_even() -> None:
    m = _model("kxr-l2-gripper")
    assert set(m.indices) == set(range(2, 20))
    assert set(_model("kxr-l2").indices) == set(range(2, 18))
    for s in m.servos:
        assert m.joint(s.joint).side == ("right" if s.index % 2 == 0 else "left")
        assert s.servo is not None and s.servo.name == "KRS-3304R2"


@pytest.mark.parametrize("name", BUILTIN)
def test_mirror_symmetry(name: str) -> None:
    m = _model(name)
    for j in m.joints:
        if j.side == "centre":
            assert j.mirror is None
            continue
        assert j.mirror is not None
        o = m.joint(j.mirror)
        assert o.mirror == j.name and o.side != j.side and o.kind == j.kind
        assert o.xyz == pytest.approx((j.xyz[0], -j.xyz[1], j.xyz[2]))
        if j.kind in ("roll", "yaw"):
            assert (o.lower, o.upper) == pytest.approx((-j.upper, -j.lower))
        else:
            assert (o.lower, o.upper) == pytest.approx((j.lower, j.upper))
        assert m.link(o.child).inertial.mass == pytest.approx(m.link(j.child).inertial.mass)
    # a pose and its mirror image put the centre of mass at mirrored y
    pose = {j.name: 0.3 * (j.lower + j.upper) / 2 + 0.1 for j in m.joints}
    pose = {n: min(max(a, m.joint(n).lower), m.joint(n).upper) for n, a in pose.items()}
    com = center_of_mass(m, forward(m, pose))
    com_m = center_of_mass(m, forward(m, m.mirror_angles(pose)))
    assert com_m == pytest.approx((com[0], -com[1], com[2]), abs=1e-9)


@pytest.mark.parametrize(
    ("name", "sole_height"),
    [
        ("khr3hv", 0.2546),  # hip yaw level: 22.35 + 38.7 + 65 + 65 + 37 + 26.5 mm
        ("khr3hv-22", 0.2546),
        ("kxr-l2", 0.174976),  # 28 + 58 + 57.976 + 31 mm below kxreus's torso origin
        ("kxr-l2-gripper", 0.174976),
    ],
)
def test_standing_pose_fk(name: str, sole_height: float) -> None:
    m = _model(name)
    frames = forward(m, {})
    # at the zero pose the soles are flat, at the bottom, the left one at +y
    for side, sign in (("l_", 1.0), ("r_", -1.0)):
        foot = m.link(side + "foot")
        sole = next(g for g in foot.geoms if g.size[0] > 0.05)
        bottom = apply(
            frames[foot.name], (sole.pos[0], sole.pos[1], sole.pos[2] - sole.size[2] / 2)
        )
        assert bottom[2] == pytest.approx(-sole_height, abs=1e-4)
        assert sign * bottom[1] > 0.01
    for link in m.links:
        for g in link.geoms:
            centre = apply(frames[link.name], g.pos)
            assert centre[2] > -sole_height
    # in the home pose the centre of mass is over the support polygon (between the feet)
    home = forward(m, m.home)
    com = center_of_mass(m, home)
    lf, rf = (apply(home[s + "foot"], (0.0, 0.0, 0.0)) for s in ("l_", "r_"))
    assert rf[1] < com[1] < lf[1]
    assert abs(com[0] - (lf[0] + rf[0]) / 2) < 0.03


def test_kxr_home_pose_bends_knees() -> None:
    m = _model("kxr-l2-gripper")
    # the fixture's home pose: knees bent (positive), hip and ankle pitch level the torso
    for side in ("l_", "r_"):
        knee, hip, ankle = (m.home[side + j] for j in ("knee_pitch", "hip_pitch", "ankle_pitch"))
        assert knee > 0
        assert hip < 0 and ankle < 0
        assert hip + knee + ankle == pytest.approx(0.0, abs=1e-9)  # soles parallel to torso
        assert m.joint(side + "knee_pitch").lower <= knee <= m.joint(side + "knee_pitch").upper
    assert m.out_of_limits(m.home) == []
    assert m.out_of_limits(
        {"l_knee_pitch": m.joint("l_knee_pitch").upper + 0.01, "r_knee_pitch": 0.0}
    ) == ["l_knee_pitch"]
    # knee bend moves the ankle backwards (-x): the robot faces +x
    frames = forward(m, {"l_knee_pitch": 0.5})
    assert apply(frames["l_ankle"], (0.0, 0.0, 0.0))[0] < -0.01


def test_unknown_robot_lists_choices() -> None:
    with pytest.raises(RobotModelError, match="khr3hv, khr3hv-22, kxr-l2, kxr-l2-gripper"):
        load_builtin("khr4")
    with pytest.raises(RobotModelError, match="unknown robot"):
        load_robot("nao")
    with pytest.raises(RobotModelError, match="no such robot file"):
        load_robot("missing/robot.urdf")
    assert load_robot("kxr-l2") is load_builtin("kxr-l2")


def test_the_basic_kxr_l2_arm_ends_at_the_elbow_servo_s_joint_base() -> None:
    """kxreus's basic KXR-L2 (kxrl2l5a3) ends each arm with the elbow servo and the joint base
    at its end, 32.6 mm below the elbow axis; the gripper build reaches on to its finger."""
    basic, gripper = load_builtin("kxr-l2"), load_builtin("kxr-l2-gripper")
    for side in ("l", "r"):
        tip = effector_point(basic, f"{side}_forearm")
        assert tip[2] == pytest.approx(-0.0326)
        top = max(g.pos[2] + g.size[2] / 2 for g in basic.link(f"{side}_forearm").geoms)
        assert top == pytest.approx(0.013)  # the elbow servo's case, 26 mm about its axis
        bottom = min(g.pos[2] - g.size[2] / 2 for g in basic.link(f"{side}_forearm").geoms)
        assert bottom == pytest.approx(-0.0326)
    finger = gripper.joint("r_gripper")
    assert finger.xyz[2] == pytest.approx(-0.0655)  # kxrl2g.l's gripper joint below the elbow
    (box,) = gripper.link("r_finger").geoms
    assert finger.xyz[2] + box.pos[2] - box.size[2] / 2 == pytest.approx(-0.1005)


def test_the_kxr_l2_is_the_kit_builder_s_model_of_its_kit() -> None:
    """One kit, one model: the built-in names are the kit builder's KXR-L2L5A3(G) with the
    links named as the KHR-3HV's and Kondo's home pose; the torso is kxrl2l5a3.json's torso
    (372.584 g: battery box, back pack, three servo cases, frame plates) without its servo
    cases, which are counted at a KRS-3304R2's mass with the joints they drive."""
    for name, code in (("kxr-l2", "L2L5A3"), ("kxr-l2-gripper", "L2L5A3G")):
        model, kit = load_builtin(name), kit_model(parse_kit_code("kxr:" + code))
        assert model.mass == pytest.approx(kit.mass)
        assert [j.name for j in model.joints] == [j.name for j in kit.joints]
        assert [(s.index, s.joint, s.sign) for s in model.servos] == [
            (s.index, s.joint, s.sign) for s in kit.servos
        ]
        torso = model.link("torso")
        assert torso.inertial.mass == pytest.approx(0.372584 - 3 * fig("servo.mass_kxreus") / 1000)
        assert torso.inertial.com[0] < -0.004  # behind the hips, as the back pack is
