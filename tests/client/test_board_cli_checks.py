"""What `rcb4hv motion play` and `rcb4hv servo move` report: a slot that holds no motion, and a
position outside the documented range in the command line's words."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from click.testing import CliRunner, Result

from rcb4hv.cli.main import cli
from rcb4hv.client import Robot
from rcb4hv.emulator import emulator_url
from rcb4hv.errors import ArgumentError
from tests.client.conftest import make_board

EMPTY_SLOT = 18  # the default image holds motions in slots 1-17 only


def _run(*args: str) -> Result:
    return CliRunner().invoke(cli, list(args), catch_exceptions=False)


@pytest.fixture
def board_url() -> Iterator[str]:
    """A board the commands share (`motion status` sees what `motion play` left), on virtual
    time that moves 5 ms a request: motion 1 (0.6 s) still plays when `motion play` returns."""
    board = make_board()
    board.step = 0.005
    yield emulator_url(board)
    board.close()


def _status(url: str) -> tuple[int | None, str]:
    """The motion and state the board's program is in, read by a Robot."""
    with Robot.open(url) as robot:
        st = robot.motion_status()
    return st.motion, st.state


def test_motion_play_reports_a_slot_that_holds_no_motion(board_url: str) -> None:
    """`motion play 18` printed "playing motion 18 (009380)" and exited 0 though the program
    had stopped with a ROM error there; only --wait said so."""
    r = _run("motion", "play", str(EMPTY_SLOT), "--port", board_url)
    assert r.exit_code == 1
    assert r.stdout == ""
    assert r.stderr.startswith(f"error: slot {EMPTY_SLOT} holds no motion: the board's program ")
    assert "ROM error at PC 009380" in r.stderr and "(ProgramStoppedError)" in r.stderr
    assert _status(board_url) == (EMPTY_SLOT, "stopped by a ROM error")
    assert _run("motion", "stop", "--port", board_url).exit_code == 0
    # a slot that holds a motion: exit 0 at once, without waiting for the motion's end
    r = _run("motion", "play", "1", "--port", board_url)
    assert r.exit_code == 0, r.output
    assert r.stdout == "playing motion 1 (000B80)\n"
    assert _status(board_url) == (1, "playing")


def test_motion_play_wait_still_waits_and_reports(board_url: str) -> None:
    r = _run("motion", "play", "1", "--wait", "--port", board_url)
    assert r.exit_code == 0, r.output
    assert r.stdout.startswith("playing motion 1 (000B80)\nmotion 1 ended after ")
    assert _status(board_url) == (None, "idle")
    r = _run("motion", "play", str(EMPTY_SLOT), "--wait", "--port", board_url)
    assert r.exit_code == 1 and f"slot {EMPTY_SLOT} holds no motion" in r.stderr


def test_motion_play_on_the_in_process_emulator() -> None:
    r = _run("motion", "play", str(EMPTY_SLOT), "--port", "rcb4emu://")
    assert r.exit_code == 1 and f"slot {EMPTY_SLOT} holds no motion" in r.stderr
    assert _run("motion", "play", "2", "--port", "rcb4emu://").exit_code == 0


@pytest.mark.parametrize("target", [["2=3000"], ["--deg", "2=-150"]])
def test_servo_move_out_of_range_names_the_option(target: list[str]) -> None:
    """The error said "pass check_range=False to send it anyway", a Python argument."""
    r = _run("servo", "move", "--port", "rcb4emu://", *target)
    assert r.exit_code == 1
    assert "outside 3500..11500 (pass --unchecked to send it anyway)" in r.stderr
    assert "check_range" not in r.stderr
    r = _run("servo", "move", "--port", "rcb4emu://", "--unchecked", "--no-wait", *target)
    assert r.exit_code == 0, r.output


def test_servo_move_checks_raw_positions_before_the_link_opens() -> None:
    r = _run("servo", "move", "--port", "/nonexistent/tty", "2=3000")
    assert r.exit_code == 1
    assert r.stderr == (
        "error: ICS 2: position 3000 outside 3500..11500 (pass --unchecked to send it anyway) "
        "(ArgumentError)\n"
    )


def test_the_python_api_still_names_its_argument() -> None:
    with pytest.raises(ArgumentError, match=r"\(pass check_range=False to send it anyway\)"):
        Robot.check_position(2, 3000)
    with Robot.open("rcb4emu://") as robot, pytest.raises(ArgumentError, match="check_range"):
        robot.move({2: 3000})


@pytest.mark.parametrize("value", ["inf", "nan", "7500.5"])
def test_servo_move_refuses_a_position_that_is_not_a_whole_number(value: str) -> None:
    """`servo move 2=inf` ended in an OverflowError traceback (round(inf)); 7500.5 was
    rounded in silence."""
    r = CliRunner().invoke(cli, ["servo", "move", "--port", "rcb4emu://", f"2={value}"])
    assert r.exit_code == 2 and "a position is a whole number of counts" in r.output, r.output


def test_motion_status_from_the_shell_sees_the_motion_a_shared_board_plays(
    board_url: str,
) -> None:
    """On `rcb4emu://?board=N` (a board already running in the process) every command first
    waited for the program to be back in its main loop, so `motion status` never saw a
    motion playing. Only a fresh in-process board is waited for (its start-up program)."""
    assert _run("motion", "play", "1", "--port", board_url).exit_code == 0
    r = _run("motion", "status", "--json", "--port", board_url)
    assert r.exit_code == 0, r.output
    assert '"motion": 1' in r.output, r.output
