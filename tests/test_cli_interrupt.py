"""Ctrl-C in any command: one line and exit status 130 (128 + SIGINT, what a shell reports),
not click's "Aborted!" and status 1; a ROM write says the ROM is partly written."""

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
