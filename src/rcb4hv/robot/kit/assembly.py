"""Assemble a :class:`RobotModel` from a kit template: joint slots placed in the zero pose.

A template lists every joint a family's frame can carry (a *slot*): its parent slot, the
joint's position in the robot frame at the zero pose (mm, left side), its axis, kind and
limits, and the shapes of the part it moves (boxes in the robot frame). A project uses a
subset of the slots (its servo names say which); a slot without a servo is rigid, so its
shapes join its parent's link. All joints have identity rotation at the zero pose (KXR
frames are built square), so a joint's origin is its position minus its parent's.

Masses: where kxreus weighs each link of the build (``figures.link_figures``), each link
takes its mass and centre of mass from there. Otherwise the build's own whole-robot mass
where kxreus gives one, else the family's (``figures.MASS_SERVOS`` build) plus or minus one
servo per servo more or fewer, spread as :func:`rcb4hv.robot.humanoid.distribute_mass`
does: each link carries its servo case, the rest is shared by shape volume; a humanoid's
torso and leg links first take their figures from the weighed build with the same legs, its
arm links from the one with the same arm (``figures.torso_contents``,
``figures.weighed_legs``, ``figures.weighed_arms``): the same parts weigh the same in every
build. kxreus weighs
every servo case at 27.73 g, a KRS-3301's (``servo.mass_kxreus``; KXR-KITS.md §3.1), so such
a total counts each servo of its build short of a KRS-3304R2 (``servo.mass``): the
difference is added per servo (a weighed build's links get it per case they carry).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.humanoid import LimbJoint, build_humanoid, distribute_mass
from rcb4hv.robot.kit.figures import MASS_SERVOS, LinkFigure, case_shortfall, fig, vec
from rcb4hv.robot.model import Geom, JointKind, Link, RobotModel, ServoSpec, Vec3
from rcb4hv.robot.servos import KRS_3304R2
from rcb4hv.robot.shapes import solid_many

__all__ = ["Slot", "Template", "assemble", "box", "cylinder_x", "cylinder_y", "segment"]

MM = 0.001
_DARK, _LIGHT = (0.2, 0.2, 0.22, 1.0), (0.9, 0.9, 0.92, 1.0)
_TYRE = (0.1, 0.1, 0.1, 1.0)


def box(size: Vec3, centre: Vec3, light: bool = False) -> Geom:
    """A box (mm, robot frame at the zero pose)."""
    return Geom("box", size, centre, rgba=_LIGHT if light else _DARK)


def cylinder_y(radius: float, width: float, centre: Vec3) -> Geom:
    """A wheel: a cylinder with its axis along y (mm, robot frame)."""
    return Geom("cylinder", (radius, width, 0.0), centre, rpy=(math.pi / 2, 0.0, 0.0), rgba=_TYRE)


def cylinder_x(radius: float, width: float, centre: Vec3) -> Geom:
    """A wheel: a cylinder with its axis along x (mm, robot frame)."""
    return Geom("cylinder", (radius, width, 0.0), centre, rpy=(0.0, math.pi / 2, 0.0), rgba=_TYRE)


def segment(a: Vec3, b: Vec3, thick: float = 26.0, light: bool = False) -> Geom:
    """A box of ``thick`` square section joining ``a`` and ``b`` along their main axis."""
    size = [thick, thick, thick]
    k = max(range(3), key=lambda i: abs(b[i] - a[i]))
    size[k] = max(abs(b[k] - a[k]), thick)
    centre = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2)
    return box((size[0], size[1], size[2]), centre, light)


def sole(ankle: Vec3) -> tuple[Geom, ...]:
    """A KXR biped's foot at ``ankle`` (mm): the stepped sole plate and the block above it."""
    x0, y0, z0 = ankle
    top, thick = fig("l2.sole_top"), fig("l2.sole") - fig("l2.sole_top")
    steps = tuple(
        box((2 * x, y2 - y1, thick), (x0, y0 + (y1 + y2) / 2, z0 - top - thick / 2), True)
        for x, y1, y2 in (vec(f"l2.sole_step{k}") for k in (1, 2, 3))
    )
    return (*steps, box((38.0, 27.0, top), (x0, y0, z0 - top / 2)))


@dataclass(frozen=True)
class Slot:
    """One joint a frame can carry (left side, or ``centre``)."""

    name: str
    parent: str | None  # a slot name, or None for the torso
    pos: Vec3  # mm, robot frame, zero pose
    axis: Vec3
    kind: JointKind
    limits: tuple[float, float]  # degrees, left joint
    geoms: tuple[Geom, ...]  # mm, robot frame
    centre: bool = False
    #: an accessory (wheel, gripper finger, arm on a wheeled body) that is not there when its
    #: servo is not: its shapes are dropped instead of joining the parent's link
    optional: bool = False
    #: a joint no servo drives (a free-rolling wheel), there when the slot named here is (the
    #: L4R2A3G's free wheels come with its grippers); it carries no servo case
    passive_with: str | None = None

    @property
    def passive(self) -> bool:
        return self.passive_with is not None


@dataclass(frozen=True)
class Template:
    """A family's frame: the torso's shapes and every slot, parents before children."""

    family: str
    torso: tuple[Geom, ...]
    slots: tuple[Slot, ...]

    def slot(self, name: str) -> Slot:
        for s in self.slots:
            if s.name == name:
                return s
        raise KeyError(name)


def _local(g: Geom, origin: Vec3) -> Geom:
    """``g`` (mm, robot frame) in metres relative to ``origin`` (mm)."""
    size = g.size if g.shape != "cylinder" else (g.size[0], g.size[1], 0.0)
    return replace(
        g,
        size=(size[0] * MM, size[1] * MM, size[2] * MM),
        pos=tuple((g.pos[k] - origin[k]) * MM for k in range(3)),  # type: ignore[arg-type]
    )


def assemble(
    template: Template,
    present: Sequence[str],
    joint_map: Mapping[str, tuple[int, int]],
    *,
    name: str,
    title: str,
    sources: Mapping[str, str],
    home: Mapping[str, float] | None = None,
    servo: ServoSpec = KRS_3304R2,
    total_mass: float | None = None,
    link_masses: Mapping[str, LinkFigure] | None = None,
    borrowed: Mapping[str, LinkFigure] | None = None,
) -> RobotModel:
    """The model of ``template`` with the slots ``present`` (base names); ``joint_map``: full
    joint name (``l_knee_pitch``, ``neck_yaw``) -> (servo index, sign); ``total_mass`` (kg):
    the build's own whole-robot mass when a source gives it (else the family's, see the
    module docstring); ``link_masses``: slot (``torso`` for the body) -> what a source gives
    of that link (mass, centre of mass, moments of inertia): those links take them, the
    others share what is left of the total; ``borrowed``: slot -> the figures of the same
    part in another build, for a build the source does not weigh link by link (its total,
    and so the case correction, stay this build's)."""
    by_name = {s.name: s for s in template.slots}
    unknown = [p for p in present if p not in by_name]
    if unknown:
        raise RobotModelError(f"{template.family}: no such joint in this frame: {unknown}")
    keep = set(present)
    keep |= {s.name for s in template.slots if s.passive_with in keep}

    def owner(slot: str | None) -> str | None:
        """The nearest present slot at or above ``slot`` (None: the torso)."""
        while slot is not None and slot not in keep:
            slot = by_name[slot].parent
        return slot

    shapes: dict[str | None, list[Geom]] = {None: list(template.torso)}
    dropped: set[str] = set()
    for s in template.slots:
        if s.name not in keep and (s.optional or (s.parent in dropped)):
            dropped.add(s.name)
            continue
        shapes.setdefault(owner(s.name), []).extend(s.geoms)
    for s in template.slots:  # a joint whose part is its servo alone (cross joints)
        if s.name in keep and not shapes.get(s.name):
            shapes[s.name] = [box((26.0, 26.0, 26.0), s.pos)]
    origin: dict[str | None, Vec3] = {None: (0.0, 0.0, 0.0)}
    origin.update({s.name: s.pos for s in template.slots})
    links = {k: tuple(_local(g, origin[k]) for g in v) for k, v in shapes.items()}
    # masses: the family's total, a servo more or less per servo beyond its reference build
    sided = sum(1 if by_name[p].centre else 2 for p in keep if not by_name[p].passive)
    per_servo = fig("mass.per_servo") * MM
    short = case_shortfall() * MM  # per servo case in kxreus's totals
    if total_mass is not None:  # this build's own total (a weighed build's cases: per link)
        total = total_mass + (0.0 if link_masses else sided * short)
    else:
        ref = MASS_SERVOS[template.family]
        total = fig(f"mass.{template.family}") * MM + ref * short + (sided - ref) * per_servo
    parts = {
        (k or "torso"): (
            1 if k is None or by_name[k].centre else 2,
            0 if k is None or by_name[k].passive else 1,
            g,
        )
        for k, g in links.items()
        if g
    }
    known = {**(borrowed or {}), **(link_masses or {})}
    masses = _masses(total, per_servo, parts, known)
    given = {k: f for k, f in known.items() if k in parts}
    com = {k: _scaled(f.com, MM) for k, f in given.items() if f.com is not None}
    inertia = {k: _scaled(f.inertia, 1e-7) for k, f in given.items() if f.inertia is not None}
    joints: list[LimbJoint] = []
    for s in template.slots:
        if s.name not in keep:
            continue
        par = owner(s.parent)
        rel = tuple((s.pos[k] - origin[par][k]) * MM for k in range(3))
        geoms = links[s.name]
        joints.append(
            LimbJoint(
                name=s.name,
                link=s.name + "_link",
                parent="torso" if par is None else (par + "_link"),
                xyz=(rel[0], rel[1], rel[2]),
                axis=s.axis,
                kind=s.kind,
                lower=math.radians(s.limits[0]),
                upper=math.radians(s.limits[1]),
                geoms=geoms,
                mass=masses[s.name],
                centre=s.centre,
                com=com.get(s.name),
                inertia=inertia.get(s.name),
            )
        )
    body = solid_many(masses["torso"], links[None])
    if "torso" in com:
        body = replace(body, com=com["torso"])
    if "torso" in inertia:
        body = replace(body, inertia=(*inertia["torso"], 0.0, 0.0, 0.0))
    root = Link("torso", body, links[None])
    return build_humanoid(
        name=name,
        title=title,
        root=root,
        joints=joints,
        servo_map=joint_map,
        servo=servo,
        sources=sources,
        home=home,
    )


def _masses(
    total: float,
    per_servo: float,
    parts: Mapping[str, tuple[int, int, Sequence[Geom]]],
    given: Mapping[str, LinkFigure],
) -> dict[str, float]:
    """One copy's mass (kg) of each part: the source's figure where ``given`` has one, the
    rest of ``total`` shared by servo and volume over the others (all given: their sum)."""
    fixed = {k: given[k].mass * MM for k in parts if k in given}
    free = {k: v for k, v in parts.items() if k not in fixed}
    if not free:
        return fixed
    rest = total - sum(parts[k][0] * m for k, m in fixed.items())
    if given and rest <= per_servo * sum(n * servos for n, servos, _ in free.values()):
        # parts the weighed build lacks (a kxra6g's base wheels): each its servo, a wheel
        # its tyre too
        tyre = fig("wheel.tyre_mass") * MM
        return fixed | {
            k: servos * per_servo + (tyre if k.endswith("wheel") else 0.0)
            for k, (_, servos, _) in free.items()
        }
    return distribute_mass(rest, per_servo, free) | fixed


def _scaled(v: Vec3, k: float) -> Vec3:
    return (v[0] * k, v[1] * k, v[2] * k)
