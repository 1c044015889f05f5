"""Physics as the emulator's servo backend, on a small test biped (tests/physics/robots.py):
free limbs fall and are read back by a host, stretch sets stiffness, poses stand or fall,
the sensors reach their AD channels, and the same input gives the same bits."""

from __future__ import annotations

import math
import sys

import pytest

from rcb4hv.errors import PhysicsUnavailableError
from rcb4hv.hth4.keyframes import Keyframe
from rcb4hv.physics import DEFAULT_SENSORS, require_mujoco
from rcb4hv.project.physics_sim import PhysicsSimulator
from rcb4hv.project.run import run_motions
from rcb4hv.protocol import POSITION_FREE, Com, Ics, Move, RunSingleServo, SetStretch
from rcb4hv.protocol.memory import SERVO
from tests.physics.conftest import host_read, image_with, pose
from tests.physics.robots import biped

ROBOT = biped()
STAND = pose(ROBOT, {})  # straight legs, arms down
# torso leant 60° forward over straight legs (hip pitch -60° with this model's axes)
BAD = pose(ROBOT, {"r_hip_pitch": -60.0, "l_hip_pitch": -60.0})
# forearms held straight forward: elbows at -90° with the upper arm hanging
ARMS_FORWARD = pose(ROBOT, {"r_elbow": -90.0, "l_elbow": -90.0})

IMAGE, LAYOUT, NAMES = image_with(
    [
        [Keyframe(0.5, STAND)],
        [Keyframe(0.5, BAD)],
        [Keyframe(0.3, ARMS_FORWARD)],
    ]
)
STAND_SLOT, BAD_SLOT, ARMS_SLOT = 18, 19, 20


def simulator() -> PhysicsSimulator:
    sim = PhysicsSimulator(IMAGE, ROBOT, motion_layout=LAYOUT, track=True)
    sim.boot()
    return sim


def measured(sim: PhysicsSimulator, ics: int) -> int:
    """A servo's measured position as a host reads it: the value at block +4 (motion space:
    the board reports position minus trim)."""
    data = host_read(sim.board.feed, Move(Com(), Ics(SERVO.MEASURED, ics), 2))
    return int.from_bytes(data, "little")


def test_standing_still_stays_upright() -> None:
    sim = simulator()
    sim.play(LAYOUT.address(STAND_SLOT))
    out = sim.outcomes[-1]
    assert not out.fell and out.end_pose == "upright"
    assert math.hypot(out.dx_m, out.dy_m) < 0.01
    assert abs(out.dyaw_deg) < 2.0
    assert out.max_tilt_deg < 10.0


def test_the_60_degree_lean_falls_on_its_front() -> None:
    sim = simulator()
    pitch_rates: list[int] = []
    assert sim.backend is not None
    sim.backend.observers.append(lambda _: pitch_rates.append(sim.board.ad_measured(2)))
    sim.play(LAYOUT.address(BAD_SLOT))
    # the pitch gyro (AD2, calibrated: measured = input - reference) saw the fall: pitching
    # forward is a positive rate about y, which the gyro reads as a falling value (sign -1)
    assert min(pitch_rates) < -90 * DEFAULT_SENSORS.gyro_counts_per_dps
    out = sim.outcomes[-1]
    assert out.fell and out.fell_at_s is not None and 0.0 < out.fell_at_s < 2.0
    assert out.end_pose == "on_front"
    assert out.max_tilt_deg > 60.0
    # lying on the front the forward accelerometer axis points down: about -1 g on AD5
    ad5 = sim.board.ad_input(5)
    assert ad5 < DEFAULT_SENSORS.accel_zero - 0.8 * DEFAULT_SENSORS.accel_counts_per_g


def test_a_free_limb_falls_and_a_host_reads_where_it_is() -> None:
    sim = simulator()
    sim.play(LAYOUT.address(ARMS_SLOT))
    elbow = 6  # r_elbow, held at -90° (forearm forward)
    held = measured(sim, elbow)
    assert abs(math.degrees(ROBOT.motion_angle(elbow, held)) + 90.0) < 5.0
    sim.board.feed(encode(RunSingleServo(elbow, 1, POSITION_FREE)))
    sim.run_us(3_000_000)
    sim.backend.sync()  # type: ignore[union-attr]
    fell = measured(sim, elbow)
    angle = math.degrees(ROBOT.motion_angle(elbow, fell))
    assert abs(angle) < 15.0  # the forearm hangs down (joint angle near 0)
    # the host reads the position reported at the last output period (the ICS reply)
    assert abs(math.degrees(sim.world.servo_angle(elbow)) - angle) < 1.0
    state = sim.board.servo_state(elbow)
    assert state is not None and not state.torque


def encode(cmd: RunSingleServo | SetStretch) -> bytes:
    return cmd.encode()


def _sag(stretch: int) -> float:
    """Degrees the held forearm sags under gravity at ``stretch``."""
    sim = simulator()
    sim.board.feed(encode(SetStretch({6: stretch})))
    sim.play(LAYOUT.address(ARMS_SLOT))
    return abs(math.degrees(sim.world.servo_angle(6)) + 90.0)


def test_stretch_sets_the_stiffness() -> None:
    soft, stiff = _sag(5), _sag(127)
    assert soft > 3 * stiff
    assert stiff < 1.0


def test_the_same_input_gives_the_same_bits() -> None:
    runs = []
    for _ in range(2):
        run = run_motions(
            IMAGE,
            [ARMS_SLOT, BAD_SLOT],
            names=NAMES,
            robot=ROBOT,
            motion_layout=LAYOUT,
            sequence=True,
            track=True,
        )
        runs.append(
            (
                [m.outcome for m in run.motions],
                run.virtual_s,
                [m.track for m in run.motions],
                [m.frames for m in run.motions],
            )
        )
    # floats compared with ==: the same bits, not merely close
    assert runs[0] == runs[1]
    assert sum(len(t) for t in runs[0][2]) > 100


def test_without_mujoco_the_error_names_the_extra(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)
    with pytest.raises(PhysicsUnavailableError, match=r"install rcb4hv\[sim\]"):
        require_mujoco()


def test_two_processes_give_the_same_bits() -> None:
    import subprocess

    script = (
        "from tests.physics.test_backend import IMAGE, LAYOUT, NAMES, ROBOT, BAD_SLOT\n"
        "from rcb4hv.project.run import run_motions\n"
        "run = run_motions(IMAGE, [BAD_SLOT], names=NAMES, robot=ROBOT, motion_layout=LAYOUT,"
        " sequence=False, track=True)\n"
        "print(repr(run.motions[0].outcome), [p.x.hex() for p in run.motions[0].track])\n"
    )
    outs = [
        subprocess.run(
            [sys.executable, "-c", script], capture_output=True, text=True, check=True
        ).stdout
        for _ in range(2)
    ]
    assert outs[0] == outs[1]
    assert "on_front" in outs[0]
