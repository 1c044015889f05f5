"""An object held in a hand: a point mass at the hand's tip (``PhysicsOptions.carry_left_g``
and ``carry_right_g``).

Kondo's gripper samples carry things: the KXR sets' 掴み歩行 ("walk carrying") motions lean
further onto the far foot than the plain walks do, because the real robot has something in
its hand. Played empty-handed in the model, the fixture's and three kxreus projects'
carrying side steps go the other way; with 50 g in the carrying hand they go the named way
(docs/physics.md, "What the carrying motions carry"). No project says what the object
weighs, so the model never assumes one: a load is a what-if a user sets.

The hands are the robot's :func:`~rcb4hv.robot.ik.effectors` (the same ones the editor's
handles grab), the load sits at the hand's tip (:func:`~rcb4hv.robot.ik.effector_point`),
and the hand link's mass, centre of mass and moments of inertia take it in: the parallel
axis terms of the load and of the link's own mass about the new centre, on the link's
principal axes (the products of inertia a point load off those axes adds are left out).
"""

from __future__ import annotations

from typing import Any, Literal

import numpy as np

from rcb4hv.errors import PhysicsError
from rcb4hv.robot.ik import effector_point, effectors
from rcb4hv.robot.kinematics import forward
from rcb4hv.robot.model import RobotModel

__all__ = ["add_load", "hand_link"]

Side = Literal["left", "right"]


def hand_link(model: RobotModel, side: Side) -> str:
    """The link of ``model``'s ``side`` hand (left: +y of the torso at the zero pose).
    Raises :class:`~rcb4hv.errors.PhysicsError` for a robot without that hand."""
    hands = [n for n, kind in effectors(model).items() if kind == "hand"]
    frames = forward(model, {})
    sign = 1.0 if side == "left" else -1.0
    mine = [n for n in hands if sign * frames[n][1][3] > 0.0]
    if not mine:
        raise PhysicsError(f"{model.name} has no {side} hand to carry a load in")
    # two on one side (a six-legged robot's front legs are not hands): the one furthest out
    return max(mine, key=lambda n: sign * frames[n][1][3])


def add_load(mj: Any, m: Any, model: RobotModel, side: Side, grams: float) -> str:
    """Put ``grams`` at the tip of ``model``'s ``side`` hand in the compiled MuJoCo model
    ``m`` (module ``mj``); returns the hand's link name."""
    link = hand_link(model, side)
    body = int(m.body(link).id)
    load = grams / 1000.0
    tip = np.array(effector_point(model, link))
    m0 = float(m.body_mass[body])
    old = np.array(m.body_ipos[body], dtype=float)
    com = (m0 * old + load * tip) / (m0 + load)
    # the link's own centre and the load, offset from the new centre on the link's principal
    # axes (body_iquat turns those axes into the body frame): their parallel-axis terms
    inv = np.zeros(4)
    mj.mju_negQuat(inv, m.body_iquat[body])
    for point, mass in ((old, m0), (tip, load)):
        d = np.zeros(3)
        mj.mju_rotVecQuat(d, point - com, inv)
        m.body_inertia[body] += mass * (d @ d - d * d)
    m.body_mass[body] = m0 + load
    m.body_ipos[body] = com
    return link
