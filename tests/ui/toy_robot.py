"""A small humanoid for the 3D-view tests: round numbers, so poses can be checked by hand.

The torso's origin is on the hip line; legs hang 0.06 + 0.06 m to the ankle, whose foot box
(0.08 x 0.04 x 0.01 m) puts the soles 0.13 m below it. ICS numbers follow the default board
(2/3 shoulders, 14-19 legs; the right side turns the other way, as motion 1 of the default
board raises both arms with +2700 on ICS 2 and -2700 on ICS 3).
"""

from __future__ import annotations

from rcb4hv.robot import Geom, Inertial, Joint, Link, RobotModel, ServoJoint

LEG = 0.06
SOLE = (0.08, 0.04, 0.01)
SOLE_DROP = 0.01  # ankle axis to the sole's top


def _inertial(mass: float, com: tuple[float, float, float]) -> Inertial:
    return Inertial(mass, com, (1e-5, 1e-5, 1e-5, 0.0, 0.0, 0.0))


def toy_model() -> RobotModel:
    links = [
        Link(
            "torso",
            _inertial(0.4, (0.0, 0.0, 0.06)),
            (Geom("box", (0.06, 0.1, 0.12), (0.0, 0.0, 0.06)),),
        ),
        Link(
            "head", _inertial(0.05, (0.0, 0.0, 0.02)), (Geom("sphere", (0.02, 0, 0), (0, 0, 0.02)),)
        ),
    ]
    joints = [
        Joint("head_yaw", "torso", "head", (0, 0, 0.12), (0, 0, 0), (0, 0, 1), -2.3, 2.3, "yaw"),
    ]
    servos = [ServoJoint(0, "head_yaw")]
    for side, y, first, sign in (("left", 1.0, 0, 1), ("right", -1.0, 1, -1)):
        s = side[0]
        other = "r" if s == "l" else "l"
        links += [
            Link(
                f"{s}_arm",
                _inertial(0.04, (0, 0, -0.04)),
                (Geom("box", (0.03, 0.03, 0.08), (0, 0, -0.04)),),
            ),
            Link(
                f"{s}_thigh",
                _inertial(0.06, (0, 0, -LEG / 2)),
                (Geom("cylinder", (0.015, LEG, 0), (0, 0, -LEG / 2)),),
            ),
            Link(
                f"{s}_shin",
                _inertial(0.05, (0, 0, -LEG / 2)),
                (Geom("box", (0.03, 0.03, LEG), (0, 0, -LEG / 2)),),
            ),
            Link(
                f"{s}_foot",
                _inertial(0.03, (0.01, 0, -SOLE_DROP)),
                (Geom("box", SOLE, (0.01, 0.0, -SOLE_DROP - SOLE[2] / 2)),),
            ),
        ]
        joints += [
            Joint(
                f"{s}_shoulder_pitch",
                "torso",
                f"{s}_arm",
                (0, y * 0.065, 0.11),
                (0, 0, 0),
                (0, 1, 0),
                -3.0,
                3.0,
                "pitch",
                side,
                f"{other}_shoulder_pitch",
            ),
            Joint(
                f"{s}_hip_pitch",
                "torso",
                f"{s}_thigh",
                (0, y * 0.025, 0),
                (0, 0, 0),
                (0, 1, 0),
                -1.6,
                1.6,
                "pitch",
                side,
                f"{other}_hip_pitch",
            ),
            Joint(
                f"{s}_knee",
                f"{s}_thigh",
                f"{s}_shin",
                (0, 0, -LEG),
                (0, 0, 0),
                (0, 1, 0),
                -0.5,
                2.4,
                "pitch",
                side,
                f"{other}_knee",
            ),
            Joint(
                f"{s}_ankle_pitch",
                f"{s}_shin",
                f"{s}_foot",
                (0, 0, -LEG),
                (0, 0, 0),
                (0, 1, 0),
                -1.6,
                1.6,
                "pitch",
                side,
                f"{other}_ankle_pitch",
            ),
        ]
        servos += [
            ServoJoint(2 + first, f"{s}_shoulder_pitch", sign),
            ServoJoint(14 + first, f"{s}_hip_pitch", sign),
            ServoJoint(16 + first, f"{s}_knee", sign),
            ServoJoint(18 + first, f"{s}_ankle_pitch", sign),
        ]
    return RobotModel("toy", "toy humanoid", "torso", tuple(links), tuple(joints), tuple(servos))
