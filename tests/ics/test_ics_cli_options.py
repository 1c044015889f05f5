"""`rcb4hv ics`: the bus options are taken before the subcommand (on the group) and after it
(as the board commands take ``--port``); an option given after overrides the one before."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli

BUS = "icsemu://?ids=0,3"


@pytest.mark.parametrize(
    "args",
    [
        ["ics", "scan", "--port", BUS, "--json", "--ids", "0-5"],
        ["ics", "scan", "--ids", "0-5", "--json", "--port", BUS],
        ["ics", "--port", BUS, "--json", "scan", "--ids", "0-5"],
        ["ics", "--port", BUS, "scan", "--json", "--ids", "0-5"],
        ["ics", "--json", "scan", "--port", BUS, "--ids", "0-5"],
    ],
)
def test_port_and_json_before_or_after_the_subcommand(args: list[str]) -> None:
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 0, r.output
    assert json.loads(r.output) == {"ids": [0, 3]}


def test_an_option_after_the_subcommand_overrides_the_group_and_the_environment() -> None:
    runner = CliRunner()
    r = runner.invoke(cli, ["ics", "--port", "icsemu://?ids=1", "scan", "--port", BUS])
    assert r.exit_code == 0, r.output
    assert r.output.split() == ["0", "3"]
    r = runner.invoke(cli, ["ics", "scan", "--port", BUS], env={"RCB4HV_ICS_PORT": "/nonexistent"})
    assert r.exit_code == 0, r.output
    assert r.output.split() == ["0", "3"]
    r = runner.invoke(cli, ["ics", "scan"], env={"RCB4HV_ICS_PORT": "icsemu://?ids=5"})
    assert r.exit_code == 0, r.output
    assert r.output.split() == ["5"]


def test_a_subgroup_command_takes_them_too(tmp_path: Path) -> None:
    out = tmp_path / "servo3.json"
    r = CliRunner().invoke(
        cli, ["ics", "eeprom", "dump", "--port", "icsemu://?ids=3", "--json", "--id", "3", str(out)]
    )
    assert r.exit_code == 0, r.output
    assert json.loads(r.output)["id"] == 3
    assert json.loads(out.read_text())["servo_id"] == 3


def test_a_bad_value_after_the_subcommand_is_a_usage_error() -> None:
    r = CliRunner().invoke(cli, ["ics", "scan", "--port", BUS, "--baud", "9600"])
    assert r.exit_code == 2
    assert "Invalid value for '--baud'" in r.output


def test_an_id_change_with_json_needs_yes() -> None:
    """With --json there is no one to ask, and it renamed every servo on the wire unasked."""
    r = CliRunner().invoke(cli, ["ics", "--port", "icsemu://", "--json", "id", "--set", "5"])
    assert r.exit_code == 2 and "give --yes" in r.output, r.output
    r = CliRunner().invoke(
        cli, ["ics", "--port", "icsemu://", "--json", "id", "--set", "5", "--yes"]
    )
    assert r.exit_code == 0 and json.loads(r.output)["id"] == 5, r.output


def test_the_ics_tools_never_take_the_boards_port(monkeypatch: pytest.MonkeyPatch) -> None:
    """$RCB4HV_PORT is the board's: the ICS tools sent ICS bytes to an RCB-4 there."""
    monkeypatch.setenv("RCB4HV_PORT", "rcb4emu://")
    monkeypatch.delenv("RCB4HV_ICS_PORT", raising=False)
    monkeypatch.setattr("rcb4hv.transport.serial_port.find_kondo_ports", lambda: [])
    r = CliRunner().invoke(cli, ["ics", "scan"])
    assert r.exit_code == 1 and "$RCB4HV_ICS_PORT" in r.output and "icsemu://" in r.output


def test_two_servos_on_the_line_give_no_wrong_id() -> None:
    """Two servos answer an ID read at once and their answers AND into an ID neither has:
    `ics id` printed 0 with exit 0, and `--set` renamed both "from 0"."""
    for args in (["id"], ["id", "--set", "7", "--yes"]):
        r = CliRunner().invoke(cli, ["ics", "--port", "icsemu://?ids=1,2", *args])
        assert r.exit_code == 1 and "more than one servo on the line" in r.output, r.output
    r = CliRunner().invoke(cli, ["ics", "--port", "icsemu://?ids=3", "id"])
    assert r.exit_code == 0 and r.output.strip() == "3", r.output


@pytest.mark.parametrize(
    ("args", "said"),
    [(["set", "speed=0", "--live"], "speed 0 is not 1..127"), (["set", "reverse=2"], "flag")],
)
def test_a_setting_the_servo_cannot_hold_is_refused(args: list[str], said: str) -> None:
    """A live speed of 0 skipped the 1..127 check (and failed on the servo's silence); a
    reverse flag of 2 was stored as 1."""
    r = CliRunner().invoke(cli, ["ics", "--port", "icsemu://?ids=0", *args])
    assert r.exit_code == 1 and said in r.output, r.output
