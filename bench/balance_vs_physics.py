"""How well static balance (rcb4hv.robot.balance) predicts physics: every pose of a project
held still in MuJoCo.

Each pose (accumulated as ``rcb4hv project poses`` does) is placed on the floor, its servos
hold it at the stretch the physics uses by default, and it is left for :data:`HOLD_S`
virtual seconds. Physics says it **stands** when the torso has turned less than
:data:`FALLEN_DEG` from where it was set down: the same criterion as static balance's
:data:`~rcb4hv.robot.balance.MAX_TIP_DEG` (a pose that tips a few degrees onto its other foot
stands; one that topples turns much further). The table compares that with
``balanced``. Then a lean sweep: the home pose leant forward at the ankles, 1° a step, gives
the angle where each verdict turns to "falls".

Usage: ``python -m bench.balance_vs_physics [PROJECT.h4p] [--markdown]`` (needs rcb4hv[sim];
the fixture by default; about a minute).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from rcb4hv.hth4 import load_project
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.physics.world import PhysicsWorld
from rcb4hv.project.posebalance import motion_pose_angles
from rcb4hv.robot.balance import MAX_TIP_DEG, pose_balance, signed_margin
from rcb4hv.robot.geometry import convex_hull
from rcb4hv.robot.kinematics import Transform
from rcb4hv.robot.model import RobotModel

FIXTURE = (
    Path(__file__).resolve().parent.parent.parent
    / "shared/fixtures/hth4/kxr-l2-hac/HAC_KXR_HTH4_project.h4p"
)
HOLD_S = 2.0
FALLEN_DEG = MAX_TIP_DEG


def quaternion(t: Transform) -> tuple[float, float, float, float]:
    """(w, x, y, z) of the rotation part of ``t`` (Shepperd's method, the trace branch and
    the largest-diagonal branches)."""
    r = t
    tr = r[0][0] + r[1][1] + r[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return (0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s)
    i = max(range(3), key=lambda k: r[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1.0 + r[i][i] - r[j][j] - r[k][k]) * 2
    q = [0.0, 0.0, 0.0, 0.0]
    q[0] = (r[k][j] - r[j][k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (r[j][i] + r[i][j]) / s
    q[1 + k] = (r[k][i] + r[i][k]) / s
    return (q[0], q[1], q[2], q[3])


def hold(world: PhysicsWorld, angles: dict[str, float]) -> tuple[float, float]:
    """Hold ``angles`` from rest, set down as static balance sets it down (the touching
    soles flat); the torso's turn after settling (deg) and the final physics margin (m) of
    the CoM to the hull of the floor contacts."""
    world.place(angles)
    ground = pose_balance(world.model, angles).ground
    assert ground is not None
    world.d.qpos[3:7] = quaternion(ground)
    mj = world._mj  # the bench sets the pose down the way place() does
    mj.mj_forward(world.m, world.d)
    world.d.qpos[2] -= world.lowest_point()
    mj.mj_forward(world.m, world.d)
    for index, servo in world.servos.items():
        world.drive(index, angles.get(servo.joint, 0.0), world.stiffness(index, None))
    up0 = world.base().up
    world.step(round(HOLD_S / world.timestep))
    up1 = world.base().up
    cos = sum(a * b for a, b in zip(up0, up1, strict=True))
    turn = math.degrees(math.acos(max(-1.0, min(1.0, cos))))
    return turn, physics_margin(world)


def physics_margin(world: PhysicsWorld) -> float:
    d = world.d
    com = d.subtree_com[1]
    points = [(float(d.contact[i].pos[0]), float(d.contact[i].pos[1])) for i in range(d.ncon)]
    return signed_margin(convex_hull(points), (float(com[0]), float(com[1])))


def lean(model: RobotModel, degrees: float) -> dict[str, float]:
    """The home pose leant forward by ``degrees`` at both ankles (the feet stay flat, the
    body turns forward about them)."""
    out = dict(model.home)
    for side in ("l", "r"):
        name = f"{side}_ankle_pitch"
        out[name] = model.home.get(name, 0.0) - math.radians(degrees)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("project", nargs="?", type=Path, default=FIXTURE)
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args(argv)
    project = load_project(args.project)
    model = project_model(project)
    world = PhysicsWorld(model)
    table = {(s, p): 0 for s in (True, False) for p in (True, False)}
    disagree: list[str] = []
    for motion in project.used_motions:
        for i, (_, angles) in enumerate(motion_pose_angles(model, motion)):
            static = pose_balance(model, angles).balanced
            turn, _ = hold(world, angles)
            stands = turn < FALLEN_DEG
            table[(static, stands)] += 1
            if static != stands:
                disagree.append(
                    f"motion {motion.slot} pose {i + 1}: static {static}, physics {turn:.0f}°"
                )
    home = pose_balance(model, model.home)
    _, home_physics = hold(world, dict(model.home))
    static_edge = physics_edge = None
    for deg in range(0, 41):
        angles = lean(model, deg)
        if static_edge is None and not pose_balance(model, angles).balanced:
            static_edge = deg
        if physics_edge is None and hold(world, angles)[0] >= FALLEN_DEG:
            physics_edge = deg
        if static_edge is not None and physics_edge is not None:
            break
    total = sum(table.values())
    agree = table[(True, True)] + table[(False, False)]
    rows = [
        ("static balanced, physics stands", table[(True, True)]),
        ("static balanced, physics falls", table[(True, False)]),
        ("static unbalanced, physics stands", table[(False, True)]),
        ("static unbalanced, physics falls", table[(False, False)]),
        ("agreement", f"{agree}/{total} ({agree / total:.0%})"),
        (
            "home margin: static / physics (mm)",
            f"{home.margin_m * 1e3:.1f} / {home_physics * 1e3:.1f}",
        ),
        (
            "forward lean at the ankles that falls: static / physics (°)",
            f"{static_edge}/{physics_edge}",
        ),
    ]
    if args.markdown:
        print("| | poses |\n|---|---|")
        for k, v in rows:
            print(f"| {k} | {v} |")
    else:
        for k, v in rows:
            print(f"{k:62s} {v}")
    for line in disagree:
        print(line, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
