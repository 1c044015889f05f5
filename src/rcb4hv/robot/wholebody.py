"""Move one limb while the robot keeps its balance: the standing feet stay where they are, flat,
and the body shifts over them so the centre of mass stays above the middle of the feet.

:func:`solve_balanced` is :func:`rcb4hv.robot.ik.solve` plus that: the target is held fixed in
the world (the ground frame the pose stands in, :func:`rcb4hv.robot.balance.ground_frame`),
the torso is moved horizontally by the CoM's offset from the standing feet's centre, both legs
are solved for their unchanged world poses (:func:`rcb4hv.robot.ik.solve_feet`), the limb
again for its target from the moved torso, and so on: the CoM converges in a few rounds
because the torso carries most of the mass. A KHR-3HV or KXR pose has no torso pose of its
own: the shift is carried by the leg joints.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from rcb4hv.robot.balance import ground_frame
from rcb4hv.robot.ik import IKResult, Orient, effectors, limb, solve, solve_feet
from rcb4hv.robot.kinematics import (
    Transform,
    apply,
    center_of_mass,
    compose,
    forward,
    invert,
    translation,
)
from rcb4hv.robot.model import RobotModel, Vec3

__all__ = ["BALANCE_ROUNDS", "point_in_start_frame", "solve_balanced"]

#: Rounds of "shift the torso, solve the legs and the limb": the CoM's offset shrinks by
#: about the limbs' share of the mass each round (well under a millimetre after four).
BALANCE_ROUNDS = 6


def _drop(
    model: RobotModel,
    world: Mapping[str, Transform],
    feet: Mapping[str, Transform],
    shift: tuple[float, float],
) -> float:
    """How far the torso must sink as it shifts by ``shift`` so that each standing leg keeps
    its hip-to-ankle distance (a straight leg has no length to spare for a level shift)."""
    drop = 0.0
    for foot, at in feet.items():
        hip = world[limb(model, foot)[0].child]
        dx, dy, dz = (hip[k][3] - at[k][3] for k in range(3))
        reach2 = dx * dx + dy * dy + dz * dz
        side2 = (dx + shift[0]) ** 2 + (dy + shift[1]) ** 2
        drop = min(drop, math.sqrt(max(0.0, reach2 - side2)) - dz)
    return drop


def solve_balanced(
    model: RobotModel,
    link: str,
    target: Vec3,
    angles: Mapping[str, float] | None = None,
    *,
    point: Vec3 = (0.0, 0.0, 0.0),
    orient: Orient = "auto",
    rounds: int = BALANCE_ROUNDS,
) -> IKResult:
    """Put ``link``'s ``point`` at ``target`` (torso frame of the pose ``angles``, as
    :func:`~rcb4hv.robot.ik.solve`) with the feet that are not ``link`` kept in place and the
    centre of mass brought over their centre. ``reached`` covers the limb and the feet."""
    pose = {j.name: 0.0 for j in model.joints}
    pose.update(model.home if angles is None else angles)
    frames = forward(model, pose)
    ground = ground_frame(model, frames)  # where the pose stands
    feet = {
        f: compose(ground, frames[f])
        for f, kind in effectors(model).items()
        if kind == "foot" and f != link
    }
    goal = apply(ground, target)  # the target, fixed in the world
    torso = ground
    result = solve(model, link, target, pose, point=point, orient=orient)
    for _ in range(rounds):
        pose = result.angles
        world = forward(model, pose, torso)
        com = center_of_mass(model, world)
        if not feet:
            break
        cx = sum(t[0][3] for t in feet.values()) / len(feet)
        cy = sum(t[1][3] for t in feet.values()) / len(feet)
        shift = (cx - com[0], cy - com[1])
        if math.hypot(*shift) < 1e-5:
            break
        torso = compose(translation((shift[0], shift[1], _drop(model, world, feet, shift))), torso)
        legs = solve_feet(model, feet, torso, pose)
        local = apply(invert(torso), goal)
        result = solve(model, link, local, legs.angles, point=point, orient=orient, restarts=0)
        if not legs.reached:
            return IKResult(
                result.angles,
                False,
                max(result.position_error, legs.position_error),
                max(result.orientation_error, legs.orientation_error),
                result.iterations + legs.iterations,
                legs.at_limits + result.at_limits,
            )
    return result


def point_in_start_frame(
    model: RobotModel,
    link: str,
    start: Mapping[str, float],
    angles: Mapping[str, float],
) -> Vec3:
    """Where ``link``'s origin is after :func:`solve_balanced` moved the body to ``angles``,
    in the torso frame of the pose ``start`` it began from (the frame its target is given
    in): the robot stands on its other feet, which stayed where they were. The torso frame of
    ``angles`` itself has moved with the body. With no other foot, the torso frame of
    ``angles``."""
    pose = {j.name: 0.0 for j in model.joints}
    before = forward(model, {**pose, **start})
    after = forward(model, {**pose, **angles})
    feet = [f for f, kind in effectors(model).items() if kind == "foot" and f != link]
    if not feet:
        return apply(after[link], (0.0, 0.0, 0.0))
    # the torso of ``angles`` placed so that its first standing foot is where it was
    torso = compose(before[feet[0]], invert(after[feet[0]]))
    return apply(compose(torso, after[link]), (0.0, 0.0, 0.0))
