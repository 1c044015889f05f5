"""``Robot`` uses the layout the board holds: read from its ROM unless given."""

from __future__ import annotations

import json

import pytest

from rcb4hv.client import Rcb4Client, Robot
from rcb4hv.emulator import emulator_url
from rcb4hv.errors import TransportError
from rcb4hv.rom.layout import HTH4_22, LAYOUTS

from .conftest import make_board
from .test_client_golden import H, ScriptedTransport


def test_detection_reads_the_two_main_loop_starts() -> None:
    rom_reply_03fd = bytes([12, 0]) + H("09 00 02 00 00 00 9B C0 66")  # a register write
    rom_reply_044b = bytes([12, 0]) + H("1E 04 00 00 FF FF FF FF FF")
    rom_reply_03fd += bytes([sum(rom_reply_03fd) & 0xFF])
    rom_reply_044b += bytes([sum(rom_reply_044b) & 0xFF])
    t = ScriptedTransport(rom_reply_03fd, rom_reply_044b)
    robot = Robot(Rcb4Client(t, timeout=0.2))
    assert robot.layout is None
    assert robot.board_layout() == LAYOUTS["2.1"]
    assert t.writes == [
        H("0B 00 23 00 00 00 FD 03 00 09 37"),  # read 9 ROM bytes at 0003FDh
        H("0B 00 23 00 00 00 4B 04 00 09 86"),  # and at 00044Bh
    ]
    assert robot.board_layout() == LAYOUTS["2.1"] and len(t.writes) == 2  # read once


def test_unknown_rom_falls_back_to_2_2() -> None:
    erased = bytes([12, 0]) + b"\xff" * 9
    erased += bytes([sum(erased) & 0xFF])
    t = ScriptedTransport(erased, erased)
    assert Robot(Rcb4Client(t, timeout=0.2)).board_layout() == HTH4_22


@pytest.mark.parametrize("version", ["2.2", "2.1", "1.3"])
def test_robot_plays_motions_on_an_emulated_board_of_each_layout(version: str) -> None:
    lay = LAYOUTS[version]
    given = lay if version == "1.3" else None  # 1.3 cannot be told from 2.1 by the ROM reads
    board = make_board(lay)  # virtual time, moved by the robot's requests
    with Robot.open(emulator_url(board), layout=given) as robot:
        robot.wait_ready()
        assert robot.board_layout() == lay
        robot.play_motion(2)
        assert robot.current_motion() == 2
        assert robot.motion_status().pc >= lay.address(2)
        robot.wait_motion(timeout=5.0)
        assert robot.current_motion() is None
        assert lay.main_loop <= robot.motion_status().pc < lay.motion_base


def test_bad_layout_in_the_url() -> None:
    with pytest.raises(TransportError, match=r"unknown layout '9\.9'"):
        Robot.open("rcb4emu://?layout=9.9")


@pytest.mark.parametrize("url", ["rcb4emu://?speed=10&speed=0.001", "icsemu://?ids=0&ids=1"])
def test_a_setting_given_twice_in_an_emulator_url_is_refused(url: str) -> None:
    """The last one won in silence."""
    from rcb4hv.transport import SerialTransport

    with pytest.raises(TransportError, match="is given twice"):
        SerialTransport.open(url)


def test_cli_motion_play_reads_the_layout_or_takes_it() -> None:
    from click.testing import CliRunner

    from rcb4hv.cli.main import cli

    board21, board13 = make_board(LAYOUTS["2.1"]), make_board(LAYOUTS["1.3"])
    url = emulator_url(board21)
    r = CliRunner().invoke(cli, ["motion", "play", "--port", url, "2", "--wait"])
    assert r.exit_code == 0, r.output
    assert "playing motion 2 (0013B8)" in r.output and "ended" in r.output
    url13 = emulator_url(board13)
    r = CliRunner().invoke(cli, ["motion", "play", "--port", url13, "2", "--layout", "1.3"])
    assert r.exit_code == 0 and "playing motion 2 (001EB8)" in r.output
    r = CliRunner().invoke(cli, ["motion", "status", "--port", url, "--json"])
    assert r.exit_code == 0, r.output
    status = json.loads(r.output)
    assert status["running"] is False and int(status["pc"], 16) < LAYOUTS["2.1"].motion_base
