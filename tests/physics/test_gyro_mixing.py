"""The gyro as a real robot reads it: at rest it reads its calibrated reference (the measured
register 0), and Kondo's ankle mixing (Hello KXR-L2: AD2 x 9 into both ankle pitch servos,
AD1 x 8 into both ankle rolls) damps the sway after a push; with the gyro's signs reversed
the same mixing throws the robot over."""

from __future__ import annotations

import dataclasses
import math
from functools import cache

import pytest

from rcb4hv.hth4 import load_project
from rcb4hv.physics import DEFAULT_SENSORS, SensorLayout
from rcb4hv.project.physics_sim import PhysicsSimulator
from rcb4hv.project.relocate import project_image
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.rom.layout import MotionLayout
from tests.physics.conftest import PROJECT

KXR = load_builtin("kxr-l2-gripper")
AD1, AD2 = 0x4024, 0x4026  # mixing sources: the measured words of AD1, AD2 (word, RAM)
KONDO_ANKLE_MIXING = {14: (AD2, 9), 15: (AD2, 9), 16: (AD1, 8), 17: (AD1, 8)}
PUSH_N, PUSH_S, WATCH_S = 4.0, 0.1, 2.0


@cache
def fixture_image(mixing: bool) -> tuple[bytes, MotionLayout]:
    """The fixture (gyro calibrated to 273 on AD1, AD2), with Kondo's ankle mixing or none."""
    project = load_project(PROJECT)
    if mixing:
        servos = tuple(
            dataclasses.replace(s, mixing1_address=m[0], mixing1_rate=m[1])
            if (m := KONDO_ANKLE_MIXING.get(s.device_number))
            else s
            for s in project.servos
        )
        project = dataclasses.replace(project, servos=servos)
    return project_image(project, None)


def pushed(
    mixing: bool, force: tuple[float, float, float], sensors: SensorLayout
) -> tuple[float, float]:
    """Stand the booted robot, push its torso with ``force`` (N) for PUSH_S, watch WATCH_S:
    (integrated |roll rate| + |pitch rate| in degrees, largest tilt in degrees)."""
    image, lay = fixture_image(mixing)
    sim = PhysicsSimulator(image, KXR, motion_layout=lay, sensors=sensors)
    sim.boot()
    world, backend = sim.world, sim.backend
    assert backend is not None
    rates: list[float] = []
    tilts: list[float] = []

    def watch(_: object) -> None:
        gyro = world.imu()[0]
        rates.append(abs(gyro[0]) + abs(gyro[1]))
        tilts.append(world.base().tilt)

    backend.observers.append(watch)
    world.push(force)
    sim.run_us(round(PUSH_S * 1e6))
    world.push()
    sim.run_us(round(WATCH_S * 1e6))
    period = sim.board.output_period
    return math.degrees(sum(rates) * period), math.degrees(max(tilts))


def test_a_calibrated_gyro_at_rest_reads_its_reference_and_measures_zero() -> None:
    image, lay = fixture_image(True)
    sim = PhysicsSimulator(image, KXR, motion_layout=lay)
    sim.boot()
    b = sim.board
    assert (b.ad_reference(1), b.ad_reference(2)) == (273, 273)
    assert abs(b.ad_input(1) - 273) <= 1 and abs(b.ad_input(2) - 273) <= 1
    assert abs(b.ad_measured(1)) <= 1 and abs(b.ad_measured(2)) <= 1
    # so the mixed ankles stay where the motion puts them and the robot stands
    assert math.degrees(sim.world.base().tilt) < 3.0


@pytest.mark.parametrize("force", [(PUSH_N, 0.0, 0.0), (-PUSH_N, 0.0, 0.0), (0.0, PUSH_N, 0.0)])
def test_kondo_ankle_mixing_damps_the_sway_after_a_push(force: tuple[float, float, float]) -> None:
    sway_off, tilt_off = pushed(False, force, DEFAULT_SENSORS)
    sway_on, tilt_on = pushed(True, force, DEFAULT_SENSORS)
    assert tilt_off < 10.0  # the push alone does not throw it over
    assert sway_on < 0.9 * sway_off
    assert tilt_on <= tilt_off + 0.1


def test_with_the_gyro_signs_reversed_the_same_mixing_throws_the_robot_over() -> None:
    # at the default scale reversed signs sway 9x as much; at twice the scale they fall
    right = dataclasses.replace(
        DEFAULT_SENSORS, gyro_counts_per_dps=2 * DEFAULT_SENSORS.gyro_counts_per_dps
    )
    wrong = dataclasses.replace(right, gyro_x_sign=1, gyro_y_sign=1)
    _, tilt_wrong = pushed(True, (PUSH_N, 0.0, 0.0), wrong)
    _, tilt_right = pushed(True, (PUSH_N, 0.0, 0.0), right)
    assert tilt_wrong > 60.0 > 10.0 > tilt_right
