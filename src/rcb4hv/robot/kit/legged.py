"""The frames of the multi-legged KXR families: the six-legged L6 and the four-legged L4D,
L4T, L4N and L4R (with the L4R2A3(G)'s arms), as :class:`~rcb4hv.robot.kit.assembly.Template`
data (positions from :mod:`rcb4hv.robot.kit.figures`, each with its source)."""

from __future__ import annotations

from dataclasses import replace

from rcb4hv.robot.kit.assembly import Slot, Template, box, cylinder_x, segment
from rcb4hv.robot.kit.code import Family
from rcb4hv.robot.kit.figures import fig, vec
from rcb4hv.robot.kit.parts import TORSO as _TORSO
from rcb4hv.robot.kit.parts import WHEEL_LIMITS
from rcb4hv.robot.kit.parts import X as _X
from rcb4hv.robot.kit.parts import Y as _Y
from rcb4hv.robot.kit.parts import add as _add
from rcb4hv.robot.kit.parts import joint_slot as _slot
from rcb4hv.robot.kit.parts import wheel_slot as _wheel_slot
from rcb4hv.robot.model import Geom, JointKind, Vec3

__all__ = ["four", "six"]


def six() -> Template:
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


def four(family: Family, arms: bool = False) -> Template:
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
