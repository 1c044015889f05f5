"""Static balance against physics: a pose physics holds is balanced, one leant forward until
physics topples it is not (bench/balance_vs_physics.py has the whole fixture's table)."""

from __future__ import annotations

import pytest
from bench.balance_vs_physics import FALLEN_DEG, hold, lean

from rcb4hv.physics.world import PhysicsWorld
from rcb4hv.robot.balance import pose_balance
from rcb4hv.robot.builtin import load_builtin


@pytest.mark.parametrize("name", ["kxr-l2-gripper", "khr3hv"])
def test_static_balance_agrees_with_physics_on_a_forward_lean(name: str) -> None:
    model = load_builtin(name)
    world = PhysicsWorld(model)
    turn, margin = hold(world, lean(model, 0))
    assert turn < 1.0
    assert pose_balance(model, model.home).margin_m == pytest.approx(margin, abs=0.003)
    leans = range(0, 40, 3)
    physics = {}
    for degrees in leans:
        physics[degrees] = hold(world, lean(model, degrees))[0] < FALLEN_DEG
        if not physics[degrees]:
            break
    edge = max(physics)
    assert not physics[edge], "physics never toppled the lean"
    assert not pose_balance(model, lean(model, edge)).balanced  # leant until physics falls
    # static balance is conservative by at most one step (its reserve, STABILITY_RESERVE_M)
    for degrees in range(0, edge - 3, 3):
        assert pose_balance(model, lean(model, degrees)).balanced, degrees
