"""The board commands from the shell: Ctrl-C in any command gives one line and exit status
130 (128 + SIGINT, what a shell reports), not click's "Aborted!" and 1; a ROM write says the
ROM is partly written; `ping -n N` counts lost replies as ping does."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.client import Robot


def _interrupt(*_args: object, **_kwargs: object) -> None:
    raise KeyboardInterrupt


def test_ctrl_c_in_a_command_exits_130(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(Robot, "ping", _interrupt)
    r = CliRunner().invoke(cli, ["ping", "--port", "rcb4emu://"])
    assert r.exit_code == 130, r.output
    assert "interrupted" in r.output and "Aborted" not in r.output


def test_ctrl_c_in_a_rom_write_says_the_rom_is_partly_written(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    image = tmp_path / "part.bin"
    image.write_bytes(bytes(256))
    monkeypatch.setattr(Robot, "write_rom", _interrupt)
    r = CliRunner().invoke(cli, ["rom", "write", "0x1000", str(image), "--port", "rcb4emu://"])
    assert r.exit_code == 130, r.output
    assert "the ROM from 001000 is partly written" in r.output


def test_ping_goes_on_past_a_lost_reply_and_counts_it() -> None:
    """`ping -n 8` on a link that drops replies stopped at the first lost one; it goes on as
    ping does, and the times leave out the wait for a reply that never came."""
    port = "fault://drop_reply=0.3,seed=3@rcb4emu://"
    r = CliRunner().invoke(cli, ["ping", "--port", port, "-n", "8", "--timeout", "0.1"])
    assert r.exit_code == 0, r.output
    assert "5 ACKs from" in r.output and "; 3 of 8 lost" in r.output
    assert float(r.output.split("max ")[1].split(" ms")[0]) < 50.0
    port = "fault://drop_reply=1@rcb4emu://"
    r = CliRunner().invoke(cli, ["ping", "--port", port, "-n", "3", "--timeout", "0.05"])
    assert r.exit_code == 1 and "no ACK from" in r.output and "in 3 checks" in r.output
