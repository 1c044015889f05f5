"""The Kondo KHR-3HV: the 17-axis standard build and the 22-axis "Ver.2" build.

Every figure has its source (see docs/robots.md for the tables):

* joint map (servo index, sign): shared/robots/FACTS.md — index = 2 × ICS ID + side, side 0
  (SIO1-4) the robot's LEFT (Kondo's own sample names servo 2 左肩 = left shoulder); signs from
  kxreus ``rcb4robotconfig.l`` "khr" / "khr20", checked against Kondo's sample motions
  (docs/robots.md). A joint angle is ``sign × servo angle``.
* limits: hard +-180° (no public bracket stops); advisory: robotlearn/khr3hv
  ``docs/limits.png`` (software limits) widened to Kondo's sample motions (see HARD_DEG).
* distances (mm): FACTS.md's KHRBan CAD table for the shoulder span (97.8), hip span (43.4),
  shoulder-to-hip height (87.5), thigh (65.0) and shin (65.0). Hip yaw → roll (22.35),
  roll → pitch (38.7), ankle pitch → roll (37.0), the sole (26.5 below the ankle-roll axis),
  the arm and head offsets and the link boxes come from sunilgora/SIP2HumnWalking
  ``kondo/kondo_khr3hv.xml`` (Apache-2.0): the CAD table's 28.5/50.8/52.3 for those three
  would make the robot 433 mm tall, against Kondo's ~401 mm; SIP's give 400 mm.
* the sole plate (120 x 76.8 mm): kxreus's model of Kondo's foot part (eusview ``khr3.json``).
* mass: 1.493 kg (kxreus eusview ``khr3.json``) for the 17-axis robot; the 22-axis robot adds
  its five servos. Each link carries the KRS-2552RHV cases bolted to it (41.5 g each, on the
  proximal side of the joint they drive); the rest is shared by shape volume.
"""

from __future__ import annotations

import math

from rcb4hv.protocol.memory import COUNTS_PER_DEGREE
from rcb4hv.robot.humanoid import LimbJoint, build_humanoid, distribute_mass
from rcb4hv.robot.model import Geom, JointKind, Link, RobotModel, Vec3
from rcb4hv.robot.servos import KRS_2552RHV
from rcb4hv.robot.shapes import solid_many

__all__ = ["KHR_LIMITS_DEG", "KHR_SAMPLE_COUNTS", "KHR_SIGNS", "khr3hv", "khr3hv_22"]

MM = 0.001

# servo index -> sign (kxreus "khr" and "khr20"; FACTS.md)
KHR_SIGNS: dict[int, int] = {
    0: -1,
    1: -1,
    2: -1,
    3: 1,
    4: 1,
    5: 1,
    8: 1,
    9: -1,
    10: 1,
    11: 1,
    12: 1,
    13: 1,
    14: -1,
    15: 1,
    16: 1,
    17: -1,
    18: 1,
    19: -1,
    20: -1,
    21: -1,
    # upper-arm yaw (6, 7) is in no public sign table; chosen +1 on both sides like the
    # other yaw pairs (hip yaw 10, 11), so the mirror rule holds (docs/robots.md)
    6: 1,
    7: 1,
}

# Joint limits (docs/robots.md, "Hard limits and advisory ranges"), by servo index in servo
# degrees (a joint angle is sign x servo angle).
#
# Hard (refused, and where MuJoCo stops the joint): where the brackets collide. No public
# drawing gives the KHR-3HV's bracket stops, so the hard range is a generous +-180 deg (the
# links fold onto each other there): nothing a servo can reach with any trim is refused. The
# servo's own travel (+-135 deg about its centre, 3500..11500 sent) is no refusal either: a
# servo commanded past it stops at its end (the physics clamps the value sent), and Kondo's
# KXR samples command 2100 or 12900 on purpose.
HARD_DEG = 180.0
# Advisory (warn outside): robotlearn/khr3hv docs/limits.png, a library's software limits
# (FACTS.md's correction) ...
KHR_LIMITS_DEG: dict[int, tuple[float, float]] = {
    0: (-135, 135),
    2: (-90, 105),
    3: (-105, 90),
    4: (-30, 180),
    5: (-180, 30),
    8: (-130, 30),
    9: (-30, 130),
    12: (0, 30),
    13: (-30, 0),
    14: (-90, 90),
    15: (-90, 90),
    16: (-60, 135),
    17: (-135, 60),
    18: (-100, 120),
    19: (-120, 100),
    20: (-25, 90),
    21: (-90, 25),
}
# ... widened to the extremes of Kondo's own KHR-3HV sample project (kxreus projects/
# Hello_khr3/Hello_KHR3(V2.3).h4p, every pose of every motion), which are valid by definition:
# counts from 7500 (motion values, before the trim)
KHR_SAMPLE_COUNTS: dict[int, tuple[int, int]] = {
    0: (-2000, 2000),  # BTC001 head shake
    2: (-2500, 4000),  # get up from the front .. handstand
    3: (-4500, 2500),  # frustrated (3000) .. get up from the front
    4: (-750, 4500),  # .. side punch left (12000)
    5: (-4500, 750),  # side punch right (3000) ..
    8: (-3800, 0),  # handstand
    9: (0, 3800),
    12: (-500, 850),  # handstand .. side kick (left leg)
    13: (-850, 600),  # frustrated .. cheer
    14: (-2000, 3500),  # frustrated .. handstand
    15: (-3500, 3000),
    16: (-1200, 4000),  # get up from the back (knee 40.5 deg past straight) .. handstand
    17: (-4000, 1200),
    18: (-2800, 3500),  # frustrated .. get up from the back
    19: (-3500, 2800),
    20: (-300, 800),  # safety walk .. side kick
    21: (-800, 400),
}


# joint name -> left/right (or centre) servo index (FACTS.md table)
_JOINTS: dict[str, tuple[int, int | None]] = {
    "head_yaw": (0, None),
    "waist_yaw": (1, None),
    "shoulder_pitch": (2, 3),
    "shoulder_roll": (4, 5),
    "upper_arm_yaw": (6, 7),
    "elbow_pitch": (8, 9),
    "hip_yaw": (10, 11),
    "hip_roll": (12, 13),
    "hip_pitch": (14, 15),
    "knee_pitch": (16, 17),
    "ankle_pitch": (18, 19),
    "ankle_roll": (20, 21),
}
_STANDARD = (
    "head_yaw",
    "shoulder_pitch",
    "shoulder_roll",
    "elbow_pitch",
    "hip_roll",
    "hip_pitch",
    "knee_pitch",
    "ankle_pitch",
    "ankle_roll",
)

# distances, metres (sources in the module docstring)
SHOULDER_Y = 97.8 / 2 * MM
HIP_Y = 43.4 / 2 * MM
SHOULDER_Z = 87.5 * MM
HIP_YAW_TO_ROLL = 22.35 * MM
HIP_ROLL_TO_PITCH = 38.7 * MM
THIGH = 65.0 * MM
SHIN = 65.0 * MM
ANKLE_PITCH_TO_ROLL = 37.0 * MM
SOLE_BELOW_ANKLE_ROLL = 26.5 * MM
SHOULDER_PITCH_TO_ROLL = 26.45 * MM
ROLL_TO_ARM_YAW = 73.65 * MM
ARM_YAW_TO_ELBOW = 11.7 * MM
FOREARM = 106.0 * MM
HEAD_ABOVE_SHOULDER = 14.3 * MM
MASS_17 = 1.493  # kg, kxreus eusview khr3.json
# the leg's sideways offsets (SIP's kondo_khr3hv.xml body positions): the hip-roll axis sits
# 4.55 mm inward of the hip-yaw axis, the pitch chain (hip pitch, knee, ankle pitch) 11.3 mm
# outward of the hip-roll axis, the ankle-roll axis 11.25 mm inward of the pitch chain again,
# and the sole 11.25 mm outward of the ankle-roll axis (under the pitch chain)
HIP_ROLL_INWARD = 4.55 * MM
PITCH_CHAIN_OUTWARD = 11.3 * MM
ANKLE_ROLL_INWARD = 11.25 * MM
# sole: the KHR-3HV's foot plate as kxreus models Kondo's part (eusview ``khr3.json``, the
# ankle-roll links' sole: an outline of 120.0 x 76.8 mm with chamfered corners, its bottom
# 26.1 mm below the ankle-roll axis), centred 2.3 mm behind the ankle-pitch axis and 24.4 mm
# outward of the ankle-roll axis, so the two plates' inner edges nearly meet (3 mm from the
# middle). SIP's foot (its contact corners, 78 x 43 mm) is a simplified contact model, not the
# part. The plate is 10 mm thick (kxreus), so its share of the frame's mass (by box volume,
# humanoid.distribute_mass) comes to about kxreus's 40 g foot; its bottom stays SIP's 26.5 mm
# below the ankle-roll axis (kxreus: 26.1).
SOLE = (120.0 * MM, 76.8 * MM, 10.0 * MM)
SOLE_X = -2.3 * MM
SOLE_Y = 24.4 * MM

_Y, _X, _Z = (0.0, 1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)
_DARK, _LIGHT = (0.25, 0.25, 0.28, 1.0), (0.85, 0.85, 0.88, 1.0)

# (joint, link, parent, origin, axis, kind, shapes, servo cases the child link carries)
_Row = tuple[str, str, str, Vec3, Vec3, JointKind, tuple[Geom, ...], int]


def _box(
    size_mm: tuple[float, float, float],
    z_mm: float,
    x_mm: float = 0.0,
    y_mm: float = 0.0,
    rgba: tuple[float, float, float, float] = _DARK,
) -> Geom:
    return Geom(
        "box",
        (size_mm[0] * MM, size_mm[1] * MM, size_mm[2] * MM),
        (x_mm * MM, y_mm * MM, z_mm * MM),
        rgba=rgba,
    )


def _joint_range(index: int, servo_deg: tuple[float, float]) -> tuple[float, float]:
    """A servo-degree range of servo ``index`` in joint radians (joint = sign x servo)."""
    lo, hi = servo_deg
    if KHR_SIGNS[index] < 0:
        lo, hi = -hi, -lo
    return math.radians(lo), math.radians(hi)


def _sample_deg(index: int) -> tuple[float, float]:
    lo, hi = KHR_SAMPLE_COUNTS[index]
    return lo / COUNTS_PER_DEGREE, hi / COUNTS_PER_DEGREE


def _limits(
    left: int, right: int | None, kind: JointKind
) -> tuple[float, float, tuple[float, float] | None]:
    """The left (or centre) joint's hard limits and advisory range (the comment at
    HARD_DEG). The advisory range is the hull of robotlearn's and the sample's on both sides
    (the right side's mirrored), so mirroring Kondo's own motions never warns."""
    lower, upper = math.radians(-HARD_DEG), math.radians(HARD_DEG)
    if left not in KHR_LIMITS_DEG:
        return lower, upper, None
    spans = [_joint_range(left, KHR_LIMITS_DEG[left]), _joint_range(left, _sample_deg(left))]
    if right is not None:
        for deg in (KHR_LIMITS_DEG[right], _sample_deg(right)):
            lo, hi = _joint_range(right, deg)
            spans.append((lo, hi) if kind == "pitch" else (-hi, -lo))
    advisory = (max(lower, min(a for a, _ in spans)), min(upper, max(b for _, b in spans)))
    return lower, upper, advisory


def _build(axes: int) -> RobotModel:
    full = axes == 22
    used = set(_JOINTS) if full else set(_STANDARD)
    chest = "chest" if full else "torso"
    pelvis_geom = _box((50.5, 76.0, 36.0), 18.0)
    chest_geom = _box((80.5, 89.0, 60.5), 66.4, rgba=_LIGHT)
    sole = Geom("box", SOLE, (SOLE_X, SOLE_Y, -SOLE_BELOW_ANKLE_ROLL + SOLE[2] / 2), rgba=_LIGHT)
    rows: list[_Row] = [
        (
            "head_yaw",
            "head",
            chest,
            (0.0, 0.0, SHOULDER_Z + HEAD_ABOVE_SHOULDER),
            _Z,
            "yaw",
            (_box((49.5, 32.0, 38.0), 24.75, rgba=_LIGHT),),
            0,
        ),
        (
            "shoulder_pitch",
            "shoulder",
            chest,
            (0.0, SHOULDER_Y, SHOULDER_Z),
            _Y,
            "pitch",
            (_box((46.5, 36.0, 20.0), 0.0, y_mm=17.5),),
            1,
        ),
        (
            "shoulder_roll",
            "upper_arm",
            "shoulder",
            (0.0, SHOULDER_PITCH_TO_ROLL, 0.0),
            _X,
            "roll",
            (_box((35.5, 25.0, 73.65), -36.8),),
            1,
        ),
    ]
    if full:
        rows.append(
            (
                "upper_arm_yaw",
                "elbow",
                "upper_arm",
                (0.0, 0.0, -ROLL_TO_ARM_YAW),
                _Z,
                "yaw",
                (_box((42.2, 32.0, 11.7), -5.85),),
                1,
            )
        )
    rows.append(
        (
            "elbow_pitch",
            "forearm",
            "elbow" if full else "upper_arm",
            (0.0, 0.0, -(ARM_YAW_TO_ELBOW if full else ROLL_TO_ARM_YAW + ARM_YAW_TO_ELBOW)),
            _Y,
            "pitch",
            (_box((29.0, 32.0, FOREARM / MM), -FOREARM / MM / 2, rgba=_LIGHT),),
            0,
        )
    )
    if full:
        rows.append(
            (
                "hip_yaw",
                "hip_bracket",
                "pelvis",
                (0.0, HIP_Y, 0.0),
                _Z,
                "yaw",
                (_box((47.0, 24.0, 22.35), -11.2),),
                1,
            )
        )
    rows += [
        (
            "hip_roll",
            "hip",
            "hip_bracket" if full else "torso",
            (0.0, (0.0 if full else HIP_Y) - HIP_ROLL_INWARD, -HIP_YAW_TO_ROLL),
            _X,
            "roll",
            (_box((32.0, 42.5, 38.7), -19.35, y_mm=PITCH_CHAIN_OUTWARD / MM / 2),),
            1,
        ),
        (
            "hip_pitch",
            "thigh",
            "hip",
            (0.0, PITCH_CHAIN_OUTWARD, -HIP_ROLL_TO_PITCH),
            _Y,
            "pitch",
            (_box((32.0, 42.0, THIGH / MM), -THIGH / MM / 2, rgba=_LIGHT),),
            1,
        ),
        (
            "knee_pitch",
            "shin",
            "thigh",
            (0.0, 0.0, -THIGH),
            _Y,
            "pitch",
            (_box((32.0, 42.0, SHIN / MM), -SHIN / MM / 2, rgba=_LIGHT),),
            1,
        ),
        (
            "ankle_pitch",
            "ankle",
            "shin",
            (0.0, 0.0, -SHIN),
            _Y,
            "pitch",
            (
                _box(
                    (32.0, 42.5, ANKLE_PITCH_TO_ROLL / MM),
                    -ANKLE_PITCH_TO_ROLL / MM / 2,
                    y_mm=-ANKLE_ROLL_INWARD / MM / 2,
                ),
            ),
            1,
        ),
        (
            "ankle_roll",
            "foot",
            "ankle",
            (0.0, -ANKLE_ROLL_INWARD, -ANKLE_PITCH_TO_ROLL),
            _X,
            "roll",
            (sole,),
            0,
        ),
    ]
    root_name = "pelvis" if full else "torso"
    root_geoms = (pelvis_geom,) if full else (pelvis_geom, chest_geom)
    # servo cases carried by each link (proximal side of the joint they drive)
    root_servos = 3 if full else 5  # 22: waist + 2 hip yaw; 17: head + 2 shoulder + 2 hip roll
    parts: dict[str, tuple[int, int, tuple[Geom, ...]]] = {root_name: (1, root_servos, root_geoms)}
    if full:
        rows.insert(
            0, ("waist_yaw", "chest", "pelvis", (0.0, 0.0, 0.0), _Z, "yaw", (chest_geom,), 3)
        )
    for name, link, _p, _xyz, _a, _k, geoms, servos in rows:
        parts[link] = (1 if name in ("head_yaw", "waist_yaw") else 2, servos, geoms)
    total = MASS_17 + (axes - 17) * KRS_2552RHV.mass
    masses = distribute_mass(total, KRS_2552RHV.mass, parts)
    specs = []
    servo_map: dict[str, tuple[int, int]] = {}
    for name, link, parent, xyz, axis, kind, geoms, _servos in rows:
        if name not in used:
            continue
        left, right = _JOINTS[name]
        centre = right is None
        lower, upper, advisory = _limits(left, right, kind)
        specs.append(
            LimbJoint(
                name,
                link,
                parent,
                xyz,
                axis,
                kind,
                lower,
                upper,
                geoms,
                masses[link],
                centre=centre,
                advisory=advisory,
            )
        )
        if centre:
            servo_map[name] = (left, KHR_SIGNS[left])
        else:
            assert right is not None
            servo_map["l_" + name] = (left, KHR_SIGNS[left])
            servo_map["r_" + name] = (right, KHR_SIGNS[right])
    root = Link(root_name, solid_many(masses[root_name], root_geoms), root_geoms)
    return build_humanoid(
        name="khr3hv-22" if full else "khr3hv",
        title=f"Kondo KHR-3HV ({'22-axis Ver.2' if full else '17-axis standard'})",
        root=root,
        joints=specs,
        servo_map=servo_map,
        servo=KRS_2552RHV,
        sources={
            "joint map": "FACTS.md: index = 2 x ICS ID + side, side 0 = left (kxreus "
            "rcb4robotconfig.l, robotlearn/khr3hv docs/ids.png, Meridian, KHRBan)",
            "signs": "kxreus rcb4robotconfig.l 'khr'/'khr20' (6, 7: chosen +1)",
            "limits": "hard: +-180 deg (no public bracket stops); advisory: robotlearn/khr3hv "
            "docs/limits.png and the extremes of Kondo's Hello_KHR3 sample motions",
            "dimensions": "FACTS.md KHRBan CAD table; hip, ankle, arm, head and boxes from "
            "sunilgora/SIP2HumnWalking kondo/kondo_khr3hv.xml (Apache-2.0); the foot plate "
            "(120 x 76.8 x 10 mm) from kxreus eusview khr3.json",
            "mass": f"{total:.4f} kg: 1.493 kg (kxreus eusview khr3.json)"
            + (" + 5 x 41.5 g servos" if full else ""),
            "servo": KRS_2552RHV.source,
        },
    )


def khr3hv() -> RobotModel:
    """The standard 17-axis KHR-3HV."""
    return _build(17)


def khr3hv_22() -> RobotModel:
    """The 22-axis KHR-3HV "Ver.2" (adds waist yaw, upper-arm yaw and hip yaw)."""
    return _build(22)
