"""The servo controller's braking (``servos.controller_damping``): the figure follows its rule
(the bare servo critically damped at stretch 127), the MJCF carries it inside the stall-torque
clamp, a free servo loses it and gets it back when driven again, and it damps the rocking of
a pushed robot standing on its feet."""

from __future__ import annotations

import math

import pytest

from rcb4hv.hth4 import load_project
from rcb4hv.physics import PhysicsOptions, PhysicsWorld
from rcb4hv.project.physics_sim import PhysicsSimulator
from rcb4hv.project.relocate import project_image
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.robot.model import ServoSpec
from rcb4hv.robot.servos import (
    KRS_2552RHV,
    KRS_3304R2,
    armature,
    back_emf_damping,
    controller_damping,
    stiffness,
)
from tests.physics.conftest import PROJECT

KXR = load_builtin("kxr-l2-gripper")


@pytest.mark.parametrize("spec", [KRS_3304R2, KRS_2552RHV])
def test_the_bare_servo_is_critically_damped_at_stretch_127(spec: ServoSpec) -> None:
    kd = controller_damping(spec)
    b, j = back_emf_damping(spec), armature(spec)
    kp = stiffness(spec, 127)
    assert (kd + b) / (2.0 * math.sqrt(kp * j)) == pytest.approx(1.0)
    assert 0.25 < kd < 0.35  # N·m·s/rad: 1.6-1.7 x the motor's back-EMF damping


def test_a_free_servo_loses_its_braking_and_gets_it_back() -> None:
    world = PhysicsWorld(KXR, options=PhysicsOptions(servo_damping=2.0))
    s = next(iter(world.servos.values()))
    kd = 2.0 * controller_damping(s.spec)
    assert world.m.actuator_biasprm[s.actuator, 2] == pytest.approx(-kd)
    world.release(s.index)
    assert world.m.actuator_biasprm[s.actuator, 2] == 0.0
    world.drive(s.index, 0.0, 10.0)
    assert world.m.actuator_biasprm[s.actuator, 2] == pytest.approx(-kd)


def _rocking(options: PhysicsOptions) -> float:
    """The fixture's robot standing, pushed sideways at the torso (4 N for 0.1 s), watched for
    2 s: its integrated |roll rate| + |pitch rate| (degrees)."""
    image, lay = project_image(load_project(PROJECT), None)
    sim = PhysicsSimulator(image, KXR, motion_layout=lay, options=options)
    sim.boot()
    world, backend = sim.world, sim.backend
    assert backend is not None
    rates: list[float] = []
    backend.observers.append(lambda _: rates.append(sum(abs(w) for w in world.imu()[0][:2])))
    world.push((0.0, 4.0, 0.0))
    sim.run_us(100_000)
    world.push()
    sim.run_us(2_000_000)
    return math.degrees(sum(rates) * sim.board.output_period)


def test_the_braking_damps_the_rocking_of_a_pushed_robot() -> None:
    braked = _rocking(PhysicsOptions())
    unbraked = _rocking(PhysicsOptions(servo_damping=1e-6))
    assert braked < 0.8 * unbraked
