"""The multi-legged KXR kits' stock home poses: what a new project of a kit model stands in.

A kit model's zero pose (every joint at 0) is its frame as built square: the L6's legs
stretch out level from the torso and the L4T's and L4N's sideways, so the robot lies on its
belly (``rcb4hv project poses``: the torso touches the floor; ``robot detect``: "home pose
stands on its limbs: FAILED"). Kondo's sample projects stand each kit in its home position
(``ホームポジション``); :data:`STOCK_HOME` holds those poses, and :func:`with_stock_home` gives
a kit model without a home pose of its own the stock one (``project new --robot kxr:L6``).

Values are Kondo's motion values minus 7500 (the trimmed zero, KXR-KITS.md §4) at the kit's
stock ICS numbers, by the joint rcb4hv maps there (the same in every sample listed); the sign
convention turns them into angles (:meth:`~rcb4hv.robot.model.RobotModel.motion_angle`), so a
sign found wrong later moves the angle, not the pose the robot stands in. Wheels are left out
(their value is a speed). A kit model's name is its build's canonical code (``kxr:L4NH4``
builds ``kxr:L4N``), which looks the pose up.

Builds whose home position is the zero pose are missing: the KXR-L4R and the L4R2A3 (every
value 7500: ``Hello_KXR-L4R(V1.1)``, ``Hello_KXR-l4r2a3``); humanoids stand at the zero pose
too (legs straight). The L4R2A3G is missing too, though its zero pose tips onto its arms:
Kondo's home (``Hello_KXR-l4r2a3g``, XL4R_202) turns its arm rolls 3300 counts from 7500,
111.4°, past the model's ±110° (``robot detect`` on that sample: "arm_roll (1° past)"), and a
new project must not start beyond a hard limit.
"""

from __future__ import annotations

from dataclasses import replace

from rcb4hv.protocol.memory import CENTER
from rcb4hv.robot.model import RobotModel

__all__ = ["STOCK_HOME", "STOCK_HOME_SOURCES", "with_stock_home"]


def _pair(base: str, right: int, left: int) -> dict[str, int]:
    return {"r_" + base: right, "l_" + base: left}


STOCK_HOME: dict[str, dict[str, int]] = {
    "L6": {
        **_pair("front_yaw", 1200, -1200),
        **_pair("middle_yaw", 0, 0),
        **_pair("rear_yaw", -1200, 1200),
        **{f"{s}_{p}_lift": 500 for s in "lr" for p in ("front", "middle", "rear")},
        **{f"{s}_{p}_knee": 3000 for s in "lr" for p in ("front", "middle", "rear")},
    },
    "L4T": {
        **{f"{s}_{p}_yaw": 0 for s in "lr" for p in ("front", "rear")},
        **{f"{s}_{p}_roll": -1950 for s in "lr" for p in ("front", "rear")},
    },
    "L4N": {
        **_pair("front_yaw", -1802, 1946),
        **_pair("front_roll", -2811, -2667),
        **_pair("rear_yaw", 1658, -1658),
        **_pair("rear_roll", -2667, -2811),
        "neck_yaw": 0,
        "neck_pitch": 3532,
        "gripper": -600,
    },
    "L4D": {
        **_pair("front_pitch", 600, -600),
        **_pair("rear_pitch", -600, 600),
        **{f"{s}_{p}_roll": 0 for s in "lr" for p in ("front", "rear")},
        **{f"{s}_{p}_knee": -1200 for s in "lr" for p in ("front", "rear")},
        **{f"{s}_{p}_ankle": 600 for s in "lr" for p in ("front", "rear")},
        "neck_pitch": -1500,
        "jaw": -700,
    },
    "R4LL": {
        **{f"{s}_{p}_yaw": 0 for s in "lr" for p in ("front", "rear")},
        **_pair("front_pitch", 2000, -2000),
        **_pair("rear_pitch", -2000, 2000),
    },
}
"""Motion values minus 7500 by joint of each build's stock home pose, by its code (the kit
model's name after ``kxr:``; module docstring)."""

STOCK_HOME_SOURCES: dict[str, str] = {
    "L6": "Kondo's Hello_KXR-L6(V1.0), motion XL6_291_ホームポジション",
    "L4T": "Kondo's Hello_KXR-L4T(V1.1), motion XL4T_291_ホームポジション",
    "L4N": "Kondo's Hello_kxrl4nh4, motion XL4N_291_ホームポジション (its first pose: the "
    "second holds two servos only)",
    "L4D": "Kondo's Hello_KXR-L4D(V1.0), motion XL4D_291_ホームポジション",
    "R4LL": "Kondo's KXR-R4LL(V1.2), motion XR4LL_291_ホームポジション2",
}


def with_stock_home(model: RobotModel) -> RobotModel:
    """``model`` with its kit's stock home pose (:data:`STOCK_HOME`) when it is a kit model
    (``kxr:CODE``) without a home pose of its own; else ``model`` unchanged."""
    build = model.name[4:] if model.name.startswith("kxr:") else ""
    if model.home or build not in STOCK_HOME:
        return model
    home = {}
    for joint, counts in STOCK_HOME[build].items():
        servo = model.servo_for_joint(joint)
        if servo is not None:
            home[joint] = model.motion_angle(servo.index, CENTER + counts)
    sources = {**model.sources, "home": STOCK_HOME_SOURCES[build]}
    return replace(model, home=home, sources=sources)
