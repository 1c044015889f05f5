"""The CLI's shared pieces: address / integer / baud parameter types and the connection
object every board command receives (``click.make_pass_decorator``)."""

from __future__ import annotations

import json
from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from rcb4hv.cli._util import ADDRESS, BAUD, INTEGER, Connection, pass_connection
from rcb4hv.cli.main import cli
from rcb4hv.client import DEFAULT_TIMEOUT
from rcb4hv.hth4.newproject import mixing_source
from rcb4hv.transport import DEFAULT_BAUD


@pytest.mark.parametrize(
    "text", ["0B80h", "0b80H", "0x0B80", "2944", "2_944", "$0B80", "$000b80", " 0B80h ", 2944]
)
def test_address_forms(text: str | int) -> None:
    assert ADDRESS.convert(text, None, None) == 0x0B80


@pytest.mark.parametrize("text", ["", "B80", "0x", "12hh", "1.5", "$", "h", "$12h", "0010"])
def test_bad_numbers_are_usage_errors(text: str) -> None:
    with pytest.raises(click.BadParameter, match=r"is not a number \(decimal, 0x.., ..h or \$..\)"):
        INTEGER.convert(text, None, None)
    with pytest.raises(click.BadParameter, match=r"is not an address \(decimal, 0x.., ..h or \$"):
        ADDRESS.convert(text, None, None)


def test_every_command_that_takes_an_address_reads_every_form(tmp_path: Path) -> None:
    """docs/cli.md says addresses take decimal, 0x.. or ..h: `disasm --origin 4B80h` and
    `asm --origin 4B80h` were refused (asm_cmd had a parser of its own: 0x.., $.. or decimal)
    and `rom read '$4B80'` too (the board commands' parser took no $..)."""
    runner = CliRunner()
    frames = "03 0D 10"  # RETURN
    (tmp_path / "m.bin").write_bytes(bytes.fromhex(frames))
    (tmp_path / "m.s").write_text("RETURN\n")
    for rom, ram in zip(
        ("4B80h", "0x4B80", "$004B80", "19328"), ("0380h", "0x0380", "$0380", "896"), strict=True
    ):
        for args in (
            ["disasm", "--bin", str(tmp_path / "m.bin"), "--origin", rom],
            ["disasm", "--origin", rom, frames],
            ["asm", str(tmp_path / "m.s"), "--origin", rom],
            ["rom", "read", rom, "3", "--port", "rcb4emu://"],
            ["ram", "read", ram, "2", "--port", "rcb4emu://", "--json"],
        ):
            r = runner.invoke(cli, args)
            assert r.exit_code == 0, (args, r.output)
            if args[0] == "ram":
                assert json.loads(r.stdout)["address"] == 0x0380, args
            else:
                assert "004B80" in r.stdout, (args, r.stdout)
    # one parser, so one message; each command keeps its own range check
    for args in (["disasm", "--origin", "zz", frames], ["rom", "read", "zz", "--port", "x"]):
        r = runner.invoke(cli, args)
        assert r.exit_code == 2 and "is not an address (decimal, 0x.., ..h or $..)" in r.output
    r = runner.invoke(cli, ["disasm", "--origin", "40000h", frames])
    assert r.exit_code == 1 and "origin 0x40000 outside ROM" in r.output
    r = runner.invoke(cli, ["rom", "read", "$40000", "4", "--port", "rcb4emu://"])
    assert r.exit_code == 1 and "runs outside 0..0x3ffff" in r.output
    assert mixing_source("$24") == mixing_source("24h") == mixing_source("0x24") == 0x24


def test_baud_type() -> None:
    assert BAUD.convert("auto", None, None) is None
    assert BAUD.convert("625000", None, None) == 625000
    with pytest.raises(click.BadParameter, match="is not one of"):
        BAUD.convert("9600", None, None)
    with pytest.raises(click.BadParameter, match="not a baud rate"):
        BAUD.convert("fast", None, None)


def test_a_bad_baud_is_refused_before_any_port_is_opened() -> None:
    r = CliRunner().invoke(cli, ["ping", "--port", "/nonexistent/tty", "--baud", "9600"])
    assert r.exit_code == 2
    assert "Invalid value for '--baud': 9600 is not one of" in r.output


def test_pass_connection_hands_the_options_to_the_command() -> None:
    seen: list[tuple[Connection, int]] = []

    @click.command()
    @pass_connection
    @click.option("--n", type=INTEGER, default=1)
    def probe(conn: Connection, n: int) -> None:
        assert click.get_current_context().obj is conn
        seen.append((conn, n))

    runner = CliRunner()
    r = runner.invoke(probe, ["--port", "rcb4emu://", "--baud", "auto", "--n", "0x10"])
    assert r.exit_code == 0, r.output
    assert seen[-1] == (Connection("rcb4emu://", None, DEFAULT_TIMEOUT), 16)
    r = runner.invoke(probe, ["--timeout", "2"], env={"RCB4HV_PORT": "socket://h:1"})
    assert r.exit_code == 0, r.output
    assert seen[-1] == (Connection("socket://h:1", DEFAULT_BAUD, 2.0), 1)


def test_board_commands_read_addresses_in_any_form() -> None:
    runner = CliRunner()
    outs = [
        runner.invoke(cli, ["ram", "read", a, "2", "--port", "rcb4emu://", "--json"])
        for a in ("0350h", "0x0350", "848")
    ]
    assert [r.exit_code for r in outs] == [0, 0, 0], [r.output for r in outs]
    assert outs[0].output == outs[1].output == outs[2].output


def test_a_sequence_takes_the_slots_of_the_images_layout() -> None:
    from rcb4hv.cli.project_physics import parse_sequence
    from rcb4hv.rom.layout import LAYOUTS

    assert parse_sequence("33, 15,120", LAYOUTS["2.2"]) == [33, 15, 120]
    assert parse_sequence("50,1", LAYOUTS["1.3"]) == [50, 1]
    with pytest.raises(click.BadParameter, match=r"motion slots are 1-50 \(HeartToHeart4 1.3"):
        parse_sequence("33,51", LAYOUTS["1.3"])
    with pytest.raises(click.BadParameter, match="motion slots are 1-120"):
        parse_sequence("0", LAYOUTS["2.2"])
    with pytest.raises(click.BadParameter, match="separated by commas"):
        parse_sequence("a,b", LAYOUTS["2.2"])


@pytest.mark.parametrize(
    ("args", "said"),
    [
        (["robot", "ik", "kxr-l2", "--link", "l_foot", "--pos", "nan", "0", "0"], "finite"),
        (["robot", "ik", "kxr-l2", "--link", "l_foot", "--pos", "0", "inf", "0"], "finite"),
        (["project", "robust", "{fx}", "--seed", "-5", "--motion", "39"], "x>=0"),
        (["project", "simulate", "{fx}", "--physics", "--sequence", "9,,13"], "commas"),
    ],
)
def test_numbers_that_mean_nothing_are_refused(
    args: list[str], said: str, kxr_project_path: Path
) -> None:
    """A nan target exited 0, a negative seed gave numpy's message, an empty slot in a
    sequence was skipped."""
    r = CliRunner().invoke(cli, [a.format(fx=kxr_project_path) for a in args])
    assert r.exit_code == 2 and said in r.output, r.output


def test_a_list_given_to_a_repeatable_option_says_how_to_repeat_it(tmp_path: Path) -> None:
    # click's repeatable options take one value each: `--motion 9 10` leaves 10 over
    (tmp_path / "x.h4p").write_text("")
    r = CliRunner().invoke(
        cli, ["project", "simulate", str(tmp_path / "x.h4p"), "--motion", "9", "10", "11"]
    )
    assert r.exit_code == 2
    assert "unexpected extra arguments (10 11)" in r.output
    assert "--motion 9 --motion 10 --motion 11" in r.output
    # an extra argument after an option that takes one value gets no such hint
    r = CliRunner().invoke(cli, ["project", "simulate", str(tmp_path / "x.h4p"), "--json", "9"])
    assert r.exit_code == 2
    assert "unexpected extra argument (9)" in r.output
    assert "repeat" not in r.output
