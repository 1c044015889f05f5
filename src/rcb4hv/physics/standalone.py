"""A robot with no project: an emulated board set up by host frames for a model's servos.

:func:`robot_board` gives an emulated :class:`~rcb4hv.emulator.Board` on a virtual clock with
a servo block for every servo the model maps, where HeartToHeart4 puts it (the block of ICS
number n at 0090h + 20·n, :meth:`rcb4hv.protocol.memory.ADDR.servo_block`; the servo's ICS ID
is n // 2), each holding the model's joint angle 0, servo output on and the ROM
program stopped (it would install its own allocation table). It is
set up the way a host would, through real MOVE frames, so it can be driven with servo
commands (or a host client) and given a :class:`~rcb4hv.physics.PhysicsBackend`: the
benchmarks and tests use it, and so can a view that previews a robot without a project.
"""

from __future__ import annotations

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.errors import SimulationError
from rcb4hv.protocol import ICS_COUNT, Ack, Command, Data, Move, Ram, decode_reply, encode_command
from rcb4hv.protocol.memory import ADDR, SYS, ServoBlock, pack_alloc
from rcb4hv.robot.model import RobotModel

__all__ = ["robot_board"]


def _send(board: Board, cmd: Command) -> None:
    reply = decode_reply(board.feed(encode_command(cmd)), cmd)
    if not isinstance(reply, Ack):
        raise SimulationError(f"the board refused {cmd!r}")


def robot_board(model: RobotModel) -> Board:
    """An emulated board driving ``model``'s servos (see the module docstring)."""
    indices = model.indices
    board = Board(EmulatorConfig(virtual_servos=indices), clock=VirtualClock())
    table: list[int | None] = [None] * ICS_COUNT
    for index in indices:
        address = ADDR.servo_block(index)
        table[index] = address
        centre = model.motion_value(index, 0.0)
        block = ServoBlock(ics_id=index // 2, measured=centre, output=centre, end=centre)
        _send(board, Move(Ram(address), Data(block.to_bytes())))
    _send(board, Move(Ram(ADDR.ICS_ALLOC), Data(pack_alloc(table))))
    # servo output on; the ROM program and vector jumps off, so the board's own start-up
    # program never replaces this allocation table (the host drives the servos)
    word = (board.system_register | SYS.ICS_OUTPUT) & ~(SYS.ROM_RUN | SYS.VECTOR_JUMP)
    _send(board, Move(Ram(ADDR.SYSTEM), Data(word.to_bytes(2, "little"))))
    return board
