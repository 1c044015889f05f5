"""PhysicsOptions: factors on the model's chosen figures, for sensitivity studies; the default
options change nothing."""

from __future__ import annotations

import pytest

from rcb4hv.physics import DEFAULT_SENSORS, PhysicsOptions, PhysicsWorld
from rcb4hv.physics.world import with_torque
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.robot.mjcf import FLOOR_FRICTION, TORSIONAL_FRICTION
from rcb4hv.robot.servos import armature, stiffness

KXR = load_builtin("kxr-l2")


def test_each_factor_scales_its_figure_and_the_defaults_change_nothing() -> None:
    plain = PhysicsWorld(KXR)
    opts = PhysicsOptions(
        stiffness=2.0, armature=0.5, friction=0.75, free_damping=3.0, torsional_friction=4.0
    )
    scaled = PhysicsWorld(KXR, options=opts)
    index = next(iter(plain.servos))
    spec = plain.servos[index].spec
    assert plain.stiffness(index, 60) == stiffness(spec, 60)
    assert scaled.stiffness(index, 60) == pytest.approx(2.0 * stiffness(spec, 60))
    dof = plain.servos[index].dof
    assert plain.m.dof_armature[dof] == pytest.approx(armature(spec))
    assert scaled.m.dof_armature[dof] == pytest.approx(0.5 * armature(spec))
    assert scaled.m.geom_friction[0][0] == pytest.approx(0.75 * FLOOR_FRICTION)
    assert plain.m.geom_friction[0][1] == pytest.approx(TORSIONAL_FRICTION)
    assert scaled.m.geom_friction[0][1] == pytest.approx(4.0 * TORSIONAL_FRICTION)
    plain.release(index)
    scaled.release(index)
    assert scaled.m.dof_damping[dof] == pytest.approx(3.0 * plain.m.dof_damping[dof])


def test_torque_scales_each_servo_and_what_the_servo_model_derives_from_it() -> None:
    plain = PhysicsWorld(KXR)
    weak = PhysicsWorld(KXR, options=PhysicsOptions(torque=0.5))
    assert with_torque(KXR, 1.0) is KXR
    for index, s in plain.servos.items():
        w = weak.servos[index]
        assert w.spec.stall_torque == pytest.approx(0.5 * s.spec.stall_torque)
        assert w.spec.no_load_speed == s.spec.no_load_speed
        assert weak.stiffness(index, 60) == pytest.approx(0.5 * plain.stiffness(index, 60))
        assert weak.m.actuator_forcerange[w.actuator][1] == pytest.approx(
            0.5 * plain.m.actuator_forcerange[s.actuator][1]
        )
        assert weak.m.dof_armature[w.dof] == pytest.approx(0.5 * plain.m.dof_armature[s.dof])
        assert weak.m.dof_damping[w.dof] == pytest.approx(0.5 * plain.m.dof_damping[s.dof])
    # the robot model itself is not changed: a what-if is not another robot
    assert weak.model is KXR
    assert PhysicsOptions.parse(["torque=0.48"]).changed() == (("torque", 0.48),)


def test_sensor_scales() -> None:
    assert PhysicsOptions().sensors(DEFAULT_SENSORS) is DEFAULT_SENSORS
    s = PhysicsOptions(gyro_scale=2.0, accel_scale=0.5).sensors(DEFAULT_SENSORS)
    assert s.gyro_counts_per_dps == 2.0 * DEFAULT_SENSORS.gyro_counts_per_dps
    assert s.accel_counts_per_g == 0.5 * DEFAULT_SENSORS.accel_counts_per_g


@pytest.mark.parametrize("bad", [0.0, -1.0, float("inf"), float("nan")])
def test_a_factor_is_positive_and_finite(bad: float) -> None:
    with pytest.raises(ValueError, match="speed_cap"):
        PhysicsOptions(speed_cap=bad)


def test_options_parse_from_name_value_items_and_name_what_they_change() -> None:
    assert PhysicsOptions().changed() == ()
    opts = PhysicsOptions.parse(["mass=1.1", " friction = 0.5", "deadband_deg=1"])
    assert opts == PhysicsOptions(friction=0.5, mass=1.1, deadband_deg=1.0)
    # in field order, whatever order they were given in
    assert opts.changed() == (("friction", 0.5), ("mass", 1.1), ("deadband_deg", 1.0))
    assert PhysicsOptions.parse([]) == PhysicsOptions()
    # a factor given as 1 changes nothing
    assert PhysicsOptions.parse(["stiffness=1"]).changed() == ()


@pytest.mark.parametrize(
    ("item", "message"),
    [
        ("frictio=0.5", "NAME one of stiffness"),
        ("friction", "NAME=VALUE"),
        ("friction=slippery", "'slippery' is not a number"),
        ("friction=0", r"friction must be a factor of 0\.01\.\.100"),
        ("mass=1e9", r"mass must be a factor of 0\.01\.\.100"),  # MuJoCo's state went NaN
        ("mass=1e-6", "mass must be a factor"),
        ("stiffness=inf", "stiffness must be a factor"),
        ("floor_tilt_deg=50", "floor_tilt_deg must be 0..45"),
    ],
)
def test_bad_items_are_refused_by_name(item: str, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        PhysicsOptions.parse([item])


def test_masses_scale_and_the_floor_tilts_by_turning_gravity() -> None:
    import math

    plain = PhysicsWorld(KXR)
    heavy = PhysicsWorld(KXR, options=PhysicsOptions(mass=1.1))
    assert sum(heavy.m.body_mass) == pytest.approx(1.1 * sum(plain.m.body_mass))
    assert heavy.m.body_inertia[1][0] == pytest.approx(1.1 * plain.m.body_inertia[1][0])
    g = -float(plain.m.opt.gravity[2])
    tilted = PhysicsWorld(KXR, options=PhysicsOptions(floor_tilt_deg=2.0, floor_tilt_dir_deg=90))
    gx, gy, gz = tilted.m.opt.gravity
    assert (gx, gy) == pytest.approx((0.0, g * math.sin(math.radians(2.0))), abs=1e-9)
    assert math.hypot(gx, gy, gz) == pytest.approx(g)
    with pytest.raises(ValueError, match="floor_tilt_deg"):
        PhysicsOptions(floor_tilt_deg=-1.0)


def test_a_dead_band_keeps_the_target_until_the_command_leaves_it() -> None:
    """A knee moved by 0.2° keeps its target under a 0.5° dead band; moved by 1° in small
    steps, it follows in jumps and stops within the band of the end."""
    import math

    from rcb4hv.hth4.keyframes import Keyframe
    from rcb4hv.project.physics_sim import PhysicsSimulator
    from tests.physics.conftest import image_with, pose

    knee = "r_knee_pitch"
    servo = KXR.servo_for_joint(knee)
    assert servo is not None
    moves = [[Keyframe(0.1, pose(KXR, {knee: 30.0})), Keyframe(0.1, pose(KXR, {knee: end}))]
             for end in (30.2, 31.0)]  # fmt: skip
    image, layout, _ = image_with(moves)

    def final(band: float, slot: int) -> float:
        options = PhysicsOptions(deadband_deg=band)
        sim = PhysicsSimulator(image, KXR, motion_layout=layout, options=options)
        sim.boot()
        sim.play(layout.address(slot), slot=slot, limit=1.0)
        assert sim.backend is not None
        return math.degrees(sim.backend.commanded[servo.index] or 0.0)

    assert final(0.0, 18) == pytest.approx(30.2, abs=0.05)
    assert final(0.5, 18) == pytest.approx(30.0, abs=0.05)
    assert 31.0 - 0.5 <= final(0.5, 19) < 31.0  # it follows, and stops within its band
