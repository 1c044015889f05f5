"""Static balance and servo load of one pose: does it stand, and how hard does each servo work?

For joint angles the robot is set on flat ground (:func:`ground_frame`), the geometry within
:data:`CONTACT_TOL` of the lowest point is what touches the floor (soles, knees, hands, the
back), the support polygon is the convex hull of those points, and the centre of mass's
projection is measured against it: ``margin_m`` is its distance to the nearest edge, positive
inside (balanced), negative outside (the pose tips over). A line or point contact has no
inside: its margin is minus the distance to it. ``balanced`` asks for a small reserve
(:data:`STABILITY_RESERVE_M`), measured against physics.

Static torque: gravity on every link and the floor's vertical reaction at each touching link,
taken about each joint's axis (the Jacobian-transpose sum), as a fraction of its servo's
stall torque. With several touching links the reaction is split by the minimum-norm solution
of the force and moment balance (one documented choice among the statically indeterminate
splits; two feet under a centred CoM share the weight equally).

How the robot is set on the ground (a documented approximation, no dynamics): when a foot is
the lowest part in the torso's frame, the ground is that foot's sole (the feet's sole normals
averaged when both are down with soles parallel within :data:`PARALLEL_SOLES_DEG`): so a pose
leant by the ankles leans the whole robot. Otherwise (kneeling, sitting, lying) the ground is
horizontal in the torso frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from rcb4hv.errors import RobotLookupError
from rcb4hv.robot.geometry import Stance, convex_hull, geom_points, signed_margin
from rcb4hv.robot.ik import effectors, solve_linear
from rcb4hv.robot.kinematics import (
    IDENTITY,
    Transform,
    apply,
    compose,
    forward,
    rotation_about,
)
from rcb4hv.robot.model import RobotModel, Vec3
from rcb4hv.robot.servos import DEFAULT_SERVO, stiffness

__all__ = [
    "CONTACT_TOL",
    "GRAVITY",
    "MAX_TIP_DEG",
    "PARALLEL_SOLES_DEG",
    "STABILITY_RESERVE_M",
    "PoseBalance",
    "SetDown",
    "floor_forces",
    "ground_frame",
    "placed",
    "pose_balance",
    "rigid_balance",
    "set_down",
    "signed_margin",
]

#: Standard gravity (m/s², the CGPM's conventional value).
GRAVITY = 9.80665
#: Geometry within this height (m) of the lowest point touches the floor: a sole tilted by
#: 1° across a 5 cm foot lifts its far edge by < 1 mm, so a nearly flat sole stays a plane
#: contact, while a foot lifted for a step (≥ several mm) does not. A documented choice.
CONTACT_TOL = 0.002
#: A pose whose robot must tip further than this (degrees) over an edge before something
#: else touches the floor does not stand still: it topples, or lands with a jolt; a pose
#: settling a few degrees onto its other foot stands. A documented choice.
MAX_TIP_DEG = 10.0
#: How far inside the support the CoM must be for ``balanced``. Measured with
#: bench/balance_vs_physics.py: physics holds a pose leant at the ankles with 5.4 mm or more
#: of (compliant) static margin and topples it with 5.3 mm or less (KHR-3HV forward and
#: backward, KXR-L2 and KXR-L2 with grippers forward): MuJoCo's soft contact lets the loaded
#: edge of a sole sink, as a real sole's rubber and the frame's flex do. 6 mm rounds it up.
STABILITY_RESERVE_M = 0.006
#: Fixed-point iterations of the servos' sag under load (each a rigid balance); the sag of
#: a standing pose changes by well under 0.1° after the third.
COMPLIANCE_ITERATIONS = 4
#: Soles within this angle count as parallel (both on the floor).
PARALLEL_SOLES_DEG = 5.0

Point2 = tuple[float, float]


@dataclass(frozen=True)
class PoseBalance:
    """One pose's static balance (ground frame: z up, floor at z = 0, the root above the
    origin) and servo loads."""

    com: Vec3
    support: tuple[Point2, ...]  # the support polygon, counter-clockwise
    contacts: tuple[str, ...]  # the links touching the floor
    margin_m: float
    torque: dict[str, float] = field(default_factory=dict)  # N·m the servo must hold
    torque_ratio: dict[str, float] = field(default_factory=dict)  # |torque| / stall torque
    ground: Transform | None = None  # the root link's pose in the ground frame
    tipped_deg: float = 0.0  # how far the robot tipped over an edge before it settled

    @property
    def balanced(self) -> bool:
        """The pose stands still: its CoM at least :data:`STABILITY_RESERVE_M` inside."""
        return self.margin_m > STABILITY_RESERVE_M

    @property
    def margin_text(self) -> str:
        """The margin in words, true on either side of the reserve: "stands: centre of mass
        12 mm inside the support", "at the edge: centre of mass only 5 mm inside the support;
        standing still takes 6 mm" or "cannot stand still: centre of mass 3 mm outside the
        support". The one wording of the editor's line and of ``project check --balance``."""
        mm = self.margin_m * 1000
        if self.balanced:
            return f"stands: centre of mass {mm:.0f} mm inside the support"
        if self.margin_m >= 0:
            return (
                f"at the edge: centre of mass only {mm:.0f} mm inside the support; standing "
                f"still takes {STABILITY_RESERVE_M * 1000:.0f} mm"
            )
        return f"cannot stand still: centre of mass {-mm:.0f} mm outside the support"

    @property
    def overloaded(self) -> list[str]:
        """Joints whose static load exceeds the servo's stall torque."""
        return sorted(j for j, r in self.torque_ratio.items() if r > 1.0)

    def to_dict(self) -> dict[str, object]:
        return {
            "balanced": self.balanced,
            "margin_m": round(self.margin_m, 5),
            "com": [round(c, 5) for c in self.com],
            "support": [[round(x, 5), round(y, 5)] for x, y in self.support],
            "contacts": list(self.contacts),
            "tipped_deg": round(self.tipped_deg, 2),
            "torque_ratio": {j: round(r, 4) for j, r in sorted(self.torque_ratio.items())},
            "torque_nm": {j: round(t, 5) for j, t in sorted(self.torque.items())},
        }


def _rotation_to_up(up: Vec3) -> Transform:
    """The smallest rotation taking unit vector ``up`` to +z (Rodrigues)."""
    x, y, z = up
    s = math.hypot(x, y)
    if s < 1e-12:
        return IDENTITY if z > 0 else rotation_about((1.0, 0.0, 0.0), math.pi)
    return rotation_about((y, -x, 0.0), math.atan2(s, z))  # about up × z


def _points(model: RobotModel, frames: Mapping[str, Transform]) -> dict[str, list[Vec3]]:
    """Every link's shape corners (:func:`rcb4hv.robot.geometry.geom_points`) in the root's
    frame."""
    return {
        link.name: [p for g in link.geoms for p in geom_points(g, frames[link.name])]
        for link in model.links
    }


def ground_frame(
    model: RobotModel,
    frames: Mapping[str, Transform],
    points: Mapping[str, list[Vec3]] | None = None,
    feet: Sequence[str] | None = None,
) -> Transform:
    """The transform from the root's frame to the ground frame (module docstring): up is
    the down-touching sole's normal, or the root's z; the lowest point at z = 0.

    ``points`` (default: every link's shape corners in the root's frame) and ``feet``
    (default: the model's feet) may be given when the caller has them: a caller that only
    stands the robot on its feet passes just the feet's points, and saves the rest."""
    points = _points(model, frames) if points is None else points
    lowest = {name: min(p[2] for p in pts) for name, pts in points.items() if pts}
    if feet is None:
        feet = [n for n, kind in effectors(model).items() if kind == "foot"]
    feet = [n for n in feet if n in lowest]
    up: Vec3 = (0.0, 0.0, 1.0)
    if feet and lowest:
        bottom = min(lowest.values())
        down = sorted(feet, key=lambda n: lowest[n])
        if lowest[down[0]] <= bottom + CONTACT_TOL:
            normals = [_column(frames[down[0]], 2)]
            for other in down[1:]:
                n2 = _column(frames[other], 2)
                parallel = sum(a * b for a, b in zip(normals[0], n2, strict=True))
                if parallel >= math.cos(math.radians(PARALLEL_SOLES_DEG)):
                    normals.append(n2)
            sx, sy, sz = (sum(n[k] for n in normals) for k in range(3))
            norm = math.sqrt(sx * sx + sy * sy + sz * sz)
            up = (sx / norm, sy / norm, sz / norm)
    rot = _rotation_to_up(up)
    floor = min(apply(rot, p)[2] for pts in points.values() for p in pts)
    return (
        (rot[0][0], rot[0][1], rot[0][2], 0.0),
        (rot[1][0], rot[1][1], rot[1][2], 0.0),
        (rot[2][0], rot[2][1], rot[2][2], -floor),
        (0.0, 0.0, 0.0, 1.0),
    )


def _column(t: Transform, k: int) -> Vec3:
    return (t[0][k], t[1][k], t[2][k])


def floor_forces(weight: float, com: Vec3, at: Sequence[Vec3]) -> list[float]:
    """Vertical floor forces at points ``at`` carrying ``weight`` (N) at ``com``: the
    minimum-norm solution of the force and moment balance (a ridge pseudo-inverse), points
    that would pull (negative force: the floor cannot) dropped and the rest solved again; a
    CoM outside the support leaves the moment unbalanced (least squares)."""
    active = list(range(len(at)))
    f = [0.0] * len(at)
    for _ in range(len(at)):
        rows = [
            [1.0] * len(active),
            [at[k][0] - com[0] for k in active],
            [at[k][1] - com[1] for k in active],
        ]
        aat = [[sum(x * y for x, y in zip(rows[r], rows[c], strict=True))
                + (1e-9 if r == c else 0.0) for c in range(3)] for r in range(3)]  # fmt: skip
        y = solve_linear(aat, [weight, 0.0, 0.0])
        f = [0.0] * len(at)
        for i, k in enumerate(active):
            f[k] = sum(rows[r][i] * y[r] for r in range(3))
        pulling = [k for k in active if f[k] < 0.0]
        if not pulling:
            break
        active = [k for k in active if f[k] > 0.0]
        if not active:
            return [weight / len(at)] * len(at)
    return [max(0.0, x) for x in f]


def _mean(points: Sequence[Vec3]) -> Vec3:
    n = len(points)
    return (
        sum(p[0] for p in points) / n,
        sum(p[1] for p in points) / n,
        sum(p[2] for p in points) / n,
    )


def _contacts(
    points: Mapping[str, Sequence[Vec3]], ground: Transform
) -> tuple[dict[str, list[Vec3]], list[tuple[Vec3, str]]]:
    """The points (ground frame) within :data:`CONTACT_TOL` of the floor, by link, and every
    point with its link."""
    touching: dict[str, list[Vec3]] = {}
    every: list[tuple[Vec3, str]] = []
    for name, pts in points.items():
        for p in pts:
            q = apply(ground, p)
            every.append((q, name))
            if q[2] <= CONTACT_TOL:
                touching.setdefault(name, []).append(q)
    return touching, every


def _tip_axis(support: Sequence[Point2], c: Point2) -> tuple[Point2, Point2] | None:
    """The edge the robot tips over when its CoM ``c`` lies outside ``support``: a point on
    it and the axis's horizontal unit direction (right-handed: tipping by a positive angle
    lowers the side the CoM is on). None when there is no side to tip to."""
    if not support:
        return None
    if len(support) == 1:
        a = support[0]
        nx, ny = c[0] - a[0], c[1] - a[1]
        n = math.hypot(nx, ny)
        return None if n < 1e-12 else (a, (-ny / n, nx / n))  # z × outward
    n = len(support)
    edges = [(support[i], support[(i + 1) % n]) for i in range(n if n > 2 else 1)]

    def side(e: tuple[Point2, Point2]) -> float:  # < 0: c is right of a -> b (outside)
        (ax, ay), (bx, by) = e
        length = math.hypot(bx - ax, by - ay) or 1.0
        return ((bx - ax) * (c[1] - ay) - (by - ay) * (c[0] - ax)) / length

    a, b = min(edges, key=side)
    ux, uy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(ux, uy)
    if length < 1e-12 or abs(side((a, b))) < 1e-12:
        return None
    sign = 1.0 if side((a, b)) < 0 else -1.0  # a segment: tip to the CoM's side
    return a, (sign * ux / length, sign * uy / length)


def _tip(every: Sequence[tuple[Vec3, str]], pivot: Point2, axis: Point2) -> float | None:
    """The angle (rad) the robot turns about ``axis`` through ``pivot`` until another point
    touches the floor; None when nothing would."""
    nx, ny = axis[1], -axis[0]  # outward: axis × z
    best: float | None = None
    for p, _ in every:
        d = (p[0] - pivot[0]) * nx + (p[1] - pivot[1]) * ny
        if d > 1e-6 and p[2] > CONTACT_TOL:
            angle = math.atan2(p[2], d)
            best = angle if best is None else min(best, angle)
    return best


def _turned(ground: Transform, pivot: Point2, axis: Point2, angle: float) -> Transform:
    """``ground`` turned by ``angle`` about the horizontal ``axis`` through ``pivot``."""
    move = (
        (1.0, 0.0, 0.0, pivot[0]),
        (0.0, 1.0, 0.0, pivot[1]),
        (0.0, 0.0, 1.0, 0.0),
        (0.0, 0.0, 0.0, 1.0),
    )
    back = (
        (1.0, 0.0, 0.0, -pivot[0]),
        (0.0, 1.0, 0.0, -pivot[1]),
        (0.0, 0.0, 1.0, 0.0),
        (0.0, 0.0, 0.0, 1.0),
    )
    turn = rotation_about((axis[0], axis[1], 0.0), angle)
    return compose(move, compose(turn, compose(back, ground)))


def pose_balance(
    model: RobotModel,
    angles: Mapping[str, float],
    *,
    compliant: bool = True,
    stretch: int | None = None,
) -> PoseBalance:
    """Balance and static servo loads of ``model`` holding joint ``angles`` (rad by name).

    ``compliant``: the servos give under load as the physics' servos do (a position gain,
    :func:`rcb4hv.robot.servos.stiffness` at ``stretch``, default the board's), so each joint
    sags by its static torque over that gain; the sagged pose is found by fixed-point
    iteration (:data:`COMPLIANCE_ITERATIONS`). ``compliant=False``: the joints are rigid.
    """
    target = {j.name: 0.0 for j in model.joints}
    unknown = sorted(set(angles) - set(target))
    if unknown:  # a typo would be balanced as the zero pose of that joint, in silence
        raise RobotLookupError(
            f"{model.name} has no joint {', '.join(unknown)} (its joints: "
            f"{', '.join(sorted(target))})"
        )
    target.update(angles)
    result = rigid_balance(model, target)
    if not compliant:
        return result
    gains = {s.joint: stiffness(s.servo or DEFAULT_SERVO, stretch) for s in model.servos}
    for _ in range(COMPLIANCE_ITERATIONS):
        sagged = dict(target)
        for joint, kp in gains.items():
            sagged[joint] = target[joint] - result.torque[joint] / kp
        result = rigid_balance(model, sagged)
    return result


@dataclass(frozen=True)
class SetDown:
    """A pose set down on the floor (:func:`set_down`): the root's transform to the ground
    frame, the points touching the floor (ground frame, by link), every point with its link,
    the centre of mass (ground frame), the support polygon, the CoM's margin inside it and
    how far (rad) the robot tipped before it settled."""

    ground: Transform
    touching: dict[str, list[Vec3]]
    every: list[tuple[Vec3, str]]
    com: Vec3
    support: tuple[Point2, ...]
    margin: float
    tipped: float


def set_down(
    model: RobotModel,
    frames: Mapping[str, Transform],
    com_root: Vec3,
    points: Mapping[str, list[Vec3]] | None = None,
    feet: Sequence[str] | None = None,
) -> SetDown:
    """Set the robot down (:func:`ground_frame`), then, while its centre of mass (``com_root``,
    root frame) lies outside the support, tip it over the nearest edge until something else
    touches, as a rigid body settles (see :func:`rigid_balance`). ``points`` and ``feet`` as
    for :func:`ground_frame` (a caller standing the robot on its feet passes theirs)."""
    points = _points(model, frames) if points is None else points
    ground = ground_frame(model, frames, points, feet)
    tipped = 0.0
    first: float | None = None
    while True:
        touching, every = _contacts(points, ground)
        com = apply(ground, com_root)
        support = tuple(convex_hull([(p[0], p[1]) for pts in touching.values() for p in pts]))
        margin = signed_margin(support, (com[0], com[1]))
        first = margin if first is None else first
        if margin > 0.0:
            break
        edge = _tip_axis(support, (com[0], com[1]))
        angle = None if edge is None else _tip(every, *edge)
        if edge is None or angle is None or tipped + angle > math.radians(MAX_TIP_DEG):
            margin = min(margin, first)
            break
        tipped += angle
        ground = _turned(ground, edge[0], edge[1], angle)
    return SetDown(ground, touching, every, com, support, margin, tipped)


def rigid_balance(
    model: RobotModel, angles: Mapping[str, float], feet: Sequence[str] | None = None
) -> PoseBalance:
    """Balance and static servo loads of ``model`` at joint ``angles`` (rad by name), the
    joints rigid.

    The robot is set down (:func:`ground_frame`); while its centre of mass lies outside the
    support it tips over the nearest edge until something else touches, as a rigid body
    settles: a pose that settles within :data:`MAX_TIP_DEG` of tipping stands (its margin is
    the settled one), one that needs more, or has nothing to tip onto, does not (its margin
    is the one before tipping). ``feet``: the soles it stands on (default the model's feet,
    :func:`ground_frame`)."""
    frames = forward(model, angles)
    total = model.mass
    com_root = [0.0, 0.0, 0.0]
    for link in model.links:
        c = apply(frames[link.name], link.inertial.com)
        for k in range(3):
            com_root[k] += link.inertial.mass * c[k] / total
    down = set_down(model, frames, (com_root[0], com_root[1], com_root[2]), feet=feet)
    ground, touching, com, support = down.ground, down.touching, down.com, down.support
    margin, tipped = down.margin, down.tipped
    world = {name: compose(ground, t) for name, t in frames.items()}
    link_com = {lk.name: apply(world[lk.name], lk.inertial.com) for lk in model.links}
    names = sorted(touching)
    flat = [(n, p) for n in names for p in touching[n]]
    push = floor_forces(total * GRAVITY, com, [p for _, p in flat])
    loads: dict[str, list[tuple[Vec3, float]]] = {}
    for (n, p), f in zip(flat, push, strict=True):
        loads.setdefault(n, []).append((p, f))
    torque, ratio = _joint_torques(model, world, link_com, loads)
    return PoseBalance(
        com, support, tuple(names), margin, torque, ratio, ground, math.degrees(tipped)
    )


def placed(
    model: RobotModel, angles: Mapping[str, float], feet: Sequence[str] | None = None
) -> Stance:
    """Joint ``angles`` (rad by name; missing joints at 0) placed on the floor as
    :func:`rigid_balance` sets the robot down: the link transforms in the ground frame, the
    centre of mass and the support polygon (the 3D view draws these; its mark is over the
    support exactly when the balance margin is positive)."""
    full = {j.name: 0.0 for j in model.joints}
    full.update(angles)
    b = rigid_balance(model, full, feet)
    assert b.ground is not None
    frames = {name: compose(b.ground, t) for name, t in forward(model, full).items()}
    return Stance(frames, b.com, list(b.support))


def _joint_torques(
    model: RobotModel,
    world: Mapping[str, Transform],
    link_com: Mapping[str, Vec3],
    loads: Mapping[str, Sequence[tuple[Vec3, float]]],
) -> tuple[dict[str, float], dict[str, float]]:
    """The torque each joint's servo holds: the moment about its axis of the gravity and
    floor forces acting on the part of the robot beyond it (its child subtree)."""
    children: dict[str, list[str]] = {}
    for j in model.joints:
        children.setdefault(j.parent, []).append(j.child)
    mass = {link.name: link.inertial.mass for link in model.links}
    torque: dict[str, float] = {}
    ratio: dict[str, float] = {}
    for j in model.joints:
        subtree, stack = [], [j.child]
        while stack:
            name = stack.pop()
            subtree.append(name)
            stack.extend(children.get(name, []))
        t = world[j.child]
        origin = (t[0][3], t[1][3], t[2][3])
        x, y, z = j.axis
        n = math.sqrt(x * x + y * y + z * z) or 1.0
        axis = tuple((t[r][0] * x + t[r][1] * y + t[r][2] * z) / n for r in range(3))
        moment = [0.0, 0.0, 0.0]
        for name in subtree:
            forces_here = [(link_com[name], (0.0, 0.0, -mass[name] * GRAVITY))]
            forces_here += [(p, (0.0, 0.0, f)) for p, f in loads.get(name, ())]
            for p, f in forces_here:
                r = (p[0] - origin[0], p[1] - origin[1], p[2] - origin[2])
                moment[0] += r[1] * f[2] - r[2] * f[1]
                moment[1] += r[2] * f[0] - r[0] * f[2]
                moment[2] += r[0] * f[1] - r[1] * f[0]
        held = -sum(a * m for a, m in zip(axis, moment, strict=True))
        torque[j.name] = held
        servo = model.servo_for_joint(j.name)
        if servo is not None and servo.servo is not None:
            ratio[j.name] = abs(held) / servo.servo.stall_torque
    return torque, ratio
