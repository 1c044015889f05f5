"""0Eh (ICS communication) on the board emulator: NAK without ``ics_comm``, the slot's servo
with it. Frames are built by hand from the command reference: ``09 0E ICS TXCOUNT TXL TXH
RXL RXH SUM`` (SUM = low byte of the sum of the bytes before it)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.ics import BoardIcsLink, IcsBus
from rcb4hv.ics.codec import join7

TX, RX = 0x0357, 0x0397


def frame(*body: int) -> bytes:
    b = bytes(body)
    return b + bytes((sum(b) & 0xFF,))


def move_to_ram(address: int, data: bytes) -> bytes:
    """00h MOVE, COM literal -> RAM: ``SIZE 00 02 AL AH 00 data SUM``."""
    return frame(7 + len(data), 0x00, 0x02, address & 0xFF, address >> 8, 0x00, *data)


def comm(ics: int, count: int, tx: int = TX, rx: int = RX) -> bytes:
    return frame(0x09, 0x0E, ics, count, tx & 0xFF, tx >> 8, rx & 0xFF, rx >> 8)


@pytest.fixture
def board_on() -> Iterator[Board]:
    board = Board(EmulatorConfig(ics_comm=True), clock=VirtualClock())
    board.run_for(1.0)  # the start-up program homes the servos
    yield board
    board.close()


def test_without_ics_comm_0eh_is_naked_as_before() -> None:
    board = Board(clock=VirtualClock())
    board.run_for(1.0)
    assert board.feed(move_to_ram(TX, bytes((0xA2, 0x05)))) == bytes.fromhex("04 00 06 0a")
    assert board.feed(comm(4, 2)) == bytes.fromhex("04 0e 15 27")
    assert board.ics_lines is None


def test_a_position_read_through_0eh_reports_the_servo_units_position(board_on: Board) -> None:
    # ICS 4 = ID 2 on SIO1-4; read position (ICS 3.6 sc 5)
    assert board_on.feed(move_to_ram(TX, bytes((0xA2, 0x05)))) == bytes.fromhex("04 00 06 0a")
    assert board_on.feed(comm(4, 2)) == bytes.fromhex("04 0e 06 18")
    state = board_on.servo_state(4)
    assert state is not None
    answer = board_on.ram[RX : RX + 4]
    assert answer[:2] == bytes((0x22, 0x05))
    assert join7(answer[2], answer[3]) == state.position


def test_no_answer_gives_the_nak(board_on: Board) -> None:
    board_on.feed(move_to_ram(TX, bytes((0xA4, 0x01))))  # ICS 8 = ID 4: not a virtual servo
    assert board_on.feed(comm(8, 2)) == bytes.fromhex("04 0e 15 27")
    board_on.feed(move_to_ram(TX, bytes((0xA2,))))  # half a command
    assert board_on.feed(comm(4, 1)) == bytes.fromhex("04 0e 15 27")


def test_the_line_is_the_ics_numbers_side(board_on: Board) -> None:
    board_on.feed(move_to_ram(TX, bytes((0xA2, 0x01))))
    assert board_on.feed(comm(5, 2)) == bytes.fromhex("04 0e 06 18")  # ID 2 on SIO5-8: ICS 5
    assert board_on.feed(comm(1, 2)) == bytes.fromhex("04 0e 06 18")  # any odd number: line 1
    board_on.feed(move_to_ram(TX, bytes((0xA0, 0x01))))  # ID 0 on SIO5-8 is ICS 1: absent
    assert board_on.feed(comm(1, 2)) == bytes.fromhex("04 0e 15 27")


def test_stretch_is_one_value_whichever_way_it_was_set(board_on: Board) -> None:
    # 12h SetStretch ICS 4 = 33, then read it through ICS
    assert board_on.feed(frame(0x0A, 0x12, 0x10, 0, 0, 0, 0, 0x01, 33)) == bytes.fromhex(
        "04 12 06 1c"
    )
    board_on.feed(move_to_ram(TX, bytes((0xA2, 0x01))))
    board_on.feed(comm(4, 2))
    assert board_on.ram[RX : RX + 3] == bytes((0x22, 0x01, 33))
    # an ICS write of speed reaches Board.speed_parameter (what physics reads)
    board_on.feed(move_to_ram(TX, bytes((0xC2, 0x02, 77))))
    assert board_on.feed(comm(4, 3)) == bytes.fromhex("04 0e 06 18")
    assert board_on.ram[RX : RX + 3] == bytes((0x42, 0x02, 77))
    assert board_on.speed_parameter[4] == 77


def test_an_ics_move_sets_the_slot_position(board_on: Board) -> None:
    board_on.feed(move_to_ram(TX, bytes((0x82, 0x3E, 0x40))))  # ID 2 -> 8000
    assert board_on.feed(comm(4, 3)) == bytes.fromhex("04 0e 06 18")
    lines = board_on.ics_lines
    assert lines is not None
    servo = lines.servo(4)
    assert servo is not None and servo.position(0.0) == 8000


def test_the_host_api_through_a_board(board_on: Board) -> None:
    from rcb4hv.emulator import emulator_url
    from rcb4hv.transport import SerialTransport

    url = emulator_url(board_on)
    with IcsBus(BoardIcsLink(SerialTransport.open(url), ics=4)) as bus:
        servo = bus.servo(2)
        assert servo.stretch() == 90
        assert servo.set_params(speed=50, live=True) == {"speed": (127, 50)}
        assert board_on.speed_parameter[4] == 50
        assert servo.eeprom().servo_id == 2
        assert bus.scan(range(6)) == [0, 1, 2, 3, 5]  # slots 0, 2, 4, 6, 10 of SIO1-4


@pytest.mark.parametrize("ics_comm", [False, True])
def test_rcb4hv_emulate_with_and_without_ics_comm_over_a_pty(ics_comm: bool) -> None:
    import signal
    import subprocess
    import sys

    import serial

    args = ["emulate", "--pty", *(["--ics-comm"] if ics_comm else [])]
    proc = subprocess.Popen(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout is not None
        path = proc.stdout.readline().split(" ", 1)[1].strip()
        port = serial.Serial(path, 115200, parity="E", timeout=2)
        try:
            port.write(move_to_ram(TX, bytes((0xA2, 0x05))))
            assert port.read(4) == bytes.fromhex("04 00 06 0a")
            port.write(comm(4, 2))
            reply = port.read(4)
            if not ics_comm:
                assert reply == bytes.fromhex("04 0e 15 27")
                return
            assert reply == bytes.fromhex("04 0e 06 18")
            port.write(frame(0x0A, 0x00, 0x20, 0x00, 0x00, 0x00, RX & 0xFF, RX >> 8, 4))
            answer = port.read(7)  # MOVE RAM -> COM: 07 00 + 4 bytes + SUM
            assert answer[2:4] == bytes((0x22, 0x05)) and 3500 <= join7(*answer[4:6]) <= 11500
        finally:
            port.close()
    finally:
        proc.send_signal(signal.SIGINT)
        proc.communicate(timeout=10)
    assert proc.returncode == 0


def test_the_cli_via_board() -> None:
    import json

    from click.testing import CliRunner

    from rcb4hv.cli.main import cli

    runner = CliRunner()
    base = ["ics", "--via-board", "--port", "rcb4emu://?ics_comm=1", "--line", "4", "--json"]
    got = runner.invoke(cli, [*base, "get", "--id", "2", "stretch"])
    assert got.exit_code == 0, got.output
    assert json.loads(got.output) == {"id": 2, "stretch": 90, "stretch_live": 90}
    live = runner.invoke(cli, [*base, "set", "--id", "2", "--live", "stretch=12"])
    assert json.loads(live.output) == {"id": 2, "changed": {"stretch": [90, 12]}}
    eeprom = runner.invoke(cli, [*base, "set", "--id", "2", "stretch=12"])
    assert eeprom.exit_code == 1 and "at most 64 bytes" in eeprom.output
    off = runner.invoke(cli, ["ics", "--via-board", "--port", "rcb4emu://", "--line", "4", "id"])
    assert off.exit_code == 1 and "IcsNoReply" in off.output


def test_via_board_on_an_ics_bus_says_it_is_not_a_board() -> None:
    """--via-board on an ICS bus: a clear error, not "size byte says 9 but the frame has 4
    bytes (FrameError)" from the bus's echo of the board frame."""
    from click.testing import CliRunner

    import rcb4hv.emulator as emu
    from rcb4hv.cli.main import cli
    from rcb4hv.emulator import RealClock
    from rcb4hv.errors import IcsError
    from rcb4hv.ics import EmulatedBus
    from rcb4hv.transport import SerialTransport

    got = CliRunner().invoke(cli, ["ics", "--port", "icsemu://", "--via-board", "scan"])
    assert got.exit_code == 2, got.output
    assert "icsemu:// is an ICS bus (servos), not a board" in got.output
    assert "FrameError" not in got.output
    # over a link whose URL says nothing (emulate-ics on TCP, an adapter in ICS mode): the echo
    bus = EmulatedBus.with_ids((0,), clock=RealClock())
    with emu.TcpServer(bus, "127.0.0.1", 0) as srv:
        url = f"socket://{srv.address[0]}:{srv.address[1]}"
        ics = IcsBus(BoardIcsLink(SerialTransport.open(url, 115200)))
        with ics, pytest.raises(IcsError, match="echoes the frame sent: an ICS bus") as info:
            ics.scan([0])
    assert "not a board, so --via-board does not apply" in str(info.value)


def test_a_scan_through_a_board_that_refuses_0eh_says_so() -> None:
    """Every 0Eh NAKed printed only "no servo answered": a user looks for absent servos."""
    from click.testing import CliRunner

    from rcb4hv.cli.main import cli

    r = CliRunner().invoke(
        cli, ["ics", "--port", "rcb4emu://", "--via-board", "--line", "4", "scan", "--ids", "0-3"]
    )
    assert r.exit_code == 0 and r.stdout == "no servo answered\n"
    assert "a board that does not serve 0Eh" in r.stderr and "--ics-comm" in r.stderr


def test_via_board_leaves_a_heart_to_heart_program_as_it_found_it(kxr_project_path: Path) -> None:
    """0Eh's scratch RAM is HeartToHeart4's vector-jump table (its button bindings): the link
    pauses the program, saves the bytes and puts both back. Before, a scan through the board
    left ICS replies in the table, and the running program jumped into the walk bound to UP
    (motion 9 of the fixture) with no button pressed."""
    from rcb4hv.emulator import emulator_url
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.image import build_project_image
    from rcb4hv.transport import SerialTransport

    image = build_project_image(load_project(kxr_project_path))
    board = Board(EmulatorConfig(ics_comm=True), clock=VirtualClock(), rom_image=image)
    try:
        board.run_for(2.0)  # the start-up motion, then the main loop reading the remote
        table = bytes(board.ram[TX : TX + 130])
        sysreg = bytes(board.ram[0:2])
        assert sysreg[0] & 0x0A == 0x0A  # ROM_F and VEC_F: the program runs, vector jumps on
        with IcsBus(BoardIcsLink(SerialTransport.open(emulator_url(board)), ics=4)) as bus:
            assert bus.scan(range(4))
            assert bus.servo(2).stretch() > 0
        assert bytes(board.ram[TX : TX + 130]) == table
        assert bytes(board.ram[0:2]) == sysreg
        board.run_for(1.0)
        assert board.ram[5] == 0, "the program called a motion: no button was pressed"
    finally:
        board.close()
