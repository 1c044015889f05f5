"""Servo roles -> the joints of one family's frame (the joint map's names).

:func:`map_roles` places every named servo on a slot of a family: humanoid names by body part
and axis (``右肩（ピッチ）`` -> ``r_shoulder_pitch``), legged names by limb position and
segment, axis or order (``右中脚（先）`` -> ``r_middle_knee``). A servo name without a side
(``腿ロール``) takes the side of its ICS number; so does every servo (the kit's wiring,
:func:`_side_prefix`), and a name saying the other side is noted. The result
says which servos found no slot, so a family that does not fit is visible.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

from rcb4hv.robot.kit.code import Family
from rcb4hv.robot.kit.convention import LIMBS
from rcb4hv.robot.kit.names import Role

__all__ = ["Placement", "map_roles"]

_CENTRE_HUMANOID = frozenset({"neck_yaw", "neck_pitch", "waist_yaw"})
_CORE: dict[Family, frozenset[str]] = {
    "humanoid": frozenset({"shoulder_pitch", "hip_roll"}),
    "L6": frozenset(s for limb in LIMBS["L6"].values() for s in limb),
    "L4T": frozenset(s for limb in LIMBS["L4T"].values() for s in limb),
    "L4N": frozenset(s for limb in LIMBS["L4N"].values() for s in limb),
    "L4R": frozenset({"front_yaw", "rear_yaw", "rear_wheel"}),  # L4R2A3: arms, no front wheel
    "L4D": frozenset(s for limb in LIMBS["L4D"].values() for s in limb),
    "R4LL": frozenset(s for limb in LIMBS["R4LL"].values() for s in limb),
}
_CENTRE_LEGGED: dict[Family, tuple[tuple[str, str | None, str], ...]] = {
    # (part, axis, slot) in order: a second match takes the next free slot of the same part
    "L4T": (("neck", "yaw", "neck_yaw"), ("neck", "pitch", "neck_pitch"),
            ("neck", None, "neck_yaw"), ("neck", None, "neck_pitch")),
    "L4R": (("neck", "yaw", "neck_yaw"), ("neck", "pitch", "neck_pitch"),
            ("neck", None, "neck_yaw"), ("neck", None, "neck_pitch")),
    "L4N": (("neck", "yaw", "neck_yaw"), ("neck", "pitch", "neck_pitch"),
            ("neck", "pitch", "neck_pitch2"), ("neck", "pitch", "neck_pitch3"),
            ("neck", None, "neck_yaw"), ("gripper", None, "gripper"), ("jaw", None, "gripper")),
    "L4D": (("neck", None, "neck_pitch"), ("jaw", None, "jaw"), ("gripper", None, "jaw")),
}  # fmt: skip


# sided servos named without a limb position: (part, axis, slot)
_SIDED_LEGGED: dict[Family, tuple[tuple[str, str | None, str], ...]] = {
    "L4R": (("shoulder", "roll", "arm_roll"), ("elbow", None, "arm_elbow"),
            ("wrist", None, "arm_elbow"), ("gripper", None, "gripper"),
            ("hip", None, "rear_yaw")),
}  # fmt: skip
# the body part that names the limb whatever position word the name carries: the L4R's front
# limbs hang from its shoulders (前肩), its rear ones from its crotch (股間); Kondo's KXR-L4R
# projects name the right rear yaw 右前股間 ("right front crotch") next to 左足股間
_LIMB_OF_PART: dict[Family, dict[str, str]] = {"L4R": {"hip": "rear", "shoulder": "front"}}


@dataclass
class Placement:
    """Where each servo went: full joint name -> ICS number, and what found no joint."""

    family: Family
    joints: dict[str, int] = field(default_factory=dict)
    unplaced: list[tuple[int, str]] = field(default_factory=list)  # (index, why)
    side_conflicts: list[int] = field(default_factory=list)  # names saying the other side

    @property
    def bases(self) -> set[str]:
        return {j[2:] if j[:2] in ("l_", "r_") else j for j in self.joints}

    @property
    def fits(self) -> bool:
        """Every named servo found a joint and the family's core joints are all there."""
        return not self.unplaced and _CORE[self.family] <= self.bases


def _side_prefix(p: Placement, role: Role, index: int) -> str:
    """The kit's wiring decides the side: even ICS numbers (SIO1-4) are the robot's right in
    every KXR build (KXR-KITS.md §1.2). A name that says the other side is noted: Kondo's own
    KXR-L4T project names its even servos 左 (left), yet its walks go forward and its turns
    the named way only with even = right (docs/robots.md, measured)."""
    right = index % 2 == 0
    if role.side != "centre" and (role.side == "right") != right:
        p.side_conflicts.append(index)
    return "r_" if right else "l_"


def _humanoid_slot(role: Role) -> str | None:
    part, axis = role.part, role.axis
    if part == "shoulder":
        return f"shoulder_{axis or 'pitch'}"
    if part == "arm" and axis is not None:  # 腕ヨー: the upper arm's yaw, at the shoulder
        return f"shoulder_{axis}"
    if part == "elbow":
        return "elbow_yaw" if axis == "yaw" else "elbow_pitch"
    if part == "wrist":
        return f"wrist_{axis or 'pitch'}"
    if part == "gripper":
        return "gripper"
    if part == "hip" or (part == "leg" and axis is not None and role.position is None):
        return f"hip_{axis or 'pitch'}"
    if part == "knee":
        return "knee_pitch"
    if part == "ankle":
        return f"ankle_{axis or 'pitch'}"
    if part == "wheel":
        return {"front": "front_wheel", "rear": "rear_wheel"}.get(
            role.position or "", "ankle_wheel"
        )
    if part == "neck" and axis != "roll":
        return f"neck_{axis or 'yaw'}"
    if part == "waist":
        return "waist_yaw"
    return None


def _place(p: Placement, joint: str, index: int, name: str) -> None:
    if joint in p.joints:
        p.unplaced.append((index, f"{name}: {joint} is already servo {p.joints[joint]}"))
    else:
        p.joints[joint] = index


def _humanoid(roles: Mapping[int, tuple[str, Role]]) -> Placement:
    p = Placement("humanoid")
    for index, (name, role) in sorted(roles.items()):
        slot = _humanoid_slot(role)
        if slot is None or role.position == "middle":
            p.unplaced.append((index, f"{name}: no humanoid joint"))
            continue
        joint = slot if slot in _CENTRE_HUMANOID else _side_prefix(p, role, index) + slot
        _place(p, joint, index, name)
    if not p.bases & {"hip_roll", "hip_pitch", "knee_pitch", "ankle_pitch"}:
        # the short (2-axis) legs: a yaw and one roll, which Kondo's projects name the ankle's
        # (右足首（ロール） on 16/17); kxreus calls it the crotch roll (KXR-KITS.md §1.4)
        for side in ("l_", "r_"):
            if side + "ankle_roll" in p.joints:
                p.joints[side + "hip_roll"] = p.joints.pop(side + "ankle_roll")
    return p


def _legged(family: Family, roles: Mapping[int, tuple[str, Role]], wheel_tips: bool) -> Placement:
    p = Placement(family)
    limbs = LIMBS[family]
    groups: dict[tuple[str, str], list[tuple[int, str, Role]]] = {}
    centre = list(_CENTRE_LEGGED.get(family, ()))
    for index, (name, role) in sorted(roles.items()):
        limb_of = _LIMB_OF_PART.get(family, {}).get(role.part)
        if limb_of is not None and role.position is not None:
            role = replace(role, position=limb_of)  # type: ignore[arg-type]
        if role.position is None and role.side != "centre":
            extra = next(
                (c for c in _SIDED_LEGGED.get(family, ()) if c[0] == role.part
                 and c[1] in (None, role.axis)),
                None,
            )  # fmt: skip
            if extra is not None:
                _place(p, _side_prefix(p, role, index) + extra[2], index, name)
                continue
        if role.position is None:
            match = next(
                (c for c in centre if c[0] == role.part and c[1] in (None, role.axis)
                 and c[2] not in p.joints),
                None,
            )  # fmt: skip
            if match is None:
                p.unplaced.append((index, f"{name}: no {family} joint"))
            else:
                p.joints[match[2]] = index
            continue
        if role.position not in limbs:
            p.unplaced.append((index, f"{name}: a {family} has no {role.position} limbs"))
            continue
        groups.setdefault((_side_prefix(p, role, index), role.position), []).append(
            (index, name, role)
        )
    for (prefix, position), members in groups.items():
        slots = list(limbs[position])
        free = list(slots)
        moving = [s for s in slots if not s.endswith("_wheel")]
        pending: list[tuple[int, str]] = []
        for index, name, role in members:
            want: str | None = None
            if role.part == "wheel":
                want = next((s for s in slots if s.endswith("_wheel")), None)
            elif role.segment == "root":
                want = moving[0]
            elif role.segment == "tip":  # a wheel after one joint is the tip (L4R: 後足先端)
                wheeled = wheel_tips and len(moving) == 1 and slots[-1].endswith("_wheel")
                want = slots[-1] if wheeled else moving[-1]
            elif role.segment == "mid" and len(moving) >= 3:
                want = moving[1]
            elif role.part in ("knee", "ankle"):
                want = f"{position}_{role.part}" if f"{position}_{role.part}" in slots else None
            elif role.axis is not None:
                want = next((s for s in moving if s.endswith("_" + role.axis)), None)
            if want is None or want not in free:
                pending.append((index, name))
                continue
            free.remove(want)
            _place(p, prefix + want, index, name)
        for index, name in pending:  # the rest by ICS number, root to tip
            rest = [s for s in free if not s.endswith("_wheel")]
            if not rest:
                p.unplaced.append((index, f"{name}: the {position} limb has no joint left"))
                continue
            free.remove(rest[0])
            _place(p, prefix + rest[0], index, name)
    return p


def map_roles(
    family: Family, roles: Mapping[int, tuple[str, Role]], *, wheel_tips: bool = False
) -> Placement:
    """Place the servos ``roles`` (index -> (name, role)) on the frame of ``family``.
    ``wheel_tips``: the title names the family, so the tip (先) of a limb of one joint and a
    wheel (the L4R's) is its wheel; without it, a leg's tip is never taken for a wheel."""
    return _humanoid(roles) if family == "humanoid" else _legged(family, roles, wheel_tips)
