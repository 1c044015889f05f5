"""Per-link figures of the builds kxreus weighs link by link (its eusview json files'
``physics.links``): masses (g), centres of mass (mm) and moments of inertia about them
(g·cm²; the products of inertia, at most a fifth of a moment, are left out) in the model's
link frame (the robot's axes at zero pose, left side, the origin at the model's joint). Part
of :data:`rcb4hv.robot.kit.figures.FIGURES` (one table), kept here for its length. Generated
from the json files' numbers; a part several builds share is written once (``_PART``).
"""

from __future__ import annotations

from rcb4hv.robot.kit.sources import Figure
from rcb4hv.robot.kit.sources import row as _f

_Vec = tuple[float, float, float]
#: one weighed link: (slot, index in physics.links, what it is, mass g, com mm, moments g·cm²,
#: the servo cases kxreus counts in it at 27.73 g each)
_Link = tuple[str, int, str, float, _Vec | None, _Vec | None, int]

__all__ = ["LINK_ROWS"]

EUCLID_HEAD_G = 145.7
"""The Intel Euclid head (g) kxreus mounts on its ``:head :e`` builds (its explicit part masses,
KXR-KITS.md §3): the KXR-L2W2L6A4H2's and KXR-L2W2L5A3H2's head-neck-p links carry it
(156.521 g). Kondo's samples of those builds carry Kondo's own head part, which no source
weighs, so the model's neck-pitch link is kxreus's less this part: the servo horn's bracket
alone, its centre of mass and moments the model's own shapes'."""


def _neck_without_euclid_head(index: int) -> _Link:
    """The ``:head :e`` builds' head-neck-p link (physics.links[``index``], 156.521 g in both
    jsons) less :data:`EUCLID_HEAD_G`: its centre of mass and moments the model's own shapes'."""
    return (
        "neck_pitch",
        index,
        "head-neck-p (156.521 g) less the Euclid head (part.euclid_head), which Kondo's build "
        "lacks",
        156.521 - EUCLID_HEAD_G,
        None,
        None,
        0,
    )


# parts with the same figures in several builds' jsons (kxreus weighs each link from its
# boxes): name -> (what, mass g, com mm, moments g·cm², servo cases)
_PART: dict[str, tuple[str, float, _Vec, _Vec, int]] = {
    "hip_yaw": ("lleg-crotch-y", 11.547, (0.0, 0.0, -12.994), (18.2922, 32.7364, 23.7035), 0),
    "hip_roll": (
        "lleg-crotch-r (2 servos)",
        78.374,
        (-13.148, 0.0, -8.556),
        (118.7695, 357.5857, 338.7957),
        2,
    ),
    "hip_pitch": ("lleg-crotch-p", 22.434, (0.0, 0.0, -33.737), (99.6459, 70.1625, 47.8128), 0),
    "knee_pitch": ("lleg-knee-p", 54.3, (10.966, 0.0, -12.284), (193.2207, 201.9425, 106.4056), 1),
    "ankle_wheel": (
        "lleg-ankle-w (tyre 39.87 + horn 0.46)",
        40.332,
        (0.0, 23.412, 0.0),
        (99.2558, 186.3529, 99.2813),
        0,
    ),
    "ankle_roll": (
        "lleg-ankle-r (sole plate)",
        38.432,
        (0.0, 7.514, -25.416),
        (147.3124, 301.5243, 402.4514),
        0,
    ),
}


def _rows(build: str, source: str, links: list[_Link]) -> dict[str, Figure]:
    """The lmass / lcom / linert rows of ``build``'s weighed links (``source``: the json)."""
    out: dict[str, Figure] = {}
    for slot, i, what, mass, com, inertia, cases in links:
        where = f"{source} physics.links[{i}]"
        out[f"lcases.{build}.{slot}"] = _f(
            float(cases), "servos", "KX", f"{where}: its 27.73 g servo-case boxes"
        )
        out[f"lmass.{build}.{slot}"] = _f(mass, "g", "KX", f"{where} {what}".rstrip())
        if com is not None:
            out[f"lcom.{build}.{slot}"] = _f(com, "mm", "KX", f"{where} com")
        if inertia is not None:
            out[f"linert.{build}.{slot}"] = _f(
                inertia, "g·cm²", "KX", f"{where} inertia ixx, iyy, izz"
            )
    return out


# kxreus's KXR-L2W2L6A4H2 (kxrl2w2l6a4h2.json): its gripper fingers' centres of mass are in
# rotated frames, not taken; the tyres it puts on the A4 arms' ends are left out
_W2L6A4: list[_Link] = [
    (
        "torso",
        0,
        "torso: 5 servos, board, battery box 30 g, back-pack 66 g",
        437.985,
        (-6.626, 0.0, 30.964),
        (8345.2624, 7306.4656, 4648.4596),
        5,
    ),
    (
        "shoulder_pitch",
        8,
        "left arm's 1st link (shoulder-p)",
        11.283,
        (0.0, 12.333, 0.0),
        (16.2679, 22.9413, 30.0663),
        0,
    ),
    (
        "shoulder_roll",
        9,
        "2nd (shoulder-r, 2 servos)",
        80.649,
        (-3.649, 0.0, -34.002),
        (470.5507, 502.6735, 127.0268),
        2,
    ),
    (
        "shoulder_yaw",
        10,
        "3rd (shoulder-y)",
        11.283,
        (0.0, 0.0, -12.333),
        (30.0663, 16.2679, 22.9413),
        0,
    ),
    (
        "elbow_pitch",
        11,
        "4th (elbow-p, 2 servos)",
        74.384,
        (0.0, 5.27, -31.679),
        (458.4022, 415.938, 141.462),
        2,
    ),
    ("hip_yaw", 22, *_PART["hip_yaw"]),
    ("hip_roll", 23, *_PART["hip_roll"]),
    ("hip_pitch", 24, *_PART["hip_pitch"]),
    ("knee_pitch", 25, *_PART["knee_pitch"]),
    (
        "ankle_pitch",
        26,
        "lleg-ankle-p: 3 servos (ankle pitch, ankle roll, the wheel's) and their frames",
        122.858,
        (-33.808, 0.0, 9.676),
        (207.2716, 1400.3496, 1357.4437),
        3,
    ),
    ("ankle_wheel", 27, *_PART["ankle_wheel"]),
    ("ankle_roll", 28, *_PART["ankle_roll"]),
    (
        "neck_yaw",
        29,
        "head-neck-y (1 servo)",
        37.982,
        (8.177, 0.0, 22.956),
        (87.2107, 89.7321, 58.3253),
        1,
    ),
    _neck_without_euclid_head(30),
]

# kxreus's KXR-L2L6A6H2 (kxrl2l6a6h2.json, 31 links summing to its 1708.46 g): the A6 arm's
# wrist-roll frame is 15 mm forward of the model's wrist joint and the two fingers' frames are
# turned, so those rows are given in the model's frames (com from the joint; the fingers'
# moments about the gripper joint's axes, parallel axes)
_L6A6: list[_Link] = [
    (
        "torso",
        0,
        "torso-link-l2l6: board, battery box, back pack and the servos on the torso",
        437.985,
        (-6.705, 0.0, 30.964),
        (8345.2624, 7306.304, 4648.298),
        5,
    ),
    (
        "shoulder_pitch",
        9,
        "larm-shoulder-p",
        11.547,
        (0.0, 12.994, 0.0),
        (18.2922, 23.7035, 32.7364),
        0,
    ),
    (
        "shoulder_roll",
        10,
        "larm-shoulder-r (2 servos)",
        78.374,
        (-13.148, 8.556, 0.0),
        (118.7695, 338.7957, 357.5857),
        2,
    ),
    (
        "shoulder_yaw",
        11,
        "larm-shoulder-y",
        12.867,
        (0.0, 0.0, -16.508),
        (49.1613, 31.4878, 27.5141),
        0,
    ),
    (
        "elbow_pitch",
        12,
        "larm-elbow-p",
        52.98,
        (-14.792, 0.0, -5.477),
        (141.5894, 162.8648, 112.3415),
        1,
    ),
    (
        "wrist_pitch",
        13,
        "larm-wrist-p (2 servos)",
        78.374,
        (0.0, 13.148, -8.556),
        (357.5857, 118.7695, 338.7957),
        2,
    ),
    (
        "wrist_roll",
        14,
        "larm-wrist-r: its com (20.834, 2.435, 0) + 15 mm in x (its frame is 15 mm forward of "
        "the model's wrist joint)",
        42.518,
        (35.834, 2.435, 0.0),
        (63.8086, 92.7799, 96.6327),
        1,
    ),
    (
        "gripper",
        15,
        "+ [16]: the two fingers, 13.267 g each (one servo drives both), their rotated frames "
        "turned into the model's: the com from the gripper joint, the moments about it "
        "(parallel axes)",
        26.534,
        (20.023, -1.24, 0.0),
        (139.754, 126.468, 185.402),
        0,
    ),
    ("hip_yaw", 23, *_PART["hip_yaw"]),
    ("hip_roll", 24, *_PART["hip_roll"]),
    ("hip_pitch", 25, *_PART["hip_pitch"]),
    ("knee_pitch", 26, *_PART["knee_pitch"]),
    (
        "ankle_pitch",
        27,
        "lleg-ankle-p (2 servos)",
        78.374,
        (-13.148, 0.0, 8.556),
        (118.7695, 357.5857, 338.7957),
        2,
    ),
    ("ankle_roll", 28, *_PART["ankle_roll"]),
    ("neck_yaw", 29, "head-neck-y", 37.326, (0.0, 0.0, 23.134), (84.8797, 79.9577, 48.4722), 1),
    (
        "neck_pitch",
        30,
        "head-neck-p (head)",
        59.841,
        (3.295, 0.0, 36.165),
        (244.5798, 182.5243, 120.6694),
        0,
    ),
]

# kxreus's KXR-L2W2L5A3H2 (kxrl2w2l5a3h2.json, 27 links summing to its 1690.68 g; without
# the two arm tyres and the Euclid head the model's links sum to 1465.24 g)
_W2L5A3: list[_Link] = [
    (
        "torso",
        0,
        "torso-link-l2l5: board, battery box, back pack and the servos on the torso",
        372.584,
        (-6.209, 0.0, 40.39),
        (5712.364, 5036.4576, 4204.1044),
        3,
    ),
    (
        "shoulder_pitch",
        7,
        "larm-shoulder-p (the model has it 1.5 mm higher, as models/kxrl2g.l)",
        11.283,
        (0.0, 12.333, 0.0),
        (16.2679, 22.9413, 30.0663),
        0,
    ),
    (
        "shoulder_roll",
        8,
        "larm-shoulder-r",
        42.494,
        (0.0, 0.0, -16.632),
        (147.1227, 137.7748, 64.0241),
        1,
    ),
    (
        "elbow_pitch",
        9,
        "larm-elbow-p (2 servos)",
        74.384,
        (-0.001, 5.27, -31.679),
        (458.4022, 415.938, 141.462),
        2,
    ),
    (
        "gripper",
        10,
        "+ [11]: the two fingers, 23.767 + 13.267 g (one servo drives both), their rotated "
        "frames turned into the model's: the com from the gripper joint, the moments about it "
        "(parallel axes); the tyre kxreus puts on it ([12]) has no servo in Kondo's project and "
        "is left out",
        37.034,
        (0.0, 29.6496, -13.245),
        (294.367, 143.1225, 244.2761),
        0,
    ),
    ("hip_roll", 19, *_PART["hip_roll"]),
    ("hip_pitch", 20, *_PART["hip_pitch"]),
    ("knee_pitch", 21, *_PART["knee_pitch"]),
    (
        "ankle_pitch",
        22,
        "lleg-ankle-p: 3 servos (ankle pitch, ankle roll, the wheel's) and their frames",
        122.858,
        (-33.808, 0.001, 9.676),
        (207.2716, 1400.3496, 1357.4437),
        3,
    ),
    ("ankle_wheel", 23, *_PART["ankle_wheel"]),
    ("ankle_roll", 24, *_PART["ankle_roll"]),
    (
        "neck_yaw",
        25,
        "head-neck-y",
        37.982,
        (8.177, -0.002, 22.956),
        (87.2107, 89.7321, 58.3253),
        1,
    ),
    _neck_without_euclid_head(26),
]

LINK_ROWS: dict[str, Figure] = {
    **_rows("L2W2L6A4H2G", "kxrl2w2l6a4h2.json", _W2L6A4),
    **_rows("L2L6A6H2G", "kxrl2l6a6h2.json", _L6A6),
    **_rows("L2W2L5A3H2G", "kxrl2w2l5a3h2.json", _W2L5A3),
    "lmass.L2W2L6A4H2G.gripper": _f(
        37.034,
        "g",
        "KX",
        "kxrl2w2l6a4h2.json physics.links[12] + [13]: the two gripper fingers 23.767 + "
        "13.267 g (one servo drives both; their CoMs are in rotated frames, not taken)",
    ),
    "part.euclid_head": _f(
        EUCLID_HEAD_G,
        "g",
        "KX",
        "kxreus's explicit part masses (KXR-KITS.md §3): the Intel Euclid head of its `:head :e` "
        "builds, in the KXR-L2W2L6A4H2's and KXR-L2W2L5A3H2's head-neck-p links; Kondo's "
        "samples of those builds carry Kondo's own head part (no source weighs it), so the "
        "model leaves this out",
    ),
    "wheel.tyre_mass": _f(
        39.87,
        "g",
        "KX",
        "kxrl2w2l6a4h2.json physics.links[14] (and [7]): the KXR wheel kxreus puts on each A4 "
        "arm's end; Kondo's project has no servo for it, so the kit builder leaves it out there "
        "(the model weighs mass.L2W2L6A4H2G less two of these and part.euclid_head); a wheel "
        "servo a weighed build lacks carries one",
    ),
}
