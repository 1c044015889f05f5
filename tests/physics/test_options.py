"""PhysicsOptions: factors on the model's chosen figures, for sensitivity studies; the default
options change nothing."""

from __future__ import annotations

import pytest

from rcb4hv.physics import DEFAULT_SENSORS, PhysicsOptions, PhysicsWorld
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.robot.mjcf import FLOOR_FRICTION
from rcb4hv.robot.servos import armature, stiffness

KXR = load_builtin("kxr-l2")


def test_each_factor_scales_its_figure_and_the_defaults_change_nothing() -> None:
    plain = PhysicsWorld(KXR)
    opts = PhysicsOptions(stiffness=2.0, armature=0.5, friction=0.75, free_damping=3.0)
    scaled = PhysicsWorld(KXR, options=opts)
    index = next(iter(plain.servos))
    spec = plain.servos[index].spec
    assert plain.stiffness(index, 60) == stiffness(spec, 60)
    assert scaled.stiffness(index, 60) == pytest.approx(2.0 * stiffness(spec, 60))
    dof = plain.servos[index].dof
    assert plain.m.dof_armature[dof] == pytest.approx(armature(spec))
    assert scaled.m.dof_armature[dof] == pytest.approx(0.5 * armature(spec))
    assert scaled.m.geom_friction[0][0] == pytest.approx(0.75 * FLOOR_FRICTION)
    plain.release(index)
    scaled.release(index)
    assert scaled.m.dof_damping[dof] == pytest.approx(3.0 * plain.m.dof_damping[dof])


def test_sensor_scales() -> None:
    assert PhysicsOptions().sensors(DEFAULT_SENSORS) is DEFAULT_SENSORS
    s = PhysicsOptions(gyro_scale=2.0, accel_scale=0.5).sensors(DEFAULT_SENSORS)
    assert s.gyro_counts_per_dps == 2.0 * DEFAULT_SENSORS.gyro_counts_per_dps
    assert s.accel_counts_per_g == 0.5 * DEFAULT_SENSORS.accel_counts_per_g


@pytest.mark.parametrize("bad", [0.0, -1.0])
def test_a_factor_is_positive(bad: float) -> None:
    with pytest.raises(ValueError, match="speed_cap"):
        PhysicsOptions(speed_cap=bad)
