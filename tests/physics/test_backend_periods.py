"""The backend's per-period shortcuts (physics/backend.py) answer as the rules they stand for:
the positions it reports are ``RobotModel.value`` of the joint angles, and a servo left alone
because its inputs did not change still follows a change of stretch."""

from __future__ import annotations

import math
from dataclasses import replace

from rcb4hv.project.physics_sim import PhysicsSimulator
from rcb4hv.protocol import POSITION_FREE, RunSingleServo, SetStretch
from rcb4hv.protocol.memory import SERVO
from tests.physics.test_backend import ARMS_SLOT, IMAGE, LAYOUT, ROBOT

ELBOW = 6  # r_elbow, held at -90° (forearm forward) by ARMS_SLOT


def test_reported_positions_are_the_models_values() -> None:
    # offsets and signs of every kind, so the written-out formula meets all of its terms
    robot = replace(
        ROBOT,
        servos=tuple(
            replace(s, offset=(s.index % 5 - 2) * 37, sign=-s.sign if s.index % 3 else s.sign)
            for s in ROBOT.servos
        ),
    )
    sim = PhysicsSimulator(IMAGE, robot, motion_layout=LAYOUT)
    sim.boot()
    sim.play(LAYOUT.address(ARMS_SLOT))
    sim.board.feed(RunSingleServo(ELBOW, 1, POSITION_FREE).encode())
    sim.run_us(300_000)  # the forearm is falling: an angle between the held ones
    board = sim.board
    checked = 0
    for s in robot.servos:
        state = board.servo_state(s.index)
        assert state is not None
        trim = SERVO.F_BASE.get(board.ram, board.alloc(s.index))
        angle = sim.world.servo_angle(s.index)
        assert state.position == robot.value(s.index, angle, trim), s.joint
        checked += abs(math.degrees(angle)) > 1.0
    assert checked >= 2


def _sag(sim: PhysicsSimulator) -> float:
    return abs(math.degrees(sim.world.servo_angle(ELBOW)) + 90.0)


def test_a_held_servo_follows_a_new_stretch() -> None:
    sim = PhysicsSimulator(IMAGE, ROBOT, motion_layout=LAYOUT)
    sim.boot()
    sim.play(LAYOUT.address(ARMS_SLOT))  # held, its target reached, for a second
    stiff = _sag(sim)
    sim.board.feed(SetStretch({ELBOW: 5}).encode())  # only the stretch changes
    sim.run_us(1_000_000)
    assert _sag(sim) > 3 * stiff
