"""Synthetic servo tables for the kit tests: Kondo-style names for every joint of a kit model
(our own test data, not copied from any project)."""

from __future__ import annotations

import math

from rcb4hv.robot.kit import KitCode, kit_model, parse_kit_code
from rcb4hv.robot.model import RobotModel

SIDE = {"r": "右", "l": "左"}
POS = {"front": "前", "middle": "中", "rear": "後"}
HUMANOID = {
    "shoulder_pitch": "肩（ピッチ）", "shoulder_roll": "肩（ロール）", "shoulder_yaw": "肩（ヨー）",
    "elbow_pitch": "肘", "wrist_pitch": "手首（ピッチ）", "wrist_roll": "手首（ロール）",
    "wrist_yaw": "手首（ヨー）", "gripper": "グリッパー", "hip_yaw": "腿（ヨー）",
    "hip_roll": "腿（ロール）", "hip_pitch": "腿（ピッチ）", "knee_pitch": "膝",
    "ankle_pitch": "足首（ピッチ）", "ankle_roll": "足首（ロール）", "ankle_wheel": "足車輪",
    "front_wheel": "前車輪", "rear_wheel": "後車輪", "arm_roll": "肩ロール",
    "arm_elbow": "肘ロール",
}  # fmt: skip
CENTRE = {
    "neck_yaw": "首（ヨー）",
    "neck_pitch": "首（ピッチ）",
    "jaw": "アゴ",
    "gripper": "ハンド",
}
SEGMENTS = {3: ("元", "中", "先"), 2: ("元", "先"), 1: ("元",), 4: ("元", "中", "中2", "先")}


def stock(text: str) -> tuple[KitCode, RobotModel]:
    code = parse_kit_code(text)
    assert code is not None
    return code, kit_model(code)


def names_for(model: RobotModel) -> dict[int, str]:
    """A Japanese servo name for each servo of ``model`` (Kondo's naming style)."""
    out: dict[int, str] = {}
    limbs: dict[str, list[str]] = {}
    for s in model.servos:
        j = s.joint
        if j[:2] in ("l_", "r_") and j[2:].split("_")[0] in POS and "wheel" not in j:
            limbs.setdefault(j[2:].split("_")[0], [])
            if j[2:] not in limbs[j[2:].split("_")[0]]:
                limbs[j[2:].split("_")[0]].append(j[2:])
    for s in model.servos:
        j = s.joint
        if j[:2] not in ("l_", "r_"):
            out[s.index] = CENTRE[j]
            continue
        side, base = SIDE[j[0]], j[2:]
        limb = base.split("_")[0]
        if base in HUMANOID and not (limb in POS and model.name[4:6] != "L2"):
            out[s.index] = side + HUMANOID[base]
        elif base.endswith("wheel"):
            out[s.index] = f"{side}{POS[limb]}足車輪"
        else:
            seq = limbs[limb]
            seg = SEGMENTS[len(seq)][seq.index(base)] if len(seq) != 4 else None
            axis = {"pitch": "ピッチ", "roll": "ロール", "knee": "膝", "ankle": "足首"}
            out[s.index] = (
                f"{side}{POS[limb]}脚（{seg}）" if seg and "中2" not in seg else
                f"{side}{POS[limb]}脚（{axis[base.split('_')[1]]}）"
            )  # fmt: skip
    return out


def home_values(model: RobotModel, degrees: dict[str, float]) -> dict[int, int]:
    """Motion values putting the named joints at ``degrees`` (others at 7500)."""
    out = {s.index: 7500 for s in model.servos}
    for joint, deg in degrees.items():
        s = model.servo_for_joint(joint)
        assert s is not None, joint
        out[s.index] = model.motion_value(s.index, math.radians(deg))
    return out
