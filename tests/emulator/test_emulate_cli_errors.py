"""``rcb4hv emulate`` / ``emulate-ics`` that cannot start: one ``error: ...`` line and exit
status 1, as every other command, never a traceback."""

from __future__ import annotations

import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from rcb4hv.cli.main import cli
from rcb4hv.rom import layout


def _fails_with_one_line(r: Result, *parts: str) -> str:
    assert r.exit_code == 1, r.output
    assert isinstance(r.exception, SystemExit), r.exception  # handled, not a crash
    assert "Traceback" not in r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), r.output
    for part in parts:
        assert part in lines[0], lines[0]
    return lines[0]


@pytest.fixture
def port_in_use() -> Iterator[int]:
    with socket.create_server(("127.0.0.1", 0)) as s:
        yield s.getsockname()[1]


@pytest.mark.parametrize("command", ["emulate", "emulate-ics"])
def test_an_address_of_no_interface(command: str) -> None:
    r = CliRunner().invoke(cli, [command, "--tcp", "1.2.3.4:0"])
    _fails_with_one_line(r, "cannot listen on TCP 1.2.3.4:0")


@pytest.mark.parametrize("command", ["emulate", "emulate-ics"])
def test_a_port_in_use(command: str, port_in_use: int) -> None:
    r = CliRunner().invoke(cli, [command, "--tcp", f"127.0.0.1:{port_in_use}"])
    _fails_with_one_line(r, f"cannot listen on TCP 127.0.0.1:{port_in_use}", "in use")


@pytest.mark.parametrize("size", [0, 100, layout.ROM_SIZE - 1])
def test_a_rom_file_of_the_wrong_size(size: int, tmp_path: Path) -> None:
    rom = tmp_path / "short.bin"
    rom.write_bytes(bytes(size))
    r = CliRunner().invoke(cli, ["emulate", "--tcp", "127.0.0.1:0", "--rom", str(rom)])
    line = _fails_with_one_line(r, str(rom), f"not a 256 KB ROM image ({size} bytes)")
    assert "project" not in line
    assert rom.read_bytes() == bytes(size)  # left as it was


def test_a_rom_file_in_a_missing_directory(tmp_path: Path) -> None:
    rom = tmp_path / "typo" / "rom.bin"
    r = CliRunner().invoke(cli, ["emulate", "--tcp", "127.0.0.1:0", "--rom", str(rom)])
    _fails_with_one_line(r, f"no directory {rom.parent} for the ROM image", "MissingFileError")
    assert not rom.parent.exists()  # refused, not created


def test_a_project_given_as_the_rom(kxr_project_path: Path) -> None:
    r = CliRunner().invoke(cli, ["emulate", "--tcp", "127.0.0.1:0", "--rom", str(kxr_project_path)])
    _fails_with_one_line(
        r, "not a 256 KB ROM image", "HeartToHeart4 project", "--rom", "rcb4hv project build"
    )


def test_the_console_script_prints_no_traceback() -> None:
    proc = subprocess.run(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "emulate", "--tcp",
         "1.2.3.4:0"],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert proc.returncode == 1
    (line,) = proc.stderr.strip().splitlines()
    assert line.startswith("error: cannot listen on TCP 1.2.3.4:0: ") and line.endswith("(OSError)")
