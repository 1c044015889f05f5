"""Mass properties of the primitive shapes a model is drawn and collided with.

Solid, uniform density; the formulas are the standard moments of inertia about the shape's
centre of mass, in its own frame (a cylinder's axis is its local z, as in URDF and MJCF).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.model import Geom, Inertial, Vec3

__all__ = [
    "box_inertia",
    "combine",
    "cylinder_inertia",
    "geom_inertia",
    "solid",
    "solid_many",
    "sphere_inertia",
    "volume",
]

Inertia = tuple[float, float, float, float, float, float]
_QUARTER = math.pi / 2.0  # a cylinder turned onto the x or y axis


def box_inertia(mass: float, size: Vec3) -> Inertia:
    """A solid box of full extents ``size`` (x, y, z): ``I_xx = m (y² + z²) / 12`` etc."""
    x, y, z = size
    k = mass / 12.0
    return (k * (y * y + z * z), k * (x * x + z * z), k * (x * x + y * y), 0.0, 0.0, 0.0)


def cylinder_inertia(mass: float, radius: float, length: float) -> Inertia:
    """A solid cylinder along z: ``I_zz = m r² / 2``, ``I_xx = I_yy = m (3 r² + l²) / 12``."""
    side = mass * (3.0 * radius * radius + length * length) / 12.0
    return (side, side, mass * radius * radius / 2.0, 0.0, 0.0, 0.0)


def sphere_inertia(mass: float, radius: float) -> Inertia:
    """A solid sphere: ``I = 2 m r² / 5`` about every axis."""
    i = 0.4 * mass * radius * radius
    return (i, i, i, 0.0, 0.0, 0.0)


def geom_inertia(mass: float, geom: Geom) -> Inertia:
    """The inertia of ``geom`` filled with ``mass``, about its centre, in the geom's own
    frame. Geoms of the built-in models are axis-aligned with their link (``rpy`` only turns
    a cylinder onto the link's x or y axis, which permutes the diagonal)."""
    if mass <= 0.0:
        raise RobotModelError(f"a link's mass must be positive, not {mass}")
    if geom.shape == "box":
        return box_inertia(mass, geom.size)
    if geom.shape == "cylinder":
        ixx, iyy, izz, *_ = cylinder_inertia(mass, geom.size[0], geom.size[1])
        roll, pitch, _yaw = geom.rpy
        if abs(abs(pitch) - _QUARTER) < 1e-9:  # axis turned onto x
            return (izz, iyy, ixx, 0.0, 0.0, 0.0)
        if abs(abs(roll) - _QUARTER) < 1e-9:  # axis turned onto y
            return (ixx, izz, iyy, 0.0, 0.0, 0.0)
        return (ixx, iyy, izz, 0.0, 0.0, 0.0)
    return sphere_inertia(mass, geom.size[0])


def solid(mass: float, geom: Geom) -> Inertial:
    """An :class:`Inertial` for ``mass`` spread uniformly through ``geom`` (centre of mass at
    the geom's centre)."""
    return Inertial(mass=mass, com=geom.pos, inertia=geom_inertia(mass, geom))


def volume(geom: Geom) -> float:
    """The volume of ``geom`` (m³)."""
    if geom.shape == "box":
        return geom.size[0] * geom.size[1] * geom.size[2]
    if geom.shape == "cylinder":
        return math.pi * geom.size[0] ** 2 * geom.size[1]
    return 4.0 / 3.0 * math.pi * geom.size[0] ** 3


def combine(parts: Sequence[Inertial]) -> Inertial:
    """The mass properties of rigidly joined ``parts`` (all in one frame): total mass, the
    common centre of mass, and the inertia about it by the parallel-axis theorem."""
    mass = sum(p.mass for p in parts)
    com = tuple(sum(p.mass * p.com[k] for p in parts) / mass for k in range(3))
    acc = [0.0] * 6
    for p in parts:
        m = p.mass
        dx, dy, dz = (p.com[0] - com[0], p.com[1] - com[1], p.com[2] - com[2])
        shift = (
            m * (dy * dy + dz * dz),
            m * (dx * dx + dz * dz),
            m * (dx * dx + dy * dy),
            -m * dx * dy,
            -m * dx * dz,
            -m * dy * dz,
        )
        for k in range(6):
            acc[k] += p.inertia[k] + shift[k]
    return Inertial(
        mass=mass,
        com=(com[0], com[1], com[2]),
        inertia=(acc[0], acc[1], acc[2], acc[3], acc[4], acc[5]),
    )


def solid_many(mass: float, geoms: Sequence[Geom]) -> Inertial:
    """An :class:`Inertial` for ``mass`` spread over several shapes at one density (each
    shape gets mass in proportion to its volume)."""
    if not geoms:
        raise RobotModelError("a link with mass needs at least one shape")
    total = sum(volume(g) for g in geoms)
    return combine([solid(mass * volume(g) / total, g) for g in geoms])
