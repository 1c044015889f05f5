"""The frames of the KXR families as :class:`~rcb4hv.robot.kit.assembly.Template` data.

Positions and masses come from :mod:`rcb4hv.robot.kit.figures` (each with its source).
Shapes are boxes around the servo cases (26 mm section, ``servo.case``) and the KXR wheel;
torso boxes are named choices (``_TORSO``).
"""

from __future__ import annotations

from dataclasses import replace

from rcb4hv.robot.kit.assembly import (
    Slot,
    Template,
    box,
    cylinder_x,
    cylinder_y,
    segment,
    sole,
)
from rcb4hv.robot.kit.code import Family, KitCode
from rcb4hv.robot.kit.figures import fig, vec
from rcb4hv.robot.model import Geom, JointKind, Vec3
from rcb4hv.robot.servos import TRAVEL_DEG

__all__ = ["template"]

_X, _Y, _Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
_Z_DOWN = (0.0, 0.0, -1.0)
_AXIS: dict[JointKind, Vec3] = {
    "pitch": _Y,
    "roll": _X,
    "yaw": _Z,
    "wheel": _Y,
    "grip": (-1.0, 0.0, 0.0),
}
WHEEL_LIMITS = (-TRAVEL_DEG, TRAVEL_DEG)  # a wheel's "angle" is its speed command

# chosen torso boxes (size, centre; mm): the body between the hips/shoulders of each family
_TORSO: dict[str, tuple[Vec3, Vec3]] = {
    "humanoid": ((50.0, 69.0, 95.0), (-7.25, 0.0, 37.5)),
    "L6": ((150.0, 87.0, 40.0), (0.0, 0.0, 5.0)),
    "L4T": ((110.0, 105.0, 40.0), (0.0, 0.0, 5.0)),
    "L4D": ((160.0, 70.0, 40.0), (0.0, 0.0, 10.0)),
}


def _add(a: Vec3, b: Vec3) -> Vec3:
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def _slot(
    name: str,
    parent: str | None,
    pos: Vec3,
    kind: JointKind,
    limits: tuple[float, float],
    geoms: tuple[Geom, ...],
    centre: bool = False,
    axis: Vec3 | None = None,
) -> Slot:
    return Slot(name, parent, pos, axis or _AXIS[kind], kind, limits, geoms, centre)


def _span(a: Vec3, b: Vec3) -> float:
    return max(abs(a[k] - b[k]) for k in range(3))


def _wheel_slot(name: str, parent: str, axle: Vec3, tyre_at: Vec3 = (0.0, 0.0, 0.0)) -> Slot:
    """A wheel turning about ``axle`` (its joint), its tyre ``tyre_at`` along from it."""
    tyre = cylinder_y(fig("wheel.radius"), fig("wheel.width"), _add(axle, tyre_at))
    return replace(_slot(name, parent, axle, "wheel", WHEEL_LIMITS, (tyre,)), optional=True)


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


def _six() -> Template:
    slots: list[Slot] = []
    coxa, femur, tibia = fig("l6.coxa"), fig("l6.femur"), vec("l6.tibia")
    for limb, base, d in (
        ("front", vec("l6.front"), _X),
        ("middle", vec("l6.middle"), _Y),
        ("rear", (-vec("l6.front")[0], *vec("l6.front")[1:]), (-1.0, 0.0, 0.0)),
    ):
        kind: JointKind = "roll" if limb == "middle" else "pitch"
        lift = _add(base, tuple(coxa * c for c in d))  # type: ignore[arg-type]
        knee = _add(lift, tuple(femur * c for c in d))  # type: ignore[arg-type]
        along = tibia[0]
        end = _add(knee, (along * d[0], along * d[1], tibia[2]))
        slots += [
            _slot(f"{limb}_yaw", None, base, "yaw", (-112, 112), (segment(base, lift),)),
            _slot(
                f"{limb}_lift",
                f"{limb}_yaw",
                lift,
                kind,
                (-170, 170),
                (segment(lift, knee, light=True),),
            ),
            _slot(
                f"{limb}_knee",
                f"{limb}_lift",
                knee,
                kind,
                (-170, 170),
                (segment(knee, end, 20, True),),
            ),
        ]
    size, centre = _TORSO["L6"]
    return Template("L6", (box(size, centre, True),), tuple(slots))


def _neck_case(torso: tuple[Vec3, Vec3], joint: Vec3) -> tuple[Geom, ...]:
    """The neck servo's case on the torso, from the torso box's top up to the joint it turns
    (kxreus places the joint above the body; the case between is part of the torso link, and
    without it the head floated 28.5 mm over the body). A column of the case's section, a
    chosen shape (``servo.case``: 26 mm square)."""
    (_, _, height), (_, _, middle) = torso
    top = middle + height / 2
    if joint[2] <= top:
        return ()
    side = vec("servo.case")[1]
    return (box((side, side, joint[2] - top), (joint[0], joint[1], (top + joint[2]) / 2), True),)


def _neck(family: Family, base: Vec3, pitches: int) -> list[Slot]:
    up = vec("l4t.neck_pitch")
    out = [
        _slot(
            "neck_yaw",
            None,
            base,
            "yaw",
            (-170, 170),
            (box((26, 26, 36), _add(base, (0, 0, 18))),),
            True,
        )
    ]
    parent, pos = "neck_yaw", _add(base, up)
    for k in range(pitches):
        name = "neck_pitch" if k == 0 else f"neck_pitch{k + 1}"
        nxt = _add(pos, up) if k + 1 < pitches else _add(pos, (30.0, 0.0, 0.0))
        out.append(
            _slot(name, parent, pos, "pitch", (-120, 120), (segment(pos, nxt, light=True),), True)
        )
        parent, pos = name, nxt
    if family == "L4N":
        hand = _add(pos, vec("l4n.hand"))
        out.append(
            _slot("gripper", parent, pos, "pitch", (-100, 100), (box((35, 10, 14), hand),), True)
        )
    return out


def _four(family: Family, arms: bool = False) -> Template:
    """A four-legged frame; ``arms``: the L4R2A3(G) build, whose front limbs are arms."""
    slots: list[Slot] = []
    if family == "L4D":
        for limb, sx in (("front", 1.0), ("rear", -1.0)):
            hip = vec("l4d.hip")
            p = (sx * hip[0], hip[1], hip[2])
            r = _add(p, vec("l4d.roll"))
            k = _add(r, vec("l4d.knee"))
            a = _add(k, vec("l4d.ankle"))
            foot = _add(a, vec("l4d.foot"))
            slots += [
                _slot(f"{limb}_pitch", None, p, "pitch", (-135, 135), (segment(p, r),)),
                _slot(
                    f"{limb}_roll",
                    f"{limb}_pitch",
                    r,
                    "roll",
                    (-80, 120),
                    (segment(r, k, light=True),),
                ),
                _slot(
                    f"{limb}_knee",
                    f"{limb}_roll",
                    k,
                    "pitch",
                    (-170, 170),
                    (segment(k, a, light=True),),
                ),
                _slot(
                    f"{limb}_ankle",
                    f"{limb}_knee",
                    a,
                    "pitch",
                    (-90, 90),
                    (
                        segment(a, (a[0], a[1], foot[2]), 20),
                        box((40, 30, 6), _add(foot, (0, 0, 3)), True),
                    ),
                ),
            ]
        neck = vec("l4d.neck")
        jaw = _add(neck, vec("l4d.jaw"))
        slots += [
            _slot(
                "neck_pitch",
                None,
                neck,
                "pitch",
                (-120, 120),
                (segment(neck, jaw, light=True),),
                True,
            ),
            _slot(
                "jaw",
                "neck_pitch",
                jaw,
                "pitch",
                (-100, 100),
                (box((40, 20, 10), _add(jaw, (15, 0, -8))),),
                True,
            ),
        ]
        size, centre = _TORSO["L4D"]
        body = (box(size, centre, True), *_neck_case(_TORSO["L4D"], vec("l4d.neck")))
        return Template(family, body, tuple(slots))
    if family == "R4LL":
        for limb, sx in (("front", 1.0), ("rear", -1.0)):
            hip = vec("r4ll.hip")
            y = (sx * hip[0], hip[1], hip[2])
            p = _add(y, vec("r4ll.pitch"))
            w = _add(p, vec("r4ll.leg"))
            slots += [
                _slot(f"{limb}_yaw", None, y, "yaw", (-135, 135), (segment(y, p),)),
                _slot(
                    f"{limb}_pitch",
                    f"{limb}_yaw",
                    p,
                    "pitch",
                    (-135, 135),
                    (segment(p, w, light=True),),
                ),
                _wheel_slot(
                    f"{limb}_wheel", f"{limb}_pitch", _add(w, (0.0, fig("wheel.axle_offset"), 0.0))
                ),
            ]
        size, centre = _TORSO["L4D"]
        body = (box(size, centre, True), *_neck_case(_TORSO["L4D"], vec("l4d.neck")))
        return Template(family, body, tuple(slots))
    # L4T, L4N, L4R: the turtle body, legs sideways from a yaw joint
    for limb, sx in (("front", 1.0), ("rear", -1.0)):
        hip = vec("l4t.hip")
        y = (sx * hip[0], hip[1], hip[2])
        if family == "L4R":
            w = _add(y, vec("l4r.wheel"))
            # the L4R2A3's front yaw joint carries an arm, not a wheel leg: its part is the
            # bracket out to the shoulder roll (kxrl4r2a3.json rarm-shoulder-y: 17 g, nothing
            # below the joint), so nothing of a front leg reaches the floor
            end = _add(y, vec("l4r.shoulder")) if arms and limb == "front" else w
            slots += [
                _slot(f"{limb}_yaw", None, y, "yaw", (-110, 110), (segment(y, end),)),
                _wheel_slot(
                    f"{limb}_wheel", f"{limb}_yaw", _add(w, (0.0, fig("wheel.axle_offset"), 0.0))
                ),
            ]
            continue
        r = _add(y, vec("l4t.roll"))
        foot = _add(r, vec("l4t.foot"))
        slots += [
            _slot(f"{limb}_yaw", None, y, "yaw", (-110, 110), (segment(y, r),)),
            _slot(
                f"{limb}_roll", f"{limb}_yaw", r, "roll", (-110, 110), (segment(r, foot, 22, True),)
            ),
        ]
    if family == "L4R":  # the L4R2A3(G) build: a 3-axis arm on each front yaw joint
        y = vec("l4t.hip")
        roll = _add(y, vec("l4r.shoulder"))
        elbow = _add(roll, vec("l4r.upper_arm"))
        grip = _add(elbow, vec("l4r.forearm"))
        arm = [
            _slot("arm_roll", "front_yaw", roll, "roll", (-110, 110),
                  (segment(roll, elbow, light=True),)),
            _slot("arm_elbow", "arm_roll", elbow, "roll", (-170, 170), (segment(elbow, grip),)),
            _slot("gripper", "arm_elbow", grip, "grip", (-100, 100),
                  (box((35, 10, 14), _add(grip, (0, 17.5, 0)), True),)),
        ]  # fmt: skip
        # the L4R2A3G's front rolls on a free wheel beside each arm: kxreus builds them with
        # its grippers (`:passive-wheel :shoulder`), not on the L4R2A3
        disc = _add(roll, vec("l4r.arm_wheel"))
        tyre = cylinder_x(fig("wheel.radius"), fig("wheel.width"), disc)
        wheel = _slot("arm_wheel", "front_yaw", roll, "wheel", WHEEL_LIMITS, (tyre,), axis=_X)
        arm.append(replace(wheel, passive_with="gripper"))
        slots += [replace(s, optional=True) for s in arm]
    slots += _neck(family, vec("l4t.neck"), 3 if family == "L4N" else 1)
    size, centre = _TORSO["L4T"]
    body = (box(size, centre, True), *_neck_case(_TORSO["L4T"], vec("l4t.neck")))
    return Template(family, body, tuple(slots))


def template(code: KitCode, *, arms: bool | None = None) -> Template:
    """The frame of the kit ``code`` describes; ``arms``: whether a four-legged body carries
    arms (default: whether the code says so; a project's servo names may say it instead)."""
    if code.family == "humanoid":
        return _humanoid(code)
    if code.family == "L6":
        return _six()
    return _four(code.family, arms=bool(code.arms) if arms is None else arms)
