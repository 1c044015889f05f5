"""A small KXR-L2-like robot model for the editor tests: every joint at ±135° and no trims
or frame limits of its own, and offsets the test chooses, so an edit's result depends only on
the joint map (the built-in ``kxr-l2`` carries the kit's trims and frame limits).

Joint kinds and left/right signs follow the fixture's own mirror pairs: its TURN_LEFT and
TURN_RIGHT motions, and its home pose (same value on both knees, hips and ankles: the
same sign; shoulder pitch 7900 / 7100: opposite signs).
"""

from __future__ import annotations

import math

from rcb4hv.robot import Inertial, Joint, JointKind, Link, RobotModel, ServoJoint
from rcb4hv.robot.servos import TRAVEL_DEG

LIMIT = math.radians(TRAVEL_DEG)  # an ICS servo turns +-135 degrees about its centre

# (right ICS, left ICS, name, kind, right sign, left sign)
PAIRS: tuple[tuple[int, int, str, JointKind, int, int], ...] = (
    (2, 3, "shoulder_pitch", "pitch", 1, -1),
    (4, 5, "shoulder_roll", "roll", 1, 1),
    (6, 7, "elbow", "pitch", 1, 1),
    (8, 9, "hip_roll", "roll", 1, 1),
    (10, 11, "hip_pitch", "pitch", 1, 1),
    (12, 13, "knee", "pitch", 1, 1),
    (14, 15, "ankle_pitch", "pitch", 1, 1),
    (16, 17, "ankle_roll", "roll", 1, 1),
    (18, 19, "gripper", "grip", 1, 1),
)


def kxr_like(*, offsets: dict[int, int] | None = None, limit: float = LIMIT) -> RobotModel:
    """The model; ``offsets`` gives servos a zero offset in counts (ICS -> counts)."""
    offsets = offsets or {}
    inertial = Inertial(0.01, (0.0, 0.0, 0.0), (1e-6, 1e-6, 1e-6, 0.0, 0.0, 0.0))
    links = [Link("body", inertial)]
    joints: list[Joint] = []
    servos: list[ServoJoint] = []
    for right, left, name, kind, rs, ls in PAIRS:
        axis = {"pitch": (0.0, 1.0, 0.0), "roll": (1.0, 0.0, 0.0), "grip": (0.0, 0.0, 1.0)}
        for side, ics, sign, other in (("right", right, rs, "left"), ("left", left, ls, "right")):
            jname = f"{side}_{name}"
            links.append(Link(f"{jname}_link", inertial))
            joints.append(
                Joint(
                    jname,
                    "body",
                    f"{jname}_link",
                    (0.0, 0.0, 0.0),
                    (0.0, 0.0, 0.0),
                    axis[kind],
                    -limit,
                    limit,
                    kind,
                    side,  # type: ignore[arg-type]
                    f"{other}_{name}",
                )
            )
            servos.append(ServoJoint(ics, jname, sign, offsets.get(ics, 0)))
    return RobotModel(
        "kxr-test", "KXR-like test model", "body", tuple(links), tuple(joints), tuple(servos)
    )
