"""The Kondo KXR-L2 by name: the basic kit (16 servos) and the fixture's robot with grippers
(18), as the kit builder builds them.

``kxr-l2`` is the kit builder's ``kxr:L2L5A3`` and ``kxr-l2-gripper`` its ``kxr:L2L5A3G``
(:mod:`rcb4hv.robot.kit`: the same joint positions, joint map, signs and frame limits as every
other KXR humanoid, each figure with its source in :mod:`rcb4hv.robot.kit.figures`), with the
home pose of Kondo's KXR-L2 motions (the fixture's XL2G_291: knees bent by 300 counts, hips and
ankles by 150 to keep the torso and soles level, elbows by -1200, shoulders forward by 400,
grippers at -650). Until 28 Nov 2026 they were a second, hand-built model of the same kit whose
link masses were kxreus's ``models/kxrl2g.l`` figures, which weigh every servo case at a
KRS-3301's 27.73 g where the KXR's KRS-3304R2 weighs 35.03 g with its horn (KXR-KITS.md §3.1):
one kit, one model (docs/robots.md, "One model of the KXR-L2").
"""

from __future__ import annotations

import math
from dataclasses import replace

from rcb4hv.protocol import POSITION_MAX, POSITION_MIN
from rcb4hv.protocol.memory import CENTER, COUNTS_PER_DEGREE
from rcb4hv.robot.model import Joint, RobotModel

__all__ = [
    "HOME_COUNTS",
    "LINK_NAMES",
    "STANDARD_TRIM",
    "kxr_l2",
    "kxr_l2_gripper",
]

HOME_COUNTS: dict[str, int] = {
    "r_shoulder_pitch": 400,
    "l_shoulder_pitch": -400,
    "r_elbow_pitch": -1200,
    "l_elbow_pitch": -1200,
    **{f"{s}_{j}": 150 for s in "lr" for j in ("hip_pitch", "ankle_pitch")},
    **{f"{s}_knee_pitch": 300 for s in "lr"},
    **{f"{s}_gripper": -650 for s in "lr"},
}
"""The home pose of Kondo's KXR-L2 motions (the fixture's XL2G_291), counts from 7500 by
joint; the basic kit leaves out the grippers."""


STANDARD_TRIM: dict[int, int] = {
    2: 1350,
    3: -1350,
    4: -2700,
    5: -2700,
    10: -250,
    11: -250,
    12: -1980,
    13: -2000,
    14: 550,
    15: 550,
    18: -100,
}
"""Kondo's standard trim of the KXR-L2G (``KXR-L2G標準トリム.h4t``), counts by servo index (the
others 0): where each joint's zero sits in its servo's travel."""

LINK_NAMES: dict[str, str] = {
    "shoulder_pitch": "shoulder",
    "shoulder_roll": "upper_arm",
    "elbow_pitch": "forearm",
    "gripper": "finger",
    "hip_roll": "hip",
    "hip_pitch": "thigh",
    "knee_pitch": "shin",
    "ankle_pitch": "ankle",
    "ankle_roll": "foot",
}
"""The KXR-L2's links by what they are (``l_foot``, ``r_forearm``), as the KHR-3HV's are named,
for the kit builder's links named after the joint that moves them (``l_ankle_roll_link``)."""


def _renamed(model: RobotModel) -> RobotModel:
    """``model`` with each ``<side>_<joint>_link`` named :data:`LINK_NAMES`' way."""

    def new(name: str) -> str:
        side, _, rest = name.partition("_")
        base = rest.removesuffix("_link")
        return f"{side}_{LINK_NAMES[base]}" if base in LINK_NAMES else name

    return replace(
        model,
        links=tuple(replace(link, name=new(link.name)) for link in model.links),
        joints=tuple(replace(j, parent=new(j.parent), child=new(j.child)) for j in model.joints),
    )


def _travel(model: RobotModel, joint: Joint) -> tuple[float, float]:
    """The joint's range (radians) inside its servo's travel (3500..11500 sent) about Kondo's
    standard trim."""
    s = next(s for s in model.servos if s.joint == joint.name)
    ends = [
        math.radians(s.sign * (v - CENTER - STANDARD_TRIM.get(s.index, 0)) / COUNTS_PER_DEGREE)
        for v in (POSITION_MIN, POSITION_MAX)
    ]
    return min(ends), max(ends)


def _with_travel(model: RobotModel) -> RobotModel:
    """Each joint warns (``advisory``) past its servo's travel about the standard trim or its
    mirror joint's, whichever is narrower, so both sides warn alike; a servo there stops at its
    end (Kondo's own motions send 2100 or 12900 to push a shoulder to its end), so it is no
    hard limit."""
    by_name = {j.name: j for j in model.joints}
    joints = []
    for j in model.joints:
        lo, hi = _travel(model, j)
        if j.mirror is not None:
            mlo, mhi = _travel(model, by_name[j.mirror])
            if j.kind in ("roll", "yaw"):
                mlo, mhi = -mhi, -mlo
            lo, hi = max(lo, mlo), min(hi, mhi)
        joints.append(replace(j, advisory=(max(j.lower, lo), min(j.upper, hi))))
    return replace(model, joints=tuple(joints))


def _build(code: str, name: str, title: str) -> RobotModel:
    from rcb4hv.robot.kit import kit_model, parse_kit_code

    kit = parse_kit_code(code)
    assert kit is not None
    model = kit_model(kit, home_counts=HOME_COUNTS)
    sources = {
        **model.sources,
        "home": "the fixture's home pose (XL2G_291), Kondo's KXR-L2 motions",
        "model": f"the kit builder's {code} (one model per kit), its links named as the KHR-3HV's",
        "limits": "hard: the kit's frame limits; advisory: within them the servo's ±135° "
        "around Kondo's standard trim (KXR-L2G標準トリム.h4t)",
    }
    return replace(_with_travel(_renamed(model)), name=name, title=title, sources=sources)


def kxr_l2() -> RobotModel:
    """Kondo's basic KXR-L2 kit (16 servos): the kit builder's ``kxr:L2L5A3``."""
    return _build("kxr:L2L5A3", "kxr-l2", "Kondo KXR-L2 (16 servos)")


def kxr_l2_gripper() -> RobotModel:
    """The KXR-L2 with a gripper on each arm (18 servos; the fixture project's robot): the kit
    builder's ``kxr:L2L5A3G``."""
    return _build("kxr:L2L5A3G", "kxr-l2-gripper", "Kondo KXR-L2 with grippers (18 servos)")
