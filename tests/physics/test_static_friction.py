"""Static friction in MuJoCo's soft contacts (``mjcf.IMPRATIO``): at MuJoCo's default a foot
loaded below its friction limit creeps, which the model documents and keeps for speed;
``PhysicsOptions(impratio=100)`` (Menagerie's legged robots' setting) holds it. Past the limit
the feet slide either way."""

from __future__ import annotations

import math

import pytest

from rcb4hv.physics import PhysicsOptions, PhysicsWorld
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.robot.mjcf import FLOOR_FRICTION, IMPRATIO, to_mjcf

KXR = load_builtin("kxr-l2-gripper")


def _travel_on_slope(
    tilt_deg: float, seconds: float, *, friction: float = 1.0, impratio: float = 1.0
) -> tuple[float, float]:
    """Where the torso goes (mm) while the robot holds its zero pose on a slope, after 0.5 s
    to settle; and its final tilt (rad)."""
    options = PhysicsOptions(floor_tilt_deg=tilt_deg, friction=friction, impratio=impratio)
    world = PhysicsWorld(KXR, options=options)
    for index in world.servos:
        world.drive(index, 0.0, world.stiffness(index, 127))
    world.step(round(0.5 / world.timestep))
    start = world.base()
    world.step(round(seconds / world.timestep))
    end = world.base()
    return 1000.0 * math.hypot(end.x - start.x, end.y - start.y), end.tilt


def test_the_option_reaches_the_model() -> None:
    assert f'impratio="{IMPRATIO!r}"' in to_mjcf(KXR)
    assert 'impratio="100.0"' in to_mjcf(KXR, impratio=100.0)
    world = PhysicsWorld(KXR, options=PhysicsOptions(impratio=100.0))
    assert world.m.opt.impratio == pytest.approx(100.0 * IMPRATIO)


def test_below_the_friction_limit_the_default_creeps_and_impratio_100_holds() -> None:
    # tan 15° = 0.27 < 0.4: dry friction would hold the feet where they stand
    assert math.tan(math.radians(15.0)) < FLOOR_FRICTION
    soft, tilt = _travel_on_slope(15.0, 5.0)
    assert tilt < math.radians(2.0)  # still standing
    assert 2.0 < soft < 20.0  # MuJoCo's soft friction: 6.1 mm in 5 s (docs/physics.md)
    held, tilt = _travel_on_slope(15.0, 5.0, impratio=100.0)
    assert tilt < math.radians(2.0)
    assert held < 0.5  # 0.17 mm


@pytest.mark.parametrize("impratio", [1.0, 100.0])
def test_past_the_friction_limit_the_feet_slide(impratio: float) -> None:
    # the same slope on a floor a third as grippy (0.13 < tan 15°): the robot slides down
    travel, _ = _travel_on_slope(15.0, 1.0, friction=1 / 3, impratio=impratio)
    assert travel > 50.0


@pytest.mark.parametrize("impratio", [0.0, -1.0, math.inf, math.nan])
def test_a_bad_impratio_is_refused(impratio: float) -> None:
    with pytest.raises(ValueError, match="impratio must be"):
        to_mjcf(KXR, impratio=impratio)
    with pytest.raises(ValueError, match="impratio"):
        PhysicsOptions(impratio=impratio)
