"""A servo that does not answer: the error names it and the likely causes (absent, another
baud rate, an ICS 3.5 servo's missing position read) and keeps the raw bytes."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.errors import IcsNoReply
from rcb4hv.ics import IcsBus


def _error(args: list[str]) -> str:
    r = CliRunner().invoke(cli, ["ics", *args])
    assert r.exit_code == 1, r.output
    assert "(IcsNoReply)" in r.output
    return r.output


def test_an_absent_id_names_the_servo_and_the_baud_to_try() -> None:
    out = _error(["--port", "icsemu://?ids=0", "get", "--id", "5"])
    assert "servo 5 does not answer" in out
    assert "absent, or at another baud rate than 115200: try --baud 625000 or 1250000" in out
    assert "a5 00" in out  # the raw command, for debugging


def test_a_wrong_baud_says_no_servo_answers_the_id_read() -> None:
    out = _error(["--port", "icsemu://?ids=0", "--baud", "625000", "get"])
    assert "no servo answers the ID read" in out
    assert "try --baud 115200 or 1250000" in out
    assert "ff 00 00 00" in out


def test_an_ics35_servo_is_told_it_has_no_position_read() -> None:
    out = _error(["--port", "icsemu://?ids=0&version=3.5", "position"])
    assert "servo 0 answers, but not the position read: an ICS 3.5 servo has none" in out
    assert "a0 05" in out
    # an absent ID: the 3.5 servo is one of the possible causes
    out = _error(["--port", "icsemu://?ids=0", "position", "--id", "4"])
    assert "servo 4 does not answer" in out and "ICS 3.5" in out


def test_the_python_api_raises_the_same_type_without_the_cli_option() -> None:
    with IcsBus.open("icsemu://?ids=0") as bus, pytest.raises(IcsNoReply) as info:
        bus.servo(7).stretch()
    text = str(info.value)
    assert text.startswith("servo 7 does not answer (absent, or at another baud rate than 115200")
    assert "try 625000 or 1250000" in text and "--baud" not in text
    assert "no reply to a7 01, got nothing" in text


def test_through_a_board_the_nak_names_the_servo_and_the_line() -> None:
    out = _error(["--via-board", "--port", "rcb4emu://", "--line", "4", "get", "--id", "3"])
    assert "servo 3 does not answer on the SIO line of ICS 4" in out
    assert "0Eh: NAK" in out and "a3 00" in out


def test_two_servos_answering_the_id_read_are_named_not_renamed() -> None:
    """IDs 1 and 3 AND into 1, a servo on the bus: the read looked right and `id --set 5`
    renamed both. The read probes the IDs a second servo could have (those holding 1's bit)."""
    from rcb4hv.errors import IcsError

    with IcsBus.open("icsemu://?ids=1,3") as bus:
        with pytest.raises(IcsError, match="servos 1, 3 answer"):
            bus.read_id()
        assert bus.scan(range(6)) == [1, 3]  # nothing renamed
    with IcsBus.open("icsemu://?ids=3") as bus:
        assert bus.read_id() == 3
