"""A robot without a project: robot_board's allocation survives the board running, and the
KHR-3HV model stands and answers servo commands through physics."""

from __future__ import annotations

import math

from rcb4hv.physics import PhysicsBackend, PhysicsWorld
from rcb4hv.physics.standalone import robot_board
from rcb4hv.protocol import POSITION_FREE, RunSingleServo
from rcb4hv.protocol.memory import SERVO
from rcb4hv.robot.builtin import load_builtin


def test_the_board_keeps_the_robots_servos_while_it_runs() -> None:
    robot = load_builtin("khr3hv-22")
    board = robot_board(robot)
    board.run_for(2.0)
    assert sorted(board.servo_outputs()) == list(robot.indices)


def test_each_servo_block_is_where_heart_to_heart4_puts_it() -> None:
    robot = load_builtin("khr3hv-22")
    board = robot_board(robot)
    assert {n: board.alloc(n) for n in robot.indices} == {n: 0x0090 + 20 * n for n in robot.indices}
    assert all(board.ram[board.alloc(n) + SERVO.ID] == n // 2 for n in robot.indices)


def test_a_khr3hv_stands_and_its_freed_elbow_drops() -> None:
    robot = load_builtin("khr3hv")
    board = robot_board(robot)
    world = PhysicsWorld(robot)
    world.place({})
    PhysicsBackend(board, world)
    elbow = robot.servo_for_joint("l_elbow_pitch")
    assert elbow is not None
    board.feed(
        RunSingleServo(elbow.index, 20, robot.motion_value(elbow.index, -math.pi / 2)).encode()
    )
    board.run_for(1.0)
    held = board.servo_state(elbow.index)
    assert held is not None and held.torque
    assert abs(math.degrees(robot.angle(elbow.index, held.position, 0)) + 90) < 5
    board.feed(RunSingleServo(elbow.index, 1, POSITION_FREE).encode())
    board.run_for(2.0)
    free = board.servo_state(elbow.index)
    assert free is not None and not free.torque
    assert abs(math.degrees(robot.angle(elbow.index, free.position, 0))) < 30
    assert math.degrees(world.base().tilt) < 5
