"""The KXR kits' assembly convention: which slots a limb has, each joint's sign, the stock
ICS numbers.

Signs and stock ICS numbers come from kxreus's joint maps of Kondo's stock builds
(KXR-KITS.md §1.4: ``kxrl2l5a3`` ... ``kxrr4ll``), which use this package's conventions
unchanged (checked on the KXR-L2, :mod:`rcb4hv.robot.kxr`). Detection checks them on each
project's own home pose (:mod:`rcb4hv.robot.kit.detect`).
"""

from __future__ import annotations

from rcb4hv.robot.kit.code import Family

__all__ = ["LIMBS", "SHORT_LEG_ROLL", "SIGNS", "STOCK", "STOCK_VARIANTS", "arm_signs"]

#: the slots of each limb, root to tip (for names that give only a position and a segment)
LIMBS: dict[str, dict[str, tuple[str, ...]]] = {
    "L6": {p: (f"{p}_yaw", f"{p}_lift", f"{p}_knee") for p in ("front", "middle", "rear")},
    "L4T": {p: (f"{p}_yaw", f"{p}_roll") for p in ("front", "rear")},
    "L4N": {p: (f"{p}_yaw", f"{p}_roll") for p in ("front", "rear")},
    "L4R": {p: (f"{p}_yaw", f"{p}_wheel") for p in ("front", "rear")},
    "L4D": {p: (f"{p}_pitch", f"{p}_roll", f"{p}_knee", f"{p}_ankle") for p in ("front", "rear")},
    "R4LL": {p: (f"{p}_yaw", f"{p}_pitch", f"{p}_wheel") for p in ("front", "rear")},
}

# the kit's assembly convention: base joint -> (right sign, left sign), KXR-KITS.md §1.4
_H = {
    "shoulder_pitch": (1, -1),
    "elbow_pitch": (1, 1),
    "elbow_yaw": (1, 1),
    "wrist_yaw": (1, 1),
    "wrist_pitch": (-1, -1),
    "gripper": (1, 1),
    "hip_yaw": (1, 1),
    "hip_roll": (1, 1),
    "hip_pitch": (-1, -1),
    "knee_pitch": (1, 1),
    "ankle_pitch": (-1, -1),
    "ankle_roll": (-1, -1),
    "ankle_wheel": (1, -1),
    "front_wheel": (1, -1),
    "rear_wheel": (1, -1),
    "neck_yaw": (-1, -1),
    "neck_pitch": (1, 1),
    "waist_yaw": (-1, -1),
}
SIGNS: dict[Family, dict[str, tuple[int, int]]] = {
    "humanoid": _H,
    "L6": {
        "front_yaw": (-1, -1),
        "front_lift": (-1, -1),
        "front_knee": (1, 1),
        "middle_yaw": (-1, -1),
        "middle_lift": (-1, 1),
        "middle_knee": (1, -1),
        "rear_yaw": (-1, -1),
        "rear_lift": (1, 1),
        "rear_knee": (-1, -1),
    },
    "L4T": {
        "front_yaw": (-1, -1),
        "front_roll": (-1, 1),
        "rear_yaw": (-1, -1),
        "rear_roll": (-1, 1),
        "neck_yaw": (-1, -1),
        "neck_pitch": (1, 1),
    },
    "L4N": {
        "front_yaw": (-1, -1),
        "front_roll": (-1, 1),
        "rear_yaw": (-1, -1),
        "rear_roll": (-1, 1),
        "neck_yaw": (1, 1),
        "neck_pitch": (-1, -1),
        "neck_pitch2": (-1, -1),
        "neck_pitch3": (1, 1),
        "gripper": (1, 1),
    },
    # the wheels: kxreus's kxrl4r map gives right -1 / left +1, its kxrl4r2a3 and kxrl4r2a3g
    # maps right +1 / left -1 for the same wheels (KXR-KITS.md §1.4). Kondo's Hello_KXR-L4R
    # decides it: with -1/+1 all 18 of its drives, side moves and turns went the other way;
    # with +1/-1 they go the named way (docs/robots.md, "KXR-L4R wheels")
    "L4R": {
        "arm_roll": (1, 1),
        "arm_elbow": (-1, -1),
        "gripper": (-1, -1),
        "front_yaw": (-1, -1),
        "front_wheel": (1, -1),
        "rear_yaw": (-1, -1),
        "rear_wheel": (1, -1),
        "neck_yaw": (1, 1),
        "neck_pitch": (1, 1),
    },
    "L4D": {
        "front_pitch": (1, -1),
        "front_roll": (-1, 1),
        "front_knee": (1, 1),
        "front_ankle": (1, 1),
        "rear_pitch": (1, -1),
        "rear_roll": (-1, 1),
        "rear_knee": (-1, -1),
        "rear_ankle": (-1, -1),
        "neck_pitch": (-1, -1),
        "jaw": (-1, -1),
    },
    "R4LL": {
        "front_yaw": (1, 1),
        "front_pitch": (-1, 1),
        "front_wheel": (1, -1),
        "rear_yaw": (1, 1),
        "rear_pitch": (-1, 1),
        "rear_wheel": (1, -1),
    },
}

#: the short (2-axis) leg's roll: Kondo's projects drive it with the ankle-roll servo
#: (右足首（ロール） on 16/17), mounted as in the ankle, and kxreus maps it -1/-1 in all four
#: of its short-leg builds (kxra6g, kxrt1l2l2d7h2m, -e7h2m, -w7h2m; KXR-KITS.md §1.4), as the
#: kit's ankle roll. With the hip roll's +1/+1, Kondo's Hello_kxrl2l2a6h2g walked every walk
#: the other way (docs/robots.md, "The A6 arm and the short leg")
SHORT_LEG_ROLL = _H["ankle_roll"]


def arm_signs(arms: int) -> dict[str, tuple[int, int]]:
    """The arm joints whose sign depends on the arm build (KXR-KITS.md §1.4)."""
    cross = arms >= 6
    return {
        "shoulder_roll": (1, -1) if cross else (-1, 1),
        "shoulder_yaw": (-1, -1) if cross else (1, 1),
        "wrist_roll": (-1, -1) if cross else (-1, 1),
    }


#: stock ICS numbers (right; left = right + 1; centre joints as given), KXR-KITS.md §1.4
STOCK: dict[Family, dict[str, int]] = {
    "humanoid": {
        "shoulder_pitch": 2,
        "shoulder_roll": 4,
        "elbow_pitch": 6,
        "hip_roll": 8,
        "hip_pitch": 10,
        "knee_pitch": 12,
        "ankle_pitch": 14,
        "ankle_roll": 16,
        "gripper": 18,
        "ankle_wheel": 20,
        "shoulder_yaw": 22,
        "hip_yaw": 24,
        "wrist_pitch": 26,
        "wrist_roll": 28,
        "wrist_yaw": 30,
        "front_wheel": 0,
        "rear_wheel": 20,
        "neck_yaw": 30,
        "neck_pitch": 32,
        "waist_yaw": 33,
    },
    "L6": {
        "front_yaw": 2,
        "front_lift": 4,
        "front_knee": 6,
        "middle_yaw": 8,
        "middle_lift": 10,
        "middle_knee": 12,
        "rear_yaw": 14,
        "rear_lift": 16,
        "rear_knee": 18,
    },
    "L4T": {"front_yaw": 2, "front_roll": 4, "rear_yaw": 6, "rear_roll": 8, "neck_yaw": 1},
    "L4N": {
        "front_yaw": 2,
        "front_roll": 4,
        "rear_yaw": 6,
        "rear_roll": 8,
        "neck_yaw": 11,
        "neck_pitch": 13,
        "gripper": 15,
    },
    "L4R": {
        "arm_roll": 10,
        "arm_elbow": 12,
        "gripper": 18,
        "front_yaw": 2,
        "front_wheel": 4,
        "rear_yaw": 6,
        "rear_wheel": 8,
        "neck_yaw": 0,
        "neck_pitch": 1,
    },
    "L4D": {
        "front_pitch": 2,
        "front_roll": 4,
        "front_knee": 6,
        "front_ankle": 8,
        "rear_pitch": 10,
        "rear_roll": 12,
        "rear_knee": 14,
        "rear_ankle": 16,
        "neck_pitch": 1,
        "jaw": 19,
    },
    "R4LL": {
        "front_yaw": 2,
        "front_pitch": 4,
        "front_wheel": 6,
        "rear_yaw": 8,
        "rear_pitch": 10,
        "rear_wheel": 12,
    },
}


#: other stock builds of a family with the same joints on other ICS numbers (right; left =
#: right + 1), tried in turn when a project's servo names carry no joint:
#: the magnet-modular KXR-L4T, kxreus ``kxrl4tm`` (KXR-KITS.md §1.4: 24/25 arm-shoulder-y,
#: 8/9 arm-shoulder-r, 20/21 leg-crotch-y, 16/17 leg-crotch-r, 32 neck-y; its signs are the
#: L4T's)
STOCK_VARIANTS: dict[Family, tuple[dict[str, int], ...]] = {
    "L4T": ({"front_yaw": 24, "front_roll": 8, "rear_yaw": 20, "rear_roll": 16, "neck_yaw": 32},),
}
