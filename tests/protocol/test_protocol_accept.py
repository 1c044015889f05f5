"""The wire layer accepts every frame the firmware accepts (issue: real HeartToHeart4 projects).

Where the spec reserves no bits, any byte value decodes, re-encodes byte for byte and runs in
the emulator without a NAK - from COM and from ROM. Documented ranges (stretch 1-127, speeds
1-255, positions 3500-11500) are checked at the robot level and by the project lint only.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import protocol as p
from rcb4hv.asm import assemble, disassemble
from rcb4hv.client import Robot
from rcb4hv.emulator import Board, VirtualClock
from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.memory import SYS
from rcb4hv.rom import layout

# a SetStretch frame from a real HeartToHeart4 motion: ICS 18 and 19 get stretch 0
REAL_12H = bytes.fromhex(
    "21 12 FC FF CF 43 01 01 14 14 14 14 41 41 41 41 41 41 41 41 41 41 41 41 00 00 14 14 41 41"
    " 14 14 70"
)


def _frame(body: bytes) -> bytes:
    """SIZE + body + SUM."""
    head = bytes((len(body) + 2,)) + body
    return head + bytes((sum(head) & 0xFF,))


masks = st.integers(0, (1 << 36) - 1)


def _ics_of(mask: int) -> list[int]:
    return [k for k in range(36) if mask >> k & 1]


@st.composite
def servo_frames(draw: st.DrawFn) -> bytes:
    """Any 0Fh, 10h or 12h frame with a valid checksum and structure, values unrestricted."""
    kind = draw(st.sampled_from((0x0F, 0x10, 0x12)))
    if kind == 0x0F:
        return _frame(bytes((0x0F, *draw(st.binary(min_size=4, max_size=4)))))
    mask = draw(masks)
    n = len(_ics_of(mask))
    if kind == 0x10:
        flag = draw(st.booleans()) << 39
        bitmap = (mask | flag).to_bytes(5, "little")
        rest = draw(st.binary(min_size=1 + 2 * n, max_size=1 + 2 * n))
        return _frame(bytes((0x10,)) + bitmap + rest)
    sub = draw(st.sampled_from((1, 2)))
    values = draw(st.binary(min_size=n, max_size=n))
    return _frame(bytes((0x12,)) + mask.to_bytes(5, "little") + bytes((sub,)) + values)


_BOARD: list[Board] = []


def _board() -> Board:
    """One booted default board shared by the examples (replies do not depend on history)."""
    if not _BOARD:
        b = Board(clock=VirtualClock())
        b.run_for(3.0)
        _BOARD.append(b)
    return _BOARD[0]


def test_real_stretch_zero_frame_decodes_and_runs() -> None:
    cmd = p.decode_command(REAL_12H)
    assert isinstance(cmd, p.SetStretch)
    assert dict(cmd.values)[18] == 0 and dict(cmd.values)[19] == 0
    assert p.encode_command(cmd) == REAL_12H
    board = Board(clock=VirtualClock())
    board.run_for(3.0)
    assert board.feed(REAL_12H) == bytes.fromhex("04 12 06 1C")
    assert board.stretch[18] == 0 and board.stretch[2] == 0x14


@given(servo_frames())
def test_any_servo_frame_decodes_reencodes_and_is_acked(frame: bytes) -> None:
    cmd = p.decode_command(frame)
    assert p.encode_command(cmd) == frame
    assert p.decode_command(p.encode_command(cmd)) == cmd
    reply = _board().feed(frame)
    assert reply == p.encode_reply(p.Ack(frame[1])), (frame.hex(" "), reply.hex(" "))


@given(servo_frames())
def test_any_servo_frame_survives_the_assembler(frame: bytes) -> None:
    text = disassemble(frame, layout.MOTIONS)
    assert ".byte" not in text
    assert assemble(text, origin=layout.MOTIONS).data == frame


@settings(max_examples=60)
@given(st.lists(servo_frames(), min_size=1, max_size=4))
def test_any_servo_frame_runs_from_rom(frames: list[bytes]) -> None:
    board = _board()
    code = b"".join(frames) + p.encode_command(p.Return())
    board.load_rom(layout.MOTIONS, code)
    # spec 11.4: suspend, PC to the main loop, CALL the motion, resume
    board.feed(p.encode_command(p.Move(p.Ram(0), p.Data(b"\x00\x00"))))
    board.feed(p.encode_command(p.Move(p.Ram(2), p.Data(layout.MAIN_LOOP.to_bytes(3, "little")))))
    board.feed(p.encode_command(p.Move(p.Ram(5), p.Data(bytes(7)))))
    assert board.feed(p.encode_command(p.Call(layout.MOTIONS))) == bytes.fromhex("04 0C 06 16")
    resume = (SYS.ICS_OUTPUT | SYS.ROM_RUN).to_bytes(2, "little")
    board.feed(p.encode_command(p.Move(p.Ram(0), p.Data(resume))))
    for _ in range(len(frames) * 14 + 2):  # each pose lasts at most 255 x 25 ms
        if board.ram[5] == 0 or not board.system_register & SYS.ROM_RUN:
            break
        board.run_for(0.5)
    sysreg = board.system_register
    assert sysreg & SYS.ROM_RUN and not sysreg & SYS.ROM_ERROR
    assert board.ram[5] == 0 and board.pc < layout.MOTIONS


@pytest.mark.parametrize(
    ("frame", "why"),
    [
        ("0D 10 01 02 00 00 70 0A 4C 1D 40 1F 52", "M4 bits 4-6"),  # reserved bitmap bits
        ("09 12 00 00 00 00 80 01 00", "M4 bit 7"),  # 12h has no update flag
        ("0A 12 01 00 00 00 00 03 05 25", "sub-command"),  # neither stretch nor speed
        ("07 0B 4B 04 00 15 76", "bits 7-4"),  # reserved condition bits
    ],
)
def test_reserved_bits_are_still_refused(frame: str, why: str) -> None:
    data = bytes.fromhex(frame)
    fixed = data[:-1] + bytes((sum(data[:-1]) & 0xFF,))
    with pytest.raises(ProtocolError, match=why):
        p.decode_command(fixed)


def test_documented_ranges_move_to_the_robot_level() -> None:
    # wire level: any byte
    assert p.SetStretch({0: 0, 1: 200}).values == ((0, 0), (1, 200))
    assert p.RunSingleServo(100, 0, 2100).ics == 100
    with Robot.open("rcb4emu://?speed=20") as robot:
        robot.wait_ready()
        with pytest.raises(ValueError, match=r"stretch 0 outside 1\.\.127"):
            robot.set_stretch({2: 0})
        with pytest.raises(ValueError, match=r"speed 128 outside 1\.\.127"):
            robot.set_speed({2: 128})
        with pytest.raises(ValueError, match="ICS number 36"):
            robot.set_stretch({36: 10}, check_range=False)
        with pytest.raises(ValueError, match=r"position 2100 outside 3500\.\.11500"):
            robot.move({2: 2100})
        robot.set_stretch({2: 0}, check_range=False)  # what real projects send
        robot.set_speed(0, [2, 3], check_range=False)


def test_single_servo_beyond_ics_35_is_skipped_like_an_unallocated_slot() -> None:
    board = Board(clock=VirtualClock())
    board.run_for(3.0)
    board.feed(p.encode_command(p.RunSingleServo(2, 200, 9000)))  # ICS 2 moving: its flag set
    assert board.ram[7] & 0b100
    frame = _frame(bytes.fromhex("0F 64 00 B4 0B"))  # ICS 100, speed 0, position 3000
    assert frame == bytes.fromhex("07 0F 64 00 B4 0B 39")
    assert board.feed(frame) == bytes.fromhex("04 0F 06 19")
    assert board.ram[7:12] == bytes(5)  # 0Fh with the flag bit clear: every other flag cleared


def test_decode_cli_prints_a_real_stretch_zero_frame() -> None:
    from click.testing import CliRunner

    from rcb4hv.cli.main import cli

    r = CliRunner().invoke(cli, ["decode", REAL_12H.hex(" ")])
    assert r.exit_code == 0, r.output
    assert "SetStretch" in r.output and "ICS 18: 0" in r.output
