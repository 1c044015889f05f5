"""Forward kinematics and the centre of mass of a :class:`~rcb4hv.robot.model.RobotModel`.

Pure Python 4x4 homogeneous transforms (row-major tuples), so the 3D view, mirroring and the
lint need no NumPy. A robot has about 20 joints, so this costs microseconds per pose.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable, Mapping, Sequence

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.model import Joint, RobotModel, Vec3, chain

__all__ = [
    "IDENTITY",
    "Transform",
    "apply",
    "center_of_mass",
    "compose",
    "forward",
    "from_xyz_rpy",
    "invert",
    "joints_to",
    "link_pose",
    "position",
    "require_link",
    "rotation_about",
    "translation",
]

Transform = tuple[
    tuple[float, float, float, float],
    tuple[float, float, float, float],
    tuple[float, float, float, float],
    tuple[float, float, float, float],
]

IDENTITY: Transform = (
    (1.0, 0.0, 0.0, 0.0),
    (0.0, 1.0, 0.0, 0.0),
    (0.0, 0.0, 1.0, 0.0),
    (0.0, 0.0, 0.0, 1.0),
)


def compose(a: Transform, b: Transform) -> Transform:
    """The transform ``a @ b``."""
    rows = []
    for i in range(4):
        ai = a[i]
        rows.append(
            (
                ai[0] * b[0][0] + ai[1] * b[1][0] + ai[2] * b[2][0] + ai[3] * b[3][0],
                ai[0] * b[0][1] + ai[1] * b[1][1] + ai[2] * b[2][1] + ai[3] * b[3][1],
                ai[0] * b[0][2] + ai[1] * b[1][2] + ai[2] * b[2][2] + ai[3] * b[3][2],
                ai[0] * b[0][3] + ai[1] * b[1][3] + ai[2] * b[2][3] + ai[3] * b[3][3],
            )
        )
    return (rows[0], rows[1], rows[2], rows[3])


def from_xyz_rpy(xyz: Vec3, rpy: Vec3) -> Transform:
    """URDF origin: translation ``xyz`` and fixed-axis roll, pitch, yaw (Rz @ Ry @ Rx)."""
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = (
        math.cos(r),
        math.sin(r),
        math.cos(p),
        math.sin(p),
        math.cos(y),
        math.sin(y),
    )
    return (
        (cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, xyz[0]),
        (sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr, xyz[1]),
        (-sp, cp * sr, cp * cr, xyz[2]),
        (0.0, 0.0, 0.0, 1.0),
    )


@functools.lru_cache(maxsize=4096)
def _origin(xyz: Vec3, rpy: Vec3) -> Transform:
    """A joint's fixed origin (:func:`from_xyz_rpy`), worked out once per model joint: forward
    kinematics runs every output period in a simulation."""
    return from_xyz_rpy(xyz, rpy)


def rotation_about(axis: Vec3, angle: float) -> Transform:
    """Rotation by ``angle`` about the unit vector ``axis`` (Rodrigues)."""
    x, y, z = axis
    n = math.sqrt(x * x + y * y + z * z) or 1.0
    x, y, z = x / n, y / n, z / n
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return (
        (t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.0),
        (t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0),
        (t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0),
        (0.0, 0.0, 0.0, 1.0),
    )


def apply(t: Transform, p: Vec3) -> Vec3:
    """Point ``p`` moved by ``t``."""
    return (
        t[0][0] * p[0] + t[0][1] * p[1] + t[0][2] * p[2] + t[0][3],
        t[1][0] * p[0] + t[1][1] * p[1] + t[1][2] * p[2] + t[1][3],
        t[2][0] * p[0] + t[2][1] * p[1] + t[2][2] * p[2] + t[2][3],
    )


def invert(t: Transform) -> Transform:
    """The inverse of the rigid transform ``t`` (rotation transposed, translation undone)."""
    r = ((t[0][0], t[1][0], t[2][0]), (t[0][1], t[1][1], t[2][1]), (t[0][2], t[1][2], t[2][2]))
    p = (t[0][3], t[1][3], t[2][3])
    back = [-(r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2]) for i in range(3)]
    return (
        (r[0][0], r[0][1], r[0][2], back[0]),
        (r[1][0], r[1][1], r[1][2], back[1]),
        (r[2][0], r[2][1], r[2][2], back[2]),
        (0.0, 0.0, 0.0, 1.0),
    )


def translation(p: Vec3) -> Transform:
    """A pure translation by ``p``."""
    return (
        (1.0, 0.0, 0.0, p[0]),
        (0.0, 1.0, 0.0, p[1]),
        (0.0, 0.0, 1.0, p[2]),
        (0.0, 0.0, 0.0, 1.0),
    )


def position(t: Transform) -> Vec3:
    """The translation part of ``t``."""
    return (t[0][3], t[1][3], t[2][3])


def forward(
    model: RobotModel,
    angles: Mapping[str, float],
    base: Transform = IDENTITY,
    joints: Sequence[Joint] | None = None,
) -> dict[str, Transform]:
    """World transform of every link for joint ``angles`` (radians by joint name; missing
    joints are at 0), with the root link at ``base``. ``joints``: only these, parent-first
    (:func:`joints_to`), for a caller that needs a few links many times."""
    out: dict[str, Transform] = {model.root: base}
    for j in chain(model.joints, model.root) if joints is None else joints:
        origin = compose(out[j.parent], _origin(j.xyz, j.rpy))
        out[j.child] = compose(origin, rotation_about(j.axis, angles.get(j.name, 0.0)))
    return out


def joints_to(model: RobotModel, links: Iterable[str]) -> tuple[Joint, ...]:
    """The joints between the root and ``links``, parent-first: what :func:`forward` needs to
    place those links."""
    by_child = {j.child: j for j in model.joints}
    needed: set[str] = set()
    for link in links:
        while link in by_child and link not in needed:
            needed.add(link)
            link = by_child[link].parent
    return tuple(j for j in chain(model.joints, model.root) if j.child in needed)


def link_pose(
    model: RobotModel, link: str, angles: Mapping[str, float], base: Transform = IDENTITY
) -> Transform:
    """Forward kinematics of one link: its transform in the frame of ``base`` (default the
    root link's frame, e.g. the torso) for joint ``angles``; :class:`RobotModelError` for a
    link the model lacks."""
    require_link(model, link)
    return forward(model, angles, base)[link]


def require_link(model: RobotModel, link: str) -> None:
    """Raise :class:`RobotModelError` naming the model's links when it has no ``link``."""
    names = [lk.name for lk in model.links]
    if link not in names:
        raise RobotModelError(f"{model.name} has no link {link!r}; its links: {', '.join(names)}")


def center_of_mass(model: RobotModel, frames: Mapping[str, Transform]) -> Vec3:
    """The whole robot's centre of mass (world frame) for link transforms ``frames``."""
    total = 0.0
    acc = [0.0, 0.0, 0.0]
    for link in model.links:
        m = link.inertial.mass
        p = apply(frames[link.name], link.inertial.com)
        total += m
        for k in range(3):
            acc[k] += m * p[k]
    if total <= 0.0:
        raise ValueError(f"{model.name}: the model has no mass")
    return (acc[0] / total, acc[1] / total, acc[2] / total)
