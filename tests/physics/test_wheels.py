"""A KRS servo in wheel mode: the value sent sets its speed (a velocity-driven joint)."""

from __future__ import annotations

import dataclasses
import math

import pytest

from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
from rcb4hv.hth4.project import load_project
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.project.physics_sim import PhysicsSimulator
from rcb4hv.project.relocate import project_image
from rcb4hv.robot.mjcf import to_mjcf
from rcb4hv.robot.servos import DEFAULT_SERVO, WHEEL_FULL_SCALE_DEG, wheel_duty
from tests.physics.conftest import PROJECT

WHEELS = {20: "右足首車輪", 21: "左足首車輪"}


def _wheeled_project():  # type: ignore[no-untyped-def]
    """The fixture (a KXR-L2 with grippers) with a wheel behind each ankle (ICS 20/21)."""
    project = load_project(PROJECT)
    servos = tuple(
        dataclasses.replace(s, name=WHEELS[s.device_number], mode="Normal")
        if s.device_number in WHEELS
        else s
        for s in project.servos
    )
    return dataclasses.replace(project, servos=servos, project_title="Hello_KXR-L2W2G")


def test_wheel_joints_turn_without_limits_in_mjcf() -> None:
    model = project_model(_wheeled_project())
    assert model.name == "kxr:L2W2L5A3G"
    text = to_mjcf(model)
    assert 'name="r_ankle_wheel" type="hinge" axis="0 1.0 0" limited="false"' in text
    assert 'ctrlrange="-1 1"' in text
    assert wheel_duty(math.radians(WHEEL_FULL_SCALE_DEG * 2)) == 1.0


def test_a_wheel_turns_at_the_commanded_speed() -> None:
    project = _wheeled_project()
    model = project_model(project)
    stand = {s.index: 7500 for s in model.servos}
    # half speed forward on both sides: right +2000 counts (sign +1), left -2000 (sign -1)
    spin = stand | {20: 9500, 21: 5500}
    stop = stand | {20: 7500, 21: 7500}
    for slot, pose in ((18, spin), (19, stop)):
        frames = [Keyframe(0.1, pose), Keyframe(1.0, pose)]
        project = add_motion(project, motion_from_keyframes(frames, slot=slot, name=f"m{slot}"))
    image, layout = project_image(project, None)
    sim = PhysicsSimulator(image, model, motion_layout=layout)
    sim.boot()
    sim.play(layout.address(18))
    want = 0.5 * DEFAULT_SERVO.no_load_speed  # duty 0.5 against the back-EMF line
    for index in WHEELS:
        assert sim.world.wheel_speed(index) == pytest.approx(want, rel=0.05)
    sim.play(layout.address(19))
    for index in WHEELS:
        assert abs(sim.world.wheel_speed(index)) < 0.05 * want


def test_the_kxr_l4r_drives_forward_as_kondos_sample_does() -> None:
    """Kondo's Hello_KXR-L4R drives forward (XL4R_101) with the right wheels (ICS 4, 8) at
    11500 and the left ones (5, 9) at 3500 for a second: the robot goes forward. kxreus's
    kxrl4r map gave the wheels the other signs, which drove all 18 of the sample's motions
    the wrong way (KXR-KITS.md §1.4 lists both)."""
    from rcb4hv.hth4.newproject import new_project
    from rcb4hv.robot.builtin import load_robot

    model = load_robot("kxr:L4R")
    project = new_project(model)
    stand = {s.index: 7500 for s in model.servos}
    drive = stand | {4: 11500, 8: 11500, 5: 3500, 9: 3500}
    frames = [Keyframe(0.025, drive), Keyframe(1.0, drive), Keyframe(0.025, stand)]
    project = add_motion(project, motion_from_keyframes(frames, slot=2, name="forward"))
    image, layout = project_image(project, None)
    sim = PhysicsSimulator(image, model, motion_layout=layout)
    sim.boot()
    sim.play(layout.address(2))
    out = sim.runs[-1].outcome
    assert out is not None and not out.fell
    assert out.dx_m > 0.1 and abs(out.dy_m) < 0.02 and abs(out.dyaw_deg) < 3.0
