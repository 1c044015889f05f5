"""The frames of the KXR families as :class:`~rcb4hv.robot.kit.assembly.Template` data.

Positions and masses come from :mod:`rcb4hv.robot.kit.figures` (each with its source).
Shapes are boxes around the servo cases (26 mm section, ``servo.case``) and the KXR wheel;
torso boxes are named choices (:data:`rcb4hv.robot.kit.parts.TORSO`); the multi-legged
families are in :mod:`rcb4hv.robot.kit.legged`.
"""

from __future__ import annotations

from dataclasses import replace

from rcb4hv.robot.kit.assembly import (
    Slot,
    Template,
    box,
    segment,
    sole,
)
from rcb4hv.robot.kit.code import KitCode
from rcb4hv.robot.kit.figures import fig, vec
from rcb4hv.robot.kit.legged import four, six
from rcb4hv.robot.kit.parts import TORSO as _TORSO
from rcb4hv.robot.kit.parts import Z_DOWN as _Z_DOWN
from rcb4hv.robot.kit.parts import add as _add
from rcb4hv.robot.kit.parts import joint_slot as _slot
from rcb4hv.robot.kit.parts import span as _span
from rcb4hv.robot.kit.parts import wheel_slot as _wheel_slot
from rcb4hv.robot.model import Geom, JointKind, Vec3
from rcb4hv.robot.servos import TRAVEL_DEG

__all__ = ["template"]

# --------------------------------------------------------------------- humanoid


def _arm(arms: int, gripper: bool) -> list[Slot]:
    # the A6's shoulder sits in front (kxreus's `:shoulder :pry-cross :shoulder-front t`)
    s = vec("arm6.shoulder" if arms == 6 else "l2.shoulder")
    pitch = _slot(
        "shoulder_pitch", None, s, "pitch", (-180, 180), (box((26, 20, 32), _add(s, (0, 14.5, 0))),)
    )
    if arms <= 3:
        roll = _add(s, vec("arm3.roll"))
        yaw = roll
        elbow = _add(roll, vec("arm3.elbow"))
        wrist = elbow
        grip = _add(elbow, vec("arm3.gripper"))
        order: tuple[JointKind, JointKind] = ("roll", "yaw")
    elif arms == 4:
        roll = _add(s, vec("arm4.roll"))
        yaw = _add(roll, vec("arm4.yaw"))
        elbow = _add(yaw, vec("arm4.elbow"))
        wrist = elbow
        grip = _add(elbow, vec("arm4.gripper"))
        order = ("roll", "yaw")
    elif arms <= 6:
        roll = _add(s, vec("arm6.roll"))
        yaw = _add(roll, vec("arm6.yaw"))
        elbow = _add(yaw, vec("arm6.elbow"))
        wrist = _add(elbow, vec("arm6.wrist"))
        grip = _add(_add(wrist, vec("arm6.wrist_roll")), vec("arm6.gripper"))
        if arms == 5:
            # no A5 figures: the A6's lengths with the forearm straight and the hand hanging
            # down, as kxreus builds the A5 without the A6's bent elbow (kxrl2l6a5h2:
            # `:shoulder :p :wrist :r`, no `:elbow :angle`)
            wrist = _add(elbow, (0.0, 0.0, vec("arm6.wrist")[2]))
            hand = vec("arm6.wrist_roll")[0] + vec("arm6.gripper")[0]
            grip = _add(wrist, (0.0, 0.0, -hand))
        order = ("roll", "yaw")
    else:
        yaw = _add(s, vec("arm7.yaw"))
        roll = yaw
        elbow = _add(roll, vec("arm7.elbow"))
        wrist = _add(_add(elbow, vec("arm7.wrist_yaw")), vec("arm7.wrist"))
        grip = _add(wrist, vec("arm7.gripper"))
        order = ("yaw", "roll")
    forward = arms == 6  # the A6's bent forearm points the hand forward at zero pose
    forearm, size = segment(wrist, grip, light=True), vec("arm3.basic_forearm")
    if arms <= 3 and not gripper:  # the basic kit's forearm ends at the elbow servo's base
        forearm = box(size, _add(elbow, (0, 0, size[2] / 2 - fig("arm3.basic_hand"))), True)
    first, second = order
    pos: dict[str, Vec3] = {"roll": roll, "yaw": yaw}
    lim: dict[str, tuple[float, float]] = {"roll": (-30.0, 185.0), "yaw": (-TRAVEL_DEG, TRAVEL_DEG)}
    upper = segment(pos[second], elbow, light=True)
    return [
        pitch,
        _slot(
            f"shoulder_{first}",
            "shoulder_pitch",
            pos[first],
            first,
            lim[first],
            # the A4's roll-to-yaw link is longer than a servo case: its frame spans it
            (segment(pos[first], pos[second]),) if _span(pos[first], pos[second]) > 26.0 else (),
        ),
        _slot(
            f"shoulder_{second}", f"shoulder_{first}", pos[second], second, lim[second], (upper,)
        ),
        _slot(
            "elbow_pitch",
            f"shoulder_{second}",
            elbow,
            "pitch",
            (-170, 170),
            (segment(elbow, wrist),),
        ),
        _slot("elbow_yaw", "elbow_pitch", elbow, "yaw", (-170, 170), ()),
        _slot("wrist_yaw", "elbow_yaw", wrist, "yaw", (-170, 170), ()),
        _slot(
            "wrist_pitch",
            "wrist_yaw",
            wrist,
            "pitch",
            (-125, 100),
            (forearm,),
        ),
        _slot("wrist_roll", "wrist_pitch", wrist, "roll", (-135, 135), ()),
        replace(
            _slot(
                "gripper",
                "wrist_roll",
                grip,
                "grip",
                (-100, 100),
                (_finger(grip, forward),),
                axis=_Z_DOWN if forward else None,
            ),
            optional=True,
        ),
    ]


def _finger(grip: Vec3, forward: bool) -> Geom:
    """The gripper's finger, 35 mm long, pointing the way the hand does at zero pose: down
    (A3, A4, A5, A7; it opens about x) or ``forward`` (A6; it opens about z, as kxreus's
    gripper frame turns it)."""
    if forward:
        return box((35, 6, 14), _add(grip, (17.5, -10, 0)), light=True)
    return box((14, 6, 35), _add(grip, (0, -10, -17.5)), light=True)


def _flip_x(v: Vec3) -> Vec3:
    return (-v[0], v[1], v[2])


def _leg(code: KitCode) -> list[Slot]:
    legs = code.legs or 5
    if legs <= 2:
        yaw = vec("l2.hip_l2")
        roll = _add(yaw, (0.0, 0.0, -fig("l2.short_leg")))
        wheel = vec("l2.base_wheel")
        return [
            _slot("hip_yaw", None, yaw, "yaw", (-90, 90), (segment(yaw, roll),)),
            # the short leg ends in the kit's sole: kxreus builds it `:leg :j2-pr :sole t`
            # (kxra6g, kxrmw4a6h2m), its leg end 31 mm below the roll axis as the sole's
            # underside is below the 5/6-axis leg's ankle roll (KXR-KITS.md §2.5)
            _slot(
                "hip_roll",
                "hip_yaw",
                roll,
                "roll",
                (-135, 133),
                (segment(roll, _add(roll, (0.0, 0.0, -fig("l2.sole_top")))), *sole(roll)),
            ),
            _wheel_slot("front_wheel", "hip_roll", _add(roll, wheel)),
            _wheel_slot("rear_wheel", "hip_roll", _add(roll, _flip_x(wheel))),
        ]
    if legs >= 6:
        yaw = vec("l2.hip_l6_wide" if code.width == "wide" else "l2.hip_l6")
        hip = _add(yaw, (0.0, 0.0, -fig("l2.hip_yaw_to_roll")))
    else:
        hip = vec("l2.hip_l5")
        yaw = hip
    knee = _add(hip, (0.0, 0.0, -fig("l2.thigh")))
    ankle = _add(knee, (0.0, 0.0, -fig("l2.shin")))
    return [
        _slot("hip_yaw", None, yaw, "yaw", (-90, 90), (box((26, 26, 20), _add(yaw, (0, 0, -10))),)),
        _slot(
            "hip_roll",
            "hip_yaw",
            hip,
            "roll",
            (-135, 133),
            (box((40, 27, 40), _add(hip, (-5, 0, -8))),),
        ),
        _slot("hip_pitch", "hip_roll", hip, "pitch", (-135, 90), (segment(hip, knee, 27, True),)),
        _slot(
            "knee_pitch", "hip_pitch", knee, "pitch", (-100, 160), (segment(knee, ankle, 27, True),)
        ),
        _slot(
            "ankle_pitch",
            "knee_pitch",
            ankle,
            "pitch",
            (-105, 105),
            (box((40, 27, 40), _add(ankle, (-5, 0, 8))),),
        ),
        _slot("ankle_roll", "ankle_pitch", ankle, "roll", (-170, 170), sole(ankle)),
        _wheel_slot(
            "ankle_wheel", "ankle_pitch", _add(ankle, vec("l2.ankle_wheel")), vec("l2.ankle_tyre")
        ),
        _wheel_slot("front_wheel", "ankle_roll", _add(ankle, vec("l2.foot_wheel"))),
        _wheel_slot("rear_wheel", "ankle_roll", _add(ankle, _flip_x(vec("l2.foot_wheel")))),
    ]


def _humanoid(code: KitCode) -> Template:
    size, centre = _TORSO["humanoid"]
    neck = vec("l2.neck_yaw")
    head = _add(neck, vec("l2.neck_pitch"))
    slots = (
        _arm(code.arms or 3, code.gripper)
        + _leg(code)
        + [
            _slot(
                "waist_yaw",
                None,
                (0.0, 0.0, -5.0),
                "yaw",
                (-135, 135),
                (box((40, 60, 10), (0, 0, -5)),),
                True,
            ),
            _slot(
                "neck_yaw",
                None,
                neck,
                "yaw",
                (-170, 170),
                (box((26, 26, 20), _add(neck, (0, 0, 10))),),
                True,
            ),
            _slot(
                "neck_pitch",
                "neck_yaw",
                head,
                "pitch",
                (-120, 120),
                (box((40, 40, 45), _add(head, (5, 0, 10)), True),),
                True,
            ),
        ]
    )
    return Template("humanoid", (box(size, centre, True),), tuple(slots))


# --------------------------------------------------------------------- legged


def template(code: KitCode, *, arms: bool | None = None) -> Template:
    """The frame of the kit ``code`` describes; ``arms``: whether a four-legged body carries
    arms (default: whether the code says so; a project's servo names may say it instead)."""
    if code.family == "humanoid":
        return _humanoid(code)
    if code.family == "L6":
        return six()
    return four(code.family, arms=bool(code.arms) if arms is None else arms)
