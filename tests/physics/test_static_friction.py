"""Static friction holds: a robot standing on a slope below its feet's friction limit stays
where it stands (``mjcf.IMPRATIO``), and past the limit it still slides."""

from __future__ import annotations

import math

import pytest

from rcb4hv.physics import PhysicsOptions, PhysicsWorld
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.robot.mjcf import FLOOR_FRICTION, IMPRATIO, to_mjcf

KXR = load_builtin("kxr-l2-gripper")


def _travel_on_slope(tilt_deg: float, seconds: float, friction: float = 1.0) -> tuple[float, float]:
    """Where the robot's torso goes (mm) while it holds its zero pose on a slope, after
    0.5 s to settle; and its final tilt (rad)."""
    world = PhysicsWorld(KXR, options=PhysicsOptions(floor_tilt_deg=tilt_deg, friction=friction))
    for index in world.servos:
        world.drive(index, 0.0, world.stiffness(index, 127))
    world.step(round(0.5 / world.timestep))
    start = world.base()
    world.step(round(seconds / world.timestep))
    end = world.base()
    return 1000.0 * math.hypot(end.x - start.x, end.y - start.y), end.tilt


def test_the_option_is_in_the_model() -> None:
    assert f'impratio="{IMPRATIO!r}"' in to_mjcf(KXR)
    assert 'impratio="1.0"' in to_mjcf(KXR, impratio=1.0)


def test_a_robot_on_a_slope_below_the_friction_limit_does_not_creep() -> None:
    # tan 15° = 0.27 < 0.4: dry friction holds the feet. With MuJoCo's default impratio of 1
    # the soft friction let them creep 6.1 mm in these 5 s (measured, 29 Nov 2026).
    assert math.tan(math.radians(15.0)) < FLOOR_FRICTION
    travel, tilt = _travel_on_slope(15.0, 5.0)
    assert tilt < math.radians(2.0)  # still standing
    assert travel < 0.5


def test_past_the_friction_limit_the_feet_still_slide() -> None:
    # the same slope on a floor a third as grippy (0.13 < tan 15°): the robot slides down
    travel, _ = _travel_on_slope(15.0, 1.0, friction=1 / 3)
    assert travel > 50.0


@pytest.mark.parametrize("impratio", [0.0, -1.0, math.inf, math.nan])
def test_a_bad_impratio_is_refused(impratio: float) -> None:
    with pytest.raises(ValueError, match="impratio must be"):
        to_mjcf(KXR, impratio=impratio)
