"""A small biped built from the model contract for the physics tests (KHR-3HV-like sizes and
masses from ../shared/robots/FACTS.md, simplified to boxes), on the KXR fixture's servo
numbering (even ICS = right side; its home pose is a slight crouch)."""

from __future__ import annotations

from rcb4hv.robot import Geom, Inertial, Joint, Link, RobotModel, ServoJoint, ServoSpec

KRS = ServoSpec("KRS-2552RHV", stall_torque=1.37, no_load_speed=7.48, mass=0.0415)
HALF_HIP = 0.0217  # FACTS.md: 43.4 mm between the hip-yaw axes
THIGH = 0.065
SHIN = 0.065
SHOULDER_Y = 0.0489  # 97.8 mm between the shoulder axes
SHOULDER_Z = 0.0875
ANKLE_TO_SOLE = 0.03


def box(name: str, mass: float, size: tuple[float, float, float], z: float) -> Link:
    x, y, h = size
    inertia = (
        mass * (y * y + h * h) / 12,
        mass * (x * x + h * h) / 12,
        mass * (x * x + y * y) / 12,
        0.0,
        0.0,
        0.0,
    )
    return Link(name, Inertial(mass, (0.0, 0.0, z), inertia), (Geom("box", size, (0.0, 0.0, z)),))


PITCH = (0.0, 1.0, 0.0)
ROLL = (1.0, 0.0, 0.0)


def biped() -> RobotModel:
    links = [box("torso", 0.45, (0.06, 0.10, 0.12), 0.06)]
    joints: list[Joint] = []
    servos: list[ServoJoint] = []
    lim = 2.3
    # joint -> (right ICS, sign right, sign left)
    numbers = {
        "shoulder_pitch": (2, 1, -1),
        "shoulder_roll": (4, 1, 1),
        "elbow": (6, 1, 1),
        "hip_roll": (8, 1, 1),
        "hip_pitch": (10, -1, -1),
        "knee": (12, 1, 1),
        "ankle_pitch": (14, -1, -1),
        "ankle_roll": (16, 1, 1),
    }
    for side, sy, off in (("left", 1.0, 1), ("right", -1.0, 0)):
        other = "right" if side == "left" else "left"
        s = side[0]
        chain = [
            # (joint, kind, axis, parent, child, xyz, link mass, link size, link z)
            (
                "hip_roll",
                "roll",
                ROLL,
                "torso",
                "hip",
                (0.0, sy * HALF_HIP, 0.0),
                0.04,
                (0.03, 0.03, 0.03),
                -0.015,
            ),
            (
                "hip_pitch",
                "pitch",
                PITCH,
                "hip",
                "thigh",
                (0.0, 0.0, -0.03),
                0.10,
                (0.03, 0.03, THIGH),
                -THIGH / 2,
            ),
            (
                "knee",
                "pitch",
                PITCH,
                "thigh",
                "shin",
                (0.0, 0.0, -THIGH),
                0.10,
                (0.03, 0.03, SHIN),
                -SHIN / 2,
            ),
            (
                "ankle_pitch",
                "pitch",
                PITCH,
                "shin",
                "ankle",
                (0.0, 0.0, -SHIN),
                0.04,
                (0.02, 0.02, 0.02),
                0.0,
            ),
            (
                "ankle_roll",
                "roll",
                ROLL,
                "ankle",
                "foot",
                (0.0, 0.0, 0.0),
                0.08,
                (0.10, 0.055, 0.01),
                -ANKLE_TO_SOLE + 0.005,
            ),
            (
                "shoulder_pitch",
                "pitch",
                PITCH,
                "torso",
                "shoulder",
                (0.0, sy * SHOULDER_Y, SHOULDER_Z),
                0.03,
                (0.02, 0.02, 0.02),
                0.0,
            ),
            (
                "shoulder_roll",
                "roll",
                ROLL,
                "shoulder",
                "upper_arm",
                (0.0, sy * 0.02, 0.0),
                0.06,
                (0.025, 0.025, 0.06),
                -0.03,
            ),
            (
                "elbow",
                "pitch",
                PITCH,
                "upper_arm",
                "forearm",
                (0.0, 0.0, -0.06),
                0.05,
                (0.025, 0.025, 0.06),
                -0.03,
            ),
        ]
        for jn, kind, axis, parent, child, xyz, mass, size, z in chain:
            p = parent if parent == "torso" else f"{s}_{parent}"
            links.append(box(f"{s}_{child}", mass, size, z))
            joints.append(
                Joint(
                    f"{s}_{jn}",
                    p,
                    f"{s}_{child}",
                    xyz,
                    (0.0, 0.0, 0.0),
                    axis,
                    -lim,
                    lim,
                    kind,
                    side,
                    f"{other[0]}_{jn}",
                )  # type: ignore[arg-type]
            )
            index, sign_right, sign_left = numbers[jn]
            sign = sign_left if side == "left" else sign_right
            servos.append(ServoJoint(index + off, f"{s}_{jn}", sign, 0, KRS))
    return RobotModel(
        "test-biped", "Test biped", "torso", tuple(links), tuple(joints), tuple(servos)
    )


def standing_height(model: RobotModel) -> float:
    """Root height with straight legs (feet flat on the floor)."""
    return 0.03 + THIGH + SHIN + ANKLE_TO_SOLE
