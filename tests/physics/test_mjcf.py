"""to_mjcf: every built-in model loads in MuJoCo with one servo per mapped joint; joint
origins rotate as the model's kinematics says; the text is the same for the same model."""

from __future__ import annotations

import math

import mujoco
import pytest

from rcb4hv.robot import Geom, Inertial, Joint, Link, RobotModel
from rcb4hv.robot.builtin import BUILTIN, load_builtin
from rcb4hv.robot.geometry import pose_transform
from rcb4hv.robot.kinematics import forward
from rcb4hv.robot.mjcf import IMU_SITE, to_mjcf
from rcb4hv.robot.servos import back_emf_damping, controller_damping, stiffness


@pytest.mark.parametrize("name", BUILTIN)
def test_every_builtin_model_loads_with_its_servos(name: str) -> None:
    model = load_builtin(name)
    text = to_mjcf(model)
    assert text == to_mjcf(model)
    m = mujoco.MjModel.from_xml_string(text)
    assert m.nu == len(model.servos)
    assert m.nq == 7 + len(model.joints)
    gyro, accelerometer = m.sensor("gyro"), m.sensor("accelerometer")  # KeyError if missing
    assert gyro.type[0] == mujoco.mjtSensor.mjSENS_GYRO
    assert accelerometer.type[0] == mujoco.mjtSensor.mjSENS_ACCELEROMETER
    imu = m.site(IMU_SITE)
    assert gyro.objid[0] == accelerometer.objid[0] == imu.id
    assert m.site_bodyid[imu.id] == m.body(model.root).id
    for s in model.servos:
        act = m.actuator(f"servo{s.index}")
        assert s.servo is not None
        assert act.forcerange[1] == pytest.approx(s.servo.stall_torque)
        assert act.gainprm[0] == pytest.approx(stiffness(s.servo, 60))
        if model.joint(s.joint).kind != "wheel":  # the controller's braking, inside the clamp
            assert act.biasprm[2] == pytest.approx(-controller_damping(s.servo))
        joint = m.joint(s.joint)
        assert m.dof_damping[joint.dofadr[0]] == pytest.approx(back_emf_damping(s.servo))
        j = model.joint(s.joint)
        assert tuple(joint.range) == pytest.approx((j.lower, j.upper))
    assert abs(sum(m.body_mass) - model.mass) < 1e-3
    # exported standing on the floor: the lowest shape just touches it
    d = mujoco.MjData(m)
    mujoco.mj_forward(m, d)
    lowest = min(
        d.geom_xpos[g][2] - sum(abs(d.geom_xmat[g][6 + k]) * m.geom_size[g][k] for k in range(3))
        for g in range(1, m.ngeom)
        if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX
    )
    assert lowest == pytest.approx(0.0, abs=1e-9)


def test_joint_origins_follow_the_models_kinematics() -> None:
    unit = Inertial(0.1, (0.0, 0.0, 0.0), (1e-4, 1e-4, 1e-4, 0.0, 0.0, 0.0))
    rpy = (0.3, -0.5, 1.1)
    model = RobotModel(
        "t",
        "test",
        "a",
        (Link("a", unit, (Geom("box", (0.1, 0.1, 0.1)),)), Link("b", unit)),
        (Joint("j", "a", "b", (0.1, 0.2, 0.3), rpy, (0.0, 0.0, 1.0), -1.0, 1.0, "yaw"),),
        (),
    )
    m = mujoco.MjModel.from_xml_string(to_mjcf(model, base_height=0.0))
    d = mujoco.MjData(m)
    d.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
    d.qpos[7] = 0.4
    mujoco.mj_forward(m, d)
    want = forward(model, {"j": 0.4})["b"]
    got = d.xmat[m.body("b").id].reshape(3, 3)
    for i in range(3):
        for k in range(3):
            assert math.isclose(got[i][k], want[i][k], abs_tol=1e-12)
    assert list(d.xpos[m.body("b").id]) == pytest.approx([want[i][3] for i in range(3)])


def test_a_recorded_pose_redraws_the_simulated_robot() -> None:
    """TrackPoint's torso pose and joint angles, through the model's own kinematics, put
    every link where MuJoCo has it (what a 3D view draws from)."""
    from rcb4hv.physics import PhysicsWorld

    model = load_builtin("kxr-l2")
    world = PhysicsWorld(model)
    world.place(model.home)
    for s in model.servos:
        world.drive(s.index, model.home.get(s.joint, 0.0) + 0.2, 20.0)
    world.step(200)
    mujoco.mj_kinematics(world.m, world.d)  # link poses of the current state (a step ends
    # with the positions integrated past the poses it computed)
    b = world.base()
    base = pose_transform((b.x, b.y, b.z), world.quaternion())
    frames = forward(model, world.joint_angles(), base)
    for link in model.links:
        got = world.d.xpos[world.m.body(link.name).id]
        want = [frames[link.name][i][3] for i in range(3)]
        assert list(got) == pytest.approx(want, abs=1e-9)
