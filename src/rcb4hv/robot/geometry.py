"""Geometry of a robot model: rotations, the points and lowest point of its shapes, convex
hulls, and where a pose stands (pure Python, no NumPy; the one place for these questions).

* Rotations: :func:`quaternion_matrix` (a unit quaternion w, x, y, z, as MuJoCo's free joint
  and ``TrackPoint`` record it) and :func:`pose_transform` (position + quaternion: the
  transform a base pose gives :func:`~rcb4hv.robot.kinematics.forward`).
* Shapes: a shape is its kind, centre, rotation and half extents (:func:`half_extents` of a
  :class:`~rcb4hv.robot.model.Geom`: a cylinder's are radius, radius, half length along its
  local z). :func:`box_corners` gives the 8 corners of its bounding box (to draw it),
  :func:`lowest_z` its exact lowest point (to put it on the floor), :func:`geom_points` the
  points a support polygon is made of.
* :func:`convex_hull` and :func:`inside`: the support polygon and the test of the centre of
  mass over it.
* Stance: where a pose stands.

  - Feet: the model's leaf links whose lowest geom point, in the zero pose (every joint at
    0), lies within :data:`CONTACT_TOLERANCE_M` of the robot's lowest point (a humanoid's
    soles).
  - Without a measured base pose (the plain simulator, the live board) the robot stands on
    its feet: the body is tilted (about a horizontal axis) so that the feet's mean sole normal
    is vertical, as a robot standing on flat ground has its soles flat, and lowered so that
    the lowest foot point is on the ground (z = 0); x, y and yaw stay at 0. A bow then leans
    the body forward over flat feet instead of tipping the feet onto their heels.
  - The support polygon is the convex hull, on the ground plane, of the geom points within
    :data:`CONTACT_TOLERANCE_M` of the ground; the centre of mass is over it or not.

  Points (:func:`geom_points`): a box's 8 corners; a cylinder's two rims as inscribed
  octagons (each point is on the rim; a straight side lies at most r(1 - cos 22.5°) = 7.6 % of
  the radius inside it); a sphere's lowest point and its 4 horizontal extremes.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache

from rcb4hv.robot.kinematics import (
    IDENTITY,
    Transform,
    apply,
    center_of_mass,
    compose,
    forward,
    from_xyz_rpy,
    rotation_about,
)
from rcb4hv.robot.model import Geom, GeomShape, RobotModel, Vec3

__all__ = [
    "CONTACT_TOLERANCE_M",
    "Matrix3",
    "Quaternion",
    "Soles",
    "Stance",
    "box_corners",
    "convex_hull",
    "feet",
    "geom_lowest_z",
    "geom_points",
    "half_extents",
    "inside",
    "lowest_z",
    "pose_transform",
    "quaternion_matrix",
    "rotation_of",
    "signed_margin",
    "stance",
]

Quaternion = tuple[float, float, float, float]
"""A unit quaternion (w, x, y, z)."""
Matrix3 = tuple[Vec3, Vec3, Vec3]
"""A rotation matrix, rows."""


# ------------------------------------------------------------------------------ rotations


def quaternion_matrix(q: Quaternion) -> Matrix3:
    """The rotation matrix of the unit quaternion ``q`` = (w, x, y, z)."""
    w, x, y, z = q
    return (
        (1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)),
        (2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)),
        (2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)),
    )


def pose_transform(position: Vec3, q: Quaternion) -> Transform:
    """The transform of a body at ``position`` turned by the unit quaternion ``q``."""
    r = quaternion_matrix(q)
    return (
        (*r[0], position[0]),
        (*r[1], position[1]),
        (*r[2], position[2]),
        (0.0, 0.0, 0.0, 1.0),
    )


def rotation_of(t: Transform) -> Matrix3:
    """The rotation part of ``t``."""
    return ((t[0][0], t[0][1], t[0][2]), (t[1][0], t[1][1], t[1][2]), (t[2][0], t[2][1], t[2][2]))


# --------------------------------------------------------------------------------- shapes


def half_extents(geom: Geom) -> Vec3:
    """The half extents of ``geom`` along its own axes: a box's half sizes; a cylinder's
    radius, radius and half length (its axis is its local z); a sphere's radius thrice."""
    a, b, c = geom.size
    if geom.shape == "box":
        return (a / 2, b / 2, c / 2)
    if geom.shape == "cylinder":
        return (a, a, b / 2)
    return (a, a, a)


def box_corners(center: Vec3, rotation: Matrix3, half: Vec3) -> tuple[Vec3, ...]:
    """The 8 corners of the box of ``half`` extents at ``center`` turned by ``rotation`` (of
    a cylinder or sphere: its bounding box in its own axes)."""
    r = rotation
    return tuple(
        (
            center[0] + r[0][0] * a * half[0] + r[0][1] * b * half[1] + r[0][2] * c * half[2],
            center[1] + r[1][0] * a * half[0] + r[1][1] * b * half[1] + r[1][2] * c * half[2],
            center[2] + r[2][0] * a * half[0] + r[2][1] * b * half[1] + r[2][2] * c * half[2],
        )
        for a, b, c in itertools.product((-1, 1), repeat=3)
    )


def lowest_z(shape: GeomShape, center: Vec3, rotation: Matrix3, half: Vec3) -> float:
    """The exact lowest z of a shape (see :func:`half_extents`) at ``center`` turned by
    ``rotation``: a box's lowest corner, a cylinder's lowest rim point (or face), a sphere's
    bottom."""
    up = rotation[2]  # the world z of each of the shape's axes
    if shape == "box":
        return center[2] - abs(up[0]) * half[0] - abs(up[1]) * half[1] - abs(up[2]) * half[2]
    if shape == "cylinder":
        c = abs(up[2])
        return center[2] - c * half[2] - half[0] * math.sqrt(max(0.0, 1.0 - c * c))
    return center[2] - half[0]


def geom_lowest_z(geom: Geom, link: Transform) -> float:
    """The exact lowest z of ``geom`` in the world, its link at ``link``."""
    t = compose(link, from_xyz_rpy(geom.pos, geom.rpy))
    return lowest_z(geom.shape, (t[0][3], t[1][3], t[2][3]), rotation_of(t), half_extents(geom))


# -------------------------------------------------------------------------------- stance

CONTACT_TOLERANCE_M = 0.001
"""A point within 1 mm of the ground touches it. The models' dimensions are published to
0.1-1 mm (docs/robots.md), so a flat sole computed from them is level to well under 1 mm;
anything higher is lifted."""

RIM_POINTS = 8
"""Points on each cylinder rim (an inscribed octagon)."""

Point2 = tuple[float, float]


def _translation(x: float, y: float, z: float) -> Transform:
    return from_xyz_rpy((x, y, z), (0.0, 0.0, 0.0))


@cache
def _corners(geom: Geom) -> tuple[Vec3, ...]:
    """A box's or cylinder's corner points in its link's frame (geoms are immutable)."""
    sx, sy, sz = geom.size
    local: list[Vec3]
    if geom.shape == "box":
        local = [
            (a * sx / 2, b * sy / 2, c * sz / 2) for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)
        ]
    else:  # cylinder: radius sx, length sy along its local z
        local = []
        for k in range(RIM_POINTS):
            phi = 2 * math.pi * k / RIM_POINTS
            local += [(sx * math.cos(phi), sx * math.sin(phi), h) for h in (-sy / 2, sy / 2)]
    t = from_xyz_rpy(geom.pos, geom.rpy)
    return tuple(apply(t, p) for p in local)


def geom_points(geom: Geom, link: Transform) -> list[Vec3]:
    """The corner points of ``geom`` in the world, its link at ``link``."""
    if geom.shape == "sphere":  # the same in every frame: its points are in the world's axes
        r = geom.size[0]
        cx, cy, cz = apply(link, geom.pos)
        ring = [(cx + r, cy, cz), (cx - r, cy, cz), (cx, cy + r, cz), (cx, cy - r, cz)]
        return [(cx, cy, cz - r), *ring]
    return [apply(link, p) for p in _corners(geom)]


def _world_points(
    model: RobotModel, frames: Mapping[str, Transform], links: Iterable[str]
) -> list[Vec3]:
    return [
        p for name in links for g in model.link(name).geoms for p in geom_points(g, frames[name])
    ]


def feet(model: RobotModel) -> tuple[str, ...]:
    """The links the robot stands on (see the module docstring); every geom-carrying leaf link
    if the model has no single lowest group."""
    parents = {j.parent for j in model.joints}
    leaves = [link.name for link in model.links if link.name not in parents and link.geoms]
    frames = forward(model, {})
    low = {name: min(p[2] for p in _world_points(model, frames, [name])) for name in leaves}
    if not low:
        return ()
    bottom = min(low.values())
    return tuple(n for n, z in low.items() if z <= bottom + CONTACT_TOLERANCE_M)


def convex_hull(points: Iterable[Point2]) -> list[Point2]:
    """Counter-clockwise convex hull (Andrew's monotone chain); collinear points dropped."""
    pts = sorted(set(points))
    if len(pts) <= 2:
        return pts

    def cross(o: Point2, a: Point2, b: Point2) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[Point2] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[Point2] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def _segment_distance(p: Point2, a: Point2, b: Point2) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    t = (
        0.0
        if length2 == 0
        else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2))
    )
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)


def signed_margin(polygon: Sequence[Point2], p: Point2) -> float:
    """Distance from ``p`` to the edge of convex ``polygon`` (counter-clockwise): positive
    inside, negative outside; minus the distance for a segment or a point."""
    n = len(polygon)
    if n == 0:
        return -math.inf
    if n < 3:
        return -_segment_distance(p, polygon[0], polygon[-1])
    edges = [(polygon[i], polygon[(i + 1) % n]) for i in range(n)]
    inside = all(
        (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) >= 0 for a, b in edges
    )
    d = min(_segment_distance(p, a, b) for a, b in edges)
    return d if inside else -d


def inside(polygon: Sequence[Point2], p: Point2) -> bool:
    """True if ``p`` lies in the counter-clockwise convex ``polygon`` (edges included)."""
    if len(polygon) < 3:
        return False
    n = len(polygon)
    for i in range(n):
        (ax, ay), (bx, by) = polygon[i], polygon[(i + 1) % n]
        if (bx - ax) * (p[1] - ay) - (by - ay) * (p[0] - ax) < -1e-12:
            return False
    return True


@dataclass(frozen=True)
class Soles:
    """The links a robot stands on and each one's up direction in its own frame (the world's
    z axis in the zero pose: the models stand there with level soles)."""

    links: tuple[str, ...]
    up: tuple[Vec3, ...]

    @classmethod
    def of(cls, model: RobotModel, links: Sequence[str] | None = None) -> Soles:
        """The soles of ``links`` (default :func:`feet`)."""
        names = tuple(links if links is not None else feet(model))
        zero = forward(model, {})
        # R0^T z: the third row of the zero-pose rotation
        return cls(names, tuple((zero[n][2][0], zero[n][2][1], zero[n][2][2]) for n in names))

    def levelling(self, frames: Mapping[str, Transform]) -> Transform:
        """The rotation (about a horizontal axis) that makes the soles' mean normal vertical."""
        n = [0.0, 0.0, 0.0]
        for name, (ux, uy, uz) in zip(self.links, self.up, strict=True):
            r = frames[name]
            for k in range(3):
                n[k] += r[k][0] * ux + r[k][1] * uy + r[k][2] * uz
        norm = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
        if norm == 0.0:
            return IDENTITY
        nx, ny, nz = n[0] / norm, n[1] / norm, n[2] / norm
        # n x z = (ny, -nx, 0); the angle between n and z
        return rotation_about((ny, -nx, 0.0), math.atan2(math.hypot(nx, ny), nz))


@dataclass(frozen=True)
class Stance:
    """One pose, placed in the world: link transforms, centre of mass, support polygon."""

    frames: dict[str, Transform]
    com: Vec3
    support: list[Point2]

    @property
    def com_inside(self) -> bool:
        """The centre of mass is over the support polygon (statically stable)."""
        return inside(self.support, (self.com[0], self.com[1]))


def stance(
    model: RobotModel,
    angles: Mapping[str, float],
    base: Transform | None = None,
    soles: Soles | None = None,
) -> Stance:
    """Place ``angles`` in the world: at ``base`` if given (a simulated base pose), else on
    the ground: the body tilted so the ``soles`` (default :meth:`Soles.of` the model) are
    level on average, and lowered so their lowest point is at z = 0. Pass ``soles`` when
    placing many poses of one model: it is worked out once."""
    if base is None:
        soles = soles if soles is not None else Soles.of(model)
        frames = forward(model, angles)
        tilt = soles.levelling(frames)
        below = soles.links or [link.name for link in model.links]
        row = tilt[2]  # the tilted height of a point p is row . p
        low = min(
            (
                row[0] * p[0] + row[1] * p[1] + row[2] * p[2]
                for p in _world_points(model, frames, below)
            ),
            default=0.0,
        )
        placed = compose(_translation(0.0, 0.0, -low), tilt)
        frames = {name: compose(placed, t) for name, t in frames.items()}
    else:
        frames = forward(model, angles, base)
    pts = _world_points(model, frames, [link.name for link in model.links])
    touching = [(p[0], p[1]) for p in pts if p[2] <= CONTACT_TOLERANCE_M]
    return Stance(frames, center_of_mass(model, frames), convex_hull(touching))
