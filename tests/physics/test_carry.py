"""A load in a hand (PhysicsOptions.carry_left_g / carry_right_g): where it goes, what it
weighs, and what it does to Kondo's carrying side steps."""

from __future__ import annotations

import pytest

from rcb4hv.errors import PhysicsError
from rcb4hv.physics import PhysicsOptions, PhysicsWorld
from rcb4hv.physics.load import hand_link
from rcb4hv.project.run import run_motions
from rcb4hv.robot.builtin import load_robot
from rcb4hv.robot.ik import effector_point
from tests.physics.test_fixture_motions import IMAGE, KXR, LAYOUT, NAMES

# the fixture's 右掴み歩行左 / 右掴み歩行右: side steps left / right, carrying in the right hand
CARRY_RIGHT_STEP_LEFT, CARRY_RIGHT_STEP_RIGHT = 52, 53


def _com(world: PhysicsWorld) -> list[float]:
    m = world.m
    total = sum(float(v) for v in m.body_mass)
    return [
        sum(float(m.body_mass[b]) * float(world.d.xipos[b][k]) for b in range(m.nbody)) / total
        for k in range(3)
    ]


def test_the_load_sits_at_the_hand_tip_and_weighs_what_was_given() -> None:
    import mujoco

    plain = PhysicsWorld(KXR)
    loaded = PhysicsWorld(KXR, options=PhysicsOptions(carry_left_g=200))
    for w in (plain, loaded):
        mujoco.mj_forward(w.m, w.d)
    assert sum(loaded.m.body_mass) == pytest.approx(sum(plain.m.body_mass) + 0.2)
    hand = hand_link(KXR, "left")
    assert hand == "l_forearm"
    body = loaded.m.body(hand).id
    tip = effector_point(KXR, hand)
    m0 = float(plain.m.body_mass[body])
    for k in range(3):  # the link's centre moves toward the tip by the load's share
        expect = (m0 * float(plain.m.body_ipos[body][k]) + 0.2 * tip[k]) / (m0 + 0.2)
        assert float(loaded.m.body_ipos[body][k]) == pytest.approx(expect)
    assert all(loaded.m.body_inertia[body] > plain.m.body_inertia[body] - 1e-12)
    # the robot's centre of mass moves to its left (+y), the hand's side
    assert _com(loaded)[1] > _com(plain)[1] + 0.005
    right = PhysicsWorld(KXR, options=PhysicsOptions(carry_right_g=200))
    mujoco.mj_forward(right.m, right.d)
    assert _com(right)[1] < _com(plain)[1] - 0.005


def test_the_hands_are_the_arms_ends_on_every_humanoid() -> None:
    for name in ("kxr-l2", "khr3hv", "khr3hv-22", "kxr:L2W2L6A4H2G"):
        model = load_robot(name)
        left, right = hand_link(model, "left"), hand_link(model, "right")
        assert left.startswith("l_") and right.startswith("r_"), name


def test_a_robot_without_hands_carries_nothing() -> None:
    with pytest.raises(PhysicsError, match="no left hand"):
        PhysicsWorld(load_robot("kxr:L4T"), options=PhysicsOptions(carry_left_g=50))


@pytest.mark.parametrize("bad", [-1.0, 2001.0, float("nan")])
def test_a_load_is_zero_to_two_kilograms(bad: float) -> None:
    with pytest.raises(ValueError, match="carry_right_g"):
        PhysicsOptions(carry_right_g=bad)
    assert PhysicsOptions.parse(["carry_left_g=50"]).changed() == (("carry_left_g", 50.0),)


def test_a_load_in_the_hand_moves_where_the_carrying_side_steps_end() -> None:
    """Held on their buttons for 3 s, the fixture's side steps carrying in the right hand: the
    step left goes left empty-handed and further with 50 g in that hand, the step right ends
    right of it either way: where they end hangs on a load no project states (docs/physics.md,
    "What the carrying motions carry")."""
    slots = [CARRY_RIGHT_STEP_LEFT, CARRY_RIGHT_STEP_RIGHT]

    def dy(grams: float) -> list[float]:
        opts = PhysicsOptions(carry_right_g=grams)
        run = run_motions(IMAGE, slots, names=NAMES, robot=KXR, motion_layout=LAYOUT, options=opts)
        assert not any(m.outcome.fell for m in run.motions)
        return [m.outcome.dy_m for m in run.motions]

    left, right = dy(0.0)
    # with the weighed A3 arm (29 Nov 2026) the empty-handed step right ends 3 cm right of
    # the step left's end, 7 cm before it
    assert left > 0.05 and right < left
    loaded_left, loaded_right = dy(50.0)
    assert loaded_left > left + 0.03  # the load carries the step left further
    assert loaded_right < loaded_left - 0.05
