"""Inverse kinematics of a :class:`~rcb4hv.robot.model.RobotModel`: the one IK of the project.

A limb is the chain of joints from its end link back to the nearest branching link (the
torso, or a KHR-3HV-22's chest for an arm), so moving a hand never turns the waist. The solver
is damped least squares (Levenberg-Marquardt) on the chain's geometric Jacobian, with joint
limits as an active set (a joint at its limit that the step would push further is frozen for
that step) and every angle clamped into the model's limits. Pure Python, like
:mod:`rcb4hv.robot.kinematics`: a 5- or 6-joint leg converges in a few iterations, well under a
millisecond each (docs/posing.md has the measured speed); why not PlaCo is in the same page.

What is solved: the end point's position, and its orientation where the chain has the axes
for it (``orient="auto"``): all three axes for a chain of 6 or more joints, the link's z axis
(a sole kept parallel to the target's) for 5 joints (the KXR leg), position only below that
(a 3-joint arm). A target out of reach is not an error: the solver stops at the nearest pose
it finds (least squares) and says so in :attr:`IKResult.reached`.

The API the gait generator uses (issue 29): :func:`solve_feet` puts both feet at world poses
for a given torso pose, seeded by the previous pose; :func:`solve` is one limb.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Literal

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.kinematics import (
    IDENTITY,
    Transform,
    apply,
    compose,
    forward,
    from_xyz_rpy,
    invert,
    require_link,
    rotation_about,
)
from rcb4hv.robot.model import Joint, RobotModel, Vec3

__all__ = [
    "IKResult",
    "Orient",
    "effector_point",
    "effectors",
    "limb",
    "solve",
    "solve_feet",
    "solve_linear",
]

Orient = Literal["auto", "full", "normal", "none"]

#: Damping (metres) of the least-squares step: small against a limb's ~0.1 m lever arms, so
#: steps near the solution are Gauss-Newton steps, large enough to keep steps bounded at a
#: straight knee (a singular Jacobian). A documented numerical choice, not a physical figure.
DAMPING = 0.005
#: Metres per radian of orientation error: weighs orientation against position in the least
#: squares of an unreachable target (about a limb segment's length).
ROTATION_WEIGHT = 0.05
#: Largest change of one joint per iteration (rad), so a far target is approached, not jumped.
MAX_STEP = 0.3
#: Convergence: position error (m) and orientation error (rad) a solution must reach.
POSITION_TOL = 1e-5
ORIENTATION_TOL = 1e-4
#: A restart is tried while the best result is further than these (m, rad).
GOOD_POSITION = 1e-4
GOOD_ORIENTATION = 1e-3
#: A result counts as reaching the target within these (the issue's 1 mm; 0.5°).
REACHED_POSITION = 1e-3
REACHED_ORIENTATION = math.radians(0.5)


@dataclass(frozen=True)
class IKResult:
    """A solved pose: ``angles`` is the whole pose (every joint the seed named, the chain's
    joints changed). ``reached`` is False when the target is out of reach (or a limit stops
    the chain): the angles are then the nearest pose found, ``position_error`` (m) and
    ``orientation_error`` (rad) say how far it stays, ``at_limits`` names the joints held at a
    limit. ``message`` says it in words."""

    angles: dict[str, float]
    reached: bool
    position_error: float
    orientation_error: float
    iterations: int
    at_limits: tuple[str, ...] = ()

    @property
    def message(self) -> str:
        if self.reached:
            return "reached"
        held = f"; held at a limit: {', '.join(self.at_limits)}" if self.at_limits else ""
        turn = f" and {math.degrees(self.orientation_error):.1f}°" if self.orientation_error else ""
        return (
            f"out of reach: stopped at the nearest pose, {self.position_error * 1000:.1f} mm"
            f"{turn} from the target{held}"
        )


def limb(model: RobotModel, link: str) -> tuple[Joint, ...]:
    """The joints that move ``link`` relative to its limb's base, base first: the chain from
    ``link`` up to the nearest ancestor link with more than one child joint (or the root). A
    gripper's finger or a wheel on a link does not make it a branch: the KXR's ankle wheel
    hangs from the ankle, whose leg goes on to the foot."""
    require_link(model, link)
    by_child = {j.child: j for j in model.joints}
    children: dict[str, int] = {}
    for j in model.joints:
        if j.kind not in ("grip", "wheel"):
            children[j.parent] = children.get(j.parent, 0) + 1
    out: list[Joint] = []
    name = link
    while name in by_child:
        j = by_child[name]
        out.append(j)
        if children.get(j.parent, 0) > 1:
            break
        name = j.parent
    return tuple(reversed(out))


def effectors(model: RobotModel) -> dict[str, Literal["hand", "foot"]]:
    """The hands and feet a user drags: the end links of limbs of at least 3 joints (a
    gripper's finger or a wheel gives way to the link it turns on: the grip or wheel joint
    does not reach; a leg with a wheel behind its ankle ends in its foot). At the zero pose a
    foot lies below the midpoint between the lowest and the highest end link, a hand above
    it."""
    by_child = {j.child: j for j in model.joints}
    turning = {j.child for j in model.joints if j.kind in ("grip", "wheel")}
    parents = {j.parent for j in model.joints if j.child not in turning}
    ends: list[str] = []
    for link in model.links:
        name = link.name
        if name in parents:
            continue
        while name in by_child and by_child[name].kind in ("grip", "wheel"):
            name = by_child[name].parent
        if name not in ends and name not in parents and len(limb(model, name)) >= 3:
            ends.append(name)
    if not ends:
        return {}
    frames = forward(model, {})
    z = {n: frames[n][2][3] for n in ends}
    mid = (min(z.values()) + max(z.values())) / 2.0
    return {n: "foot" if z[n] < mid else "hand" for n in ends}


def effector_point(model: RobotModel, link: str) -> Vec3:
    """The point of ``link`` (its frame) a handle grabs: a foot's origin (the ankle, above
    the sole's centre), a hand's tip (the far face of its shape farthest from the elbow).
    RobotModelError naming the model's links if it has no ``link``."""
    require_link(model, link)
    shapes = model.link(link).geoms
    if effectors(model).get(link) != "hand" or not shapes:
        return (0.0, 0.0, 0.0)
    g = max(shapes, key=lambda s: _norm(s.pos))
    k = max(range(3), key=lambda i: abs(g.pos[i]))
    half = (g.size[0] if g.shape != "box" else g.size[k]) / 2.0
    tip = list(g.pos)
    tip[k] += math.copysign(half, g.pos[k])
    return (tip[0], tip[1], tip[2])


def _dofs(orient: Orient, n: int) -> Literal["full", "normal", "none"]:
    if orient != "auto":
        return orient
    return "full" if n >= 6 else "normal" if n == 5 else "none"


def _cross(a: Sequence[float], b: Sequence[float]) -> Vec3:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _norm(v: Sequence[float]) -> float:
    return math.sqrt(sum(x * x for x in v))


def _col(t: Transform, k: int) -> Vec3:
    return (t[0][k], t[1][k], t[2][k])


def solve_linear(a: list[list[float]], b: list[float]) -> list[float]:
    """``a x = b`` by Gaussian elimination with partial pivoting (``a`` is small, SPD)."""
    n = len(b)
    m = [[*row, b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        piv = m[c][c]
        for r in range(c + 1, n):
            f = m[r][c] / piv
            if f:
                for k in range(c, n + 1):
                    m[r][k] -= f * m[c][k]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x


class _Chain:
    """One limb's joints with their fixed origins, for fast repeated kinematics."""

    def __init__(self, joints: tuple[Joint, ...], point: Vec3) -> None:
        self.joints = joints
        self.origins = [from_xyz_rpy(j.xyz, j.rpy) for j in joints]
        self.point = point

    def frames(
        self, base: Transform, q: Sequence[float]
    ) -> tuple[list[Vec3], list[Vec3], Transform]:
        """World position and axis of each joint, and the end link's transform."""
        t = base
        pos: list[Vec3] = []
        axes: list[Vec3] = []
        for j, origin, a in zip(self.joints, self.origins, q, strict=True):
            t = compose(t, origin)
            pos.append((t[0][3], t[1][3], t[2][3]))
            x, y, z = j.axis
            n = math.sqrt(x * x + y * y + z * z) or 1.0
            axes.append(
                (
                    (t[0][0] * x + t[0][1] * y + t[0][2] * z) / n,
                    (t[1][0] * x + t[1][1] * y + t[1][2] * z) / n,
                    (t[2][0] * x + t[2][1] * y + t[2][2] * z) / n,
                )
            )
            t = compose(t, rotation_about(j.axis, a))
        return pos, axes, t


def _errors(end: Transform, point: Vec3, target: Transform, dofs: str) -> tuple[Vec3, Vec3]:
    """Position error (target - current) and the rotation vector that turns the end link
    toward the target's orientation (only the z axis for ``normal``, none for ``none``)."""
    p = apply(end, point)
    ep = (target[0][3] - p[0], target[1][3] - p[1], target[2][3] - p[2])
    if dofs == "none":
        return ep, (0.0, 0.0, 0.0)
    if dofs == "normal":
        return ep, _cross(_col(end, 2), _col(target, 2))
    acc = [0.0, 0.0, 0.0]
    for k in range(3):
        c = _cross(_col(end, k), _col(target, k))
        for i in range(3):
            acc[i] += 0.5 * c[i]
    return ep, (acc[0], acc[1], acc[2])


def _angle_error(ew: Vec3) -> float:
    return math.asin(min(1.0, _norm(ew)))


def _step(
    cols: list[list[float]], e: list[float], q: list[float], joints: tuple[Joint, ...], lam2: float
) -> list[float]:
    """One damped least-squares step ``J^T (J J^T + lam2 I)^-1 e``, with the joints that sit
    at a limit and would be pushed past it frozen (an active set)."""
    n, rows = len(cols), len(e)
    frozen: set[int] = set()
    dq = [0.0] * n
    for _ in range(n + 1):
        jj = [[sum(cols[k][r] * cols[k][c] for k in range(n) if k not in frozen)
               for c in range(rows)] for r in range(rows)]  # fmt: skip
        for r in range(rows):
            jj[r][r] += lam2
        y = solve_linear(jj, e)
        dq = [0.0 if k in frozen else sum(cols[k][r] * y[r] for r in range(rows)) for k in range(n)]
        push = {
            k
            for k, j in enumerate(joints)
            if k not in frozen
            and ((q[k] <= j.lower + 1e-9 and dq[k] < 0) or (q[k] >= j.upper - 1e-9 and dq[k] > 0))
        }
        if not push:
            break
        frozen |= push
    return dq


def _descend(
    chain: _Chain, base: Transform, target: Transform, q: list[float], dofs: str, max_iter: int
) -> tuple[list[float], float, float, int]:
    """Levenberg-Marquardt from ``q``: a step that lowers the weighted squared error is taken
    and the damping halved, one that does not is refused and the damping raised. Returns
    the angles, the position and orientation errors and the iterations."""
    joints = chain.joints
    n = len(joints)
    rows = 3 if dofs == "none" else 6
    w = ROTATION_WEIGHT
    lam2 = DAMPING * DAMPING
    pos, axes, end = chain.frames(base, q)
    ep, ew = _errors(end, chain.point, target, dofs)
    e = list(ep) + [w * x for x in ew][: rows - 3]
    cost = sum(x * x for x in e)
    it = 0
    while it < max_iter:
        if _norm(ep) < POSITION_TOL and _angle_error(ew) < ORIENTATION_TOL:
            break
        it += 1
        p_end = apply(end, chain.point)
        cols = []
        for k in range(n):
            lin = _cross(
                axes[k], (p_end[0] - pos[k][0], p_end[1] - pos[k][1], p_end[2] - pos[k][2])
            )
            cols.append(list(lin) + [w * a for a in axes[k]][: rows - 3])
        dq = _step(cols, e, q, joints, lam2)
        biggest = max((abs(d) for d in dq), default=0.0)
        if biggest < 1e-10:
            break  # held at the limits: the nearest pose
        scale = MAX_STEP / biggest if biggest > MAX_STEP else 1.0
        q2 = [
            min(j.upper, max(j.lower, a + scale * d)) for j, a, d in zip(joints, q, dq, strict=True)
        ]
        pos2, axes2, end2 = chain.frames(base, q2)
        ep2, ew2 = _errors(end2, chain.point, target, dofs)
        e2 = list(ep2) + [w * x for x in ew2][: rows - 3]
        cost2 = sum(x * x for x in e2)
        if cost2 < cost:
            q, pos, axes, end, ep, ew, e, cost = q2, pos2, axes2, end2, ep2, ew2, e2, cost2
            lam2 = max(lam2 * 0.25, 1e-12)
        else:
            lam2 *= 16.0
            if lam2 > 1.0:
                break  # no step lowers the error: a local minimum
    return q, _norm(ep), _angle_error(ew), it


#: Bases of the restart seeds' Halton sequence, one per joint of a limb (limbs have <= 8).
_HALTON_BASES = (2, 3, 5, 7, 11, 13, 17, 19)


def _halton(index: int, base: int) -> float:
    """The ``index``-th term (from 1) of the van der Corput sequence in ``base``, in (0, 1)."""
    f, r = 1.0, 0.0
    while index > 0:
        f /= base
        r += f * (index % base)
        index //= base
    return r


def _restart_seed(joints: Sequence[Joint], index: int) -> list[float]:
    """The ``index``-th restart seed (from 1): a point of the Halton sequence in the limb's
    joint box. Low-discrepancy: the seeds cover the whole box evenly, so a solution family
    (e.g. a KXR knee bent backward within its frame limits) that fills a small corner of it
    is found within a few restarts, where random seeds leave gaps."""
    if len(joints) > len(_HALTON_BASES):
        raise RobotModelError(f"a limb of {len(joints)} joints is longer than IK supports")
    return [
        j.lower + (j.upper - j.lower) * _halton(index, b)
        for j, b in zip(joints, _HALTON_BASES, strict=False)
    ]


def _as_target(target: Vec3 | Transform, current: Transform) -> Transform:
    if len(target) == 4:
        return target
    x, y, z = target
    r = current
    return (
        (r[0][0], r[0][1], r[0][2], float(x)),
        (r[1][0], r[1][1], r[1][2], float(y)),
        (r[2][0], r[2][1], r[2][2], float(z)),
        (0.0, 0.0, 0.0, 1.0),
    )


_ORIENTS: tuple[str, ...] = ("auto", "full", "normal", "none")


def _check_solve_args(orient: object, restarts: object, max_iter: object) -> None:
    if orient not in _ORIENTS:
        raise RobotModelError(f"orient must be one of {', '.join(_ORIENTS)}, not {orient!r}")
    for name, value, low in (("restarts", restarts, 0), ("max_iter", max_iter, 1)):
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            raise RobotModelError(f"{name} must be an int >= {low}, not {value!r}")


def solve(
    model: RobotModel,
    link: str,
    target: Vec3 | Transform,
    angles: Mapping[str, float] | None = None,
    *,
    point: Vec3 = (0.0, 0.0, 0.0),
    orient: Orient = "auto",
    base: Transform = IDENTITY,
    restarts: int = 24,
    max_iter: int = 100,
) -> IKResult:
    """Move ``link`` so that its ``point`` (link frame; default the link's origin) reaches
    ``target``: a position, or a whole transform, in the frame where the root link is at
    ``base`` (default: the root link's own frame, the torso).

    ``angles`` seeds the solver and gives the joints outside the limb (default: the model's
    home pose). A position target keeps the link's current orientation where the chain can
    (``orient``, see the module docstring). When the seed does not reach, up to ``restarts``
    more seeds are tried (the middle of the limits, then points of a Halton sequence spread
    evenly over the limb's limits: deterministic); the best result is returned.

    A ``restarts`` below 0, a ``max_iter`` below 1 or an unknown ``orient`` raises
    :class:`~rcb4hv.errors.RobotModelError` (a ValueError) naming the argument.
    """
    _check_solve_args(orient, restarts, max_iter)
    seed = {j.name: 0.0 for j in model.joints}
    seed.update(model.home if angles is None else angles)
    joints = limb(model, link)
    if not joints:
        raise RobotModelError(f"{model.name}: link {link!r} has no joint to move it")
    chain = _Chain(joints, point)
    frames = forward(model, seed, base)
    limb_base = frames[joints[0].parent]
    goal = _as_target(target, frames[link])
    strict = len(target) == 4
    dofs = _dofs(orient, len(joints))
    q0 = [min(j.upper, max(j.lower, seed.get(j.name, 0.0))) for j in joints]
    best: tuple[float, list[float], float, float, int] | None = None
    total = 0
    for attempt in range(restarts + 1):
        if attempt == 1:
            q0 = [(j.lower + j.upper) / 2.0 for j in joints]
        elif attempt > 1:
            q0 = _restart_seed(joints, attempt - 1)
        q, ep, ew, it = _descend(chain, limb_base, goal, q0, dofs, max_iter)
        total += it
        if not strict and dofs != "none" and ep > POSITION_TOL * 10:
            # a position target: the position comes first, the orientation is kept only
            # where the chain can keep it along with the position
            q, ep, ew, it = _descend(chain, limb_base, goal, q, "none", max_iter)
            total += it
        ok = ep <= GOOD_POSITION and (ew <= GOOD_ORIENTATION or not strict)
        cost = (0.0 if ok else 1.0) + ep + ROTATION_WEIGHT * ew
        if best is None or cost < best[0]:
            best = (cost, q, ep, ew, it)
        if ok:
            break
    assert best is not None
    _, q, ep, ew, _ = best
    out = dict(seed)
    out.update({j.name: a for j, a in zip(joints, q, strict=True)})
    held = tuple(
        j.name for j, a in zip(joints, q, strict=True) if a <= j.lower + 1e-6 or a >= j.upper - 1e-6
    )
    reached = ep <= REACHED_POSITION and (ew <= REACHED_ORIENTATION or not strict)
    return IKResult(out, reached, ep, ew, total, held if not reached else ())


def solve_feet(
    model: RobotModel,
    feet: Mapping[str, Transform],
    torso: Transform = IDENTITY,
    angles: Mapping[str, float] | None = None,
    *,
    restarts: int = 0,
    max_iter: int = 100,
) -> IKResult:
    """Whole-leg IK for a walk: put each foot link of ``feet`` at its world transform while
    the root link (the torso) is at world transform ``torso``; the other joints keep their
    ``angles`` (the seed; pass the previous pose). Each leg gets position and as much
    orientation as it has joints for (``orient="auto"``). The result's errors are the worst
    leg's; ``reached`` is true when every foot reached its target."""
    pose = dict(model.home) if angles is None else dict(angles)
    inv = invert(torso)
    worst_p = worst_r = 0.0
    reached = True
    held: list[str] = []
    iterations = 0
    for link, world in feet.items():
        r = solve(model, link, compose(inv, world), pose, restarts=restarts, max_iter=max_iter)
        pose = r.angles
        worst_p = max(worst_p, r.position_error)
        worst_r = max(worst_r, r.orientation_error)
        reached = reached and r.reached
        held.extend(r.at_limits)
        iterations += r.iterations
    return IKResult(pose, reached, worst_p, worst_r, iterations, tuple(held))
