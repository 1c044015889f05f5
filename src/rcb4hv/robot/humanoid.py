"""Build a mirror-symmetric humanoid :class:`RobotModel` from its left half.

The built-in robots are described once, for the left side (+y) and the centre line; the right
side is the mirror image through the x-z plane: positions and centres of mass negate y, pitch
axes stay, roll and yaw axes stay too (so their limits mirror to ``[-upper, -lower]``), and a
gripper's axis flips (so equal grip angles close both hands alike). The joint map is data of
each robot (index and sign per joint name).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.model import (
    Geom,
    Inertial,
    Joint,
    JointKind,
    Link,
    RobotModel,
    ServoJoint,
    ServoSpec,
    Vec3,
)
from rcb4hv.robot.shapes import solid_many, volume

__all__ = ["LimbJoint", "build_humanoid", "distribute_mass", "mirror_geom"]

LEFT, RIGHT = "l_", "r_"


@dataclass(frozen=True, slots=True)
class LimbJoint:
    """One joint and its child link, as data.

    ``name``/``link``: base names ("knee", "shin"); a limb joint becomes ``l_knee`` and
    ``r_knee`` with links ``l_shin``/``r_shin``, a ``centre`` joint keeps its name.
    ``parent``: a centre link's name, or the base name of a link of the same limb.
    ``xyz``: the joint's origin in the parent frame (left side), metres. ``lower``/``upper``:
    the left joint's limits, radians. ``geoms``: the child link's shapes (left side);
    ``mass``: the child link's mass, kg, spread uniformly through ``geoms``; ``com``, when
    given, is the link's measured centre of mass (m, left side, link frame), which replaces
    the boxes' centroid (their inertia about it is kept unless ``inertia`` gives the moments
    about it, kg·m², link axes). ``advisory``: the left joint's
    advisory range (radians; warn outside it, see :class:`~rcb4hv.robot.model.Joint`), None
    for the hard range.
    """

    name: str
    link: str
    parent: str
    xyz: Vec3
    axis: Vec3
    kind: JointKind
    lower: float
    upper: float
    geoms: tuple[Geom, ...]
    mass: float
    centre: bool = False
    com: Vec3 | None = None
    advisory: tuple[float, float] | None = None
    inertia: Vec3 | None = None


def mirror_geom(g: Geom) -> Geom:
    """The mirror image of ``g`` through the x-z plane."""
    return replace(g, pos=(g.pos[0], -g.pos[1], g.pos[2]), rpy=(-g.rpy[0], g.rpy[1], -g.rpy[2]))


def _mirror_inertial(i: Inertial) -> Inertial:
    ixx, iyy, izz, ixy, ixz, iyz = i.inertia
    return Inertial(i.mass, (i.com[0], -i.com[1], i.com[2]), (ixx, iyy, izz, -ixy, ixz, -iyz))


def _inertial(spec: LimbJoint) -> Inertial:
    """The left link's inertial: its mass spread through its shapes, with the measured centre
    of mass and moments where ``spec`` gives them."""
    inertial = solid_many(spec.mass, spec.geoms)
    if spec.com is not None:
        inertial = replace(inertial, com=spec.com)
    if spec.inertia is not None:
        inertial = replace(inertial, inertia=(*spec.inertia, 0.0, 0.0, 0.0))
    return inertial


def _side_joint(spec: LimbJoint, prefix: str, centre_links: set[str]) -> tuple[Joint, Link]:
    parent = spec.parent if spec.parent in centre_links else prefix + spec.parent
    geoms = spec.geoms
    inertial = _inertial(spec)
    x, y, z = spec.xyz
    axis, lower, upper, advisory = spec.axis, spec.lower, spec.upper, spec.advisory
    side: str = "left"
    other = RIGHT + spec.name
    if prefix == RIGHT:
        side, other = "right", LEFT + spec.name
        y = -y
        geoms = tuple(mirror_geom(g) for g in geoms)
        inertial = _mirror_inertial(inertial)
        if spec.kind in ("roll", "yaw"):
            lower, upper = -upper, -lower
            if advisory is not None:
                advisory = (-advisory[1], -advisory[0])
        elif spec.kind == "grip":
            axis = (-axis[0], -axis[1], -axis[2])
    joint = Joint(
        name=prefix + spec.name,
        parent=parent,
        child=prefix + spec.link,
        xyz=(x, y, z),
        rpy=(0.0, 0.0, 0.0),
        axis=axis,
        lower=lower,
        upper=upper,
        kind=spec.kind,
        side="left" if side == "left" else "right",
        mirror=other,
        advisory=advisory,
    )
    return joint, Link(prefix + spec.link, inertial, geoms)


def build_humanoid(
    *,
    name: str,
    title: str,
    root: Link,
    joints: Sequence[LimbJoint],
    servo_map: Mapping[str, tuple[int, int]],
    servo: ServoSpec,
    sources: Mapping[str, str],
    home: Mapping[str, float] | None = None,
) -> RobotModel:
    """A :class:`RobotModel` from the left half ``joints`` (parents before children) and the
    joint map ``servo_map`` (full joint name -> (servo index, sign))."""
    links: list[Link] = [root]
    out: list[Joint] = []
    centre_links = {root.name}
    for spec in joints:
        if spec.centre:
            out.append(
                Joint(
                    name=spec.name,
                    parent=spec.parent,
                    child=spec.link,
                    xyz=spec.xyz,
                    rpy=(0.0, 0.0, 0.0),
                    axis=spec.axis,
                    lower=spec.lower,
                    upper=spec.upper,
                    kind=spec.kind,
                    advisory=spec.advisory,
                )
            )
            links.append(Link(spec.link, _inertial(spec), spec.geoms))
            centre_links.add(spec.link)
            continue
        for prefix in (LEFT, RIGHT):
            joint, link = _side_joint(spec, prefix, centre_links)
            out.append(joint)
            links.append(link)
    servos = tuple(
        ServoJoint(index=index, joint=joint, sign=sign, servo=servo)
        for joint, (index, sign) in sorted(servo_map.items(), key=lambda kv: kv[1][0])
    )
    return RobotModel(
        name=name,
        title=title,
        root=root.name,
        links=tuple(links),
        joints=tuple(out),
        servos=servos,
        sources=dict(sources),
        home=dict(home or {}),
    )


def distribute_mass(
    total: float,
    servo_mass: float,
    parts: Mapping[str, tuple[int, int, Sequence[Geom]]],
) -> dict[str, float]:
    """Split a robot's ``total`` mass over its links. ``parts`` maps a (base) link name to
    (copies, servo cases it carries, shapes): a limb link has 2 copies, a centre link 1. Each
    link carries its servo cases (× ``servo_mass``); the rest of the robot (frames, board,
    battery, wiring) is shared in proportion to the links' shape volumes. Returns the mass
    of one copy of each link."""
    carried = sum(n * servos for n, servos, _ in parts.values()) * servo_mass
    rest = total - carried
    if rest <= 0.0:
        raise RobotModelError(f"the servos ({carried:.3f} kg) outweigh the robot ({total:.3f} kg)")
    vols = {link: sum(volume(g) for g in geoms) for link, (_, _, geoms) in parts.items()}
    whole = sum(parts[link][0] * v for link, v in vols.items())
    return {
        link: servos * servo_mass + rest * vols[link] / whole
        for link, (_, servos, _) in parts.items()
    }
