"""Detection rules found on Kondo's public sample projects, each on a synthetic servo table
(our own names in Kondo's style; no sample data)."""

from __future__ import annotations

import pytest

from rcb4hv.errors import NoRobotModelError
from rcb4hv.robot.geometry import apply
from rcb4hv.robot.kinematics import forward
from rcb4hv.robot.kit import detect_kit, parse_servo_name
from rcb4hv.robot.model import RobotModel, Vec3
from tests.robot.kit_names import names_for, stock


def test_the_short_legs_ankle_roll_is_their_only_roll() -> None:
    # a 2-axis leg (a yaw and one roll on 16/17) named as Kondo names it: 足首（ロール）
    names = {2: "右肩（ピッチ）", 3: "左肩（ピッチ）", 6: "右肘", 7: "左肘",
             16: "右足首（ロール）", 17: "左足首（ロール）",
             24: "右脚ヨー", 25: "左脚ヨー"}  # fmt: skip
    det = detect_kit("Hello_kxrl2l2a3", names)
    assert det.model.servo(16).joint == "r_hip_roll"
    assert det.model.servo(25).joint == "l_hip_yaw"
    assert det.code is not None and det.code.legs == 2
    # mounted as in the ankle: the ankle roll's sign, as kxreus maps all its short legs
    assert det.model.servo(16).sign == -1 and det.model.servo(17).sign == -1
    full = detect_kit("Hello_KXR-L2GH(V1.0)", names_for(stock("kxr:L2GH")[1]))
    assert {full.model.servo(16).sign, full.model.servo(17).sign} == {-1}
    assert {full.model.servo(8).sign, full.model.servo(9).sign} == {1}


def test_the_a6_hand_points_forward_from_a_bent_forearm() -> None:
    # kxreus's A6 (`:elbow :angle`): the wrist 23.5 mm behind and 43 mm below the elbow, the
    # hand 15 + 31.5 mm forward of it at zero pose; the A3's and A5's hands hang below
    def origin(model: RobotModel, link: str) -> Vec3:
        return apply(forward(model, {})[link], (0.0, 0.0, 0.0))

    _, a6 = stock("kxr:L2L6A6H2G")
    elbow, wrist = origin(a6, "l_elbow_pitch_link"), origin(a6, "l_wrist_pitch_link")
    hand = origin(a6, "l_gripper_link")
    assert wrist[0] - elbow[0] == pytest.approx(-0.0235)
    assert wrist[2] - elbow[2] == pytest.approx(-0.043)
    assert hand[0] - wrist[0] == pytest.approx(0.0465) and hand[2] == pytest.approx(wrist[2])
    for code in ("kxr:L2L5A3H2G", "kxr:L2L6A5H2G"):  # A3, and the A5 (no bent elbow)
        _, arm = stock(code)
        elbow3, hand3 = origin(arm, "l_elbow_pitch_link"), origin(arm, "l_gripper_link")
        assert hand3[0] == pytest.approx(elbow3[0]) and hand3[2] < elbow3[2] - 0.05


def test_a_full_leg_keeps_its_ankle_roll() -> None:
    _, model = stock("kxr:L2GH")
    det = detect_kit("Hello_KXR-L2GH(V1.0)", names_for(model))
    assert det.model.servo(16).joint == "r_ankle_roll"


def test_tip_with_tan_is_a_tip() -> None:
    role = parse_servo_name("右後足先端")
    assert role is not None and role.segment == "tip" and role.position == "rear"


def test_the_l4r_limb_follows_its_body_part_and_its_tip_is_the_wheel() -> None:
    # the right rear yaw named "front crotch" beside a left "crotch": the part names the limb
    names = {1: "頭1", 2: "右前肩", 3: "左前肩", 4: "右前足先端", 5: "左前足先端",
             6: "右前股間", 7: "左足股間", 8: "右後足先端", 9: "左後足先端"}  # fmt: skip
    det = detect_kit("Hello_KXR-L4R(V1.1)", names)
    joints = {s.index: s.joint for s in det.model.servos}
    assert joints[6] == "r_rear_yaw" and joints[7] == "l_rear_yaw"
    assert joints[4] == "r_front_wheel" and joints[9] == "l_rear_wheel"
    assert joints[2] == "r_front_yaw"


def test_an_l4r_with_arms_under_a_plain_l4r_title() -> None:
    names = {1: "頭1", 2: "右前肩", 3: "左前肩", 6: "右前股間", 7: "左足股間",
             8: "右後足先端", 9: "左後足先端", 10: "右肩ロール", 11: "左肩ロール",
             12: "右手首ロール", 13: "左手首ロール"}  # fmt: skip
    det = detect_kit("Hello_KXR-L4R", names)
    assert det.model.name == "kxr:L4R2A3"
    assert det.model.servo(12).joint == "r_arm_elbow"


def test_unnamed_servos_on_another_stock_build_of_the_family() -> None:
    # the magnet-modular L4T's ICS numbers (kxreus kxrl4tm), names that say nothing
    used = (8, 9, 16, 17, 20, 21, 24, 25, 32)
    names = {i: ("R" if i % 2 == 0 else "L") + str(i // 2) for i in used}
    det = detect_kit("Hello_KXR-L4T(V1.1)", names)
    joints = {s.index: (s.joint, s.sign) for s in det.model.servos}
    assert joints[24] == ("r_front_yaw", -1) and joints[9] == ("l_front_roll", 1)
    assert joints[16] == ("r_rear_roll", -1) and joints[32] == ("neck_yaw", -1)
    assert any("stock build" in n for n in det.notes)


def test_unnamed_servos_on_no_stock_build_still_stop() -> None:
    names = {i: f"S{i}" for i in (8, 9, 12, 13, 20, 21, 24, 25)}
    with pytest.raises(NoRobotModelError):
        detect_kit("Hello_KXR-L4T(V1.1)", names)
