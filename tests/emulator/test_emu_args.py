"""Bad emulator parameters are refused when given; a ROM file that cannot be written is
reported (typed, naming the file) without ending the session."""

from __future__ import annotations

import contextlib
import errno
import math
from pathlib import Path

import pytest

from rcb4hv.client import Rcb4Client
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, VirtualClock, emulator_url, romstore
from rcb4hv.errors import ArgumentError, RomFileError, TransportError

ROM_PAGE = 0x3F000


@pytest.mark.parametrize(
    "query", ["speed=inf", "speed=-inf", "speed=1e999", "latency=inf", "latency=nan"]
)
def test_a_non_finite_url_parameter_is_refused_at_open(query: str) -> None:
    """``speed=inf`` opened, then the first call raised OverflowError inside the board."""
    name = query.split("=")[0]
    with pytest.raises(TransportError, match=f"{name} must be a finite number"):
        Rcb4Client.open(f"rcb4emu://?{query}")


def test_clocks_refuse_non_finite_times() -> None:
    for bad in (math.inf, math.nan, 0.0, -1.0):
        with pytest.raises(ArgumentError, match="speed must be a finite number > 0"):
            RealClock(bad)
    clock = VirtualClock()
    for bad in (math.inf, math.nan, -1.0):
        with pytest.raises(ArgumentError, match="finite number of seconds >= 0"):
            clock.advance(bad)
        with pytest.raises(ArgumentError):
            VirtualClock(bad)
    with pytest.raises(ArgumentError):
        clock.set(math.inf)
    assert clock.now() == 0.0


def _refuse_writes(monkeypatch: pytest.MonkeyPatch, path: Path) -> None:
    def refuse(target: object, data: bytes) -> None:
        raise PermissionError(errno.EACCES, f"cannot write {path}: Permission denied")

    monkeypatch.setattr(romstore, "write_atomic", refuse)


def test_a_rom_file_that_cannot_be_written_is_reported_once_and_at_close(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The call that meets the failed save raises RomFileError naming the file; the board
    serves on (every later call used to fail with "cannot flush input"), and close() reports
    the image still unsaved."""
    path = tmp_path / "board.rom"
    board = Board(EmulatorConfig(rom_flush_delay_s=0), clock=VirtualClock(), rom_path=path)
    client = Rcb4Client.open(emulator_url(board))
    _refuse_writes(monkeypatch, path)
    with pytest.raises(RomFileError, match=f"cannot save its ROM image: cannot write {path}"):
        for _ in range(3):  # the save is tried at the next tick after the write
            client.write_rom(ROM_PAGE, b"\x11" * 64)
            client.acknowledge_check()
    for _ in range(3):
        client.acknowledge_check()  # the board serves on
    assert client.read_rom(ROM_PAGE, 4) == b"\x11" * 4
    client.close()
    with pytest.raises(RomFileError, match=str(path)) as info:
        board.close()
    assert info.value.path == str(path)
    monkeypatch.undo()
    board.flush_rom()  # writable again: saved after all
    assert path.read_bytes()[ROM_PAGE : ROM_PAGE + 4] == b"\x11" * 4


def test_closing_a_port_whose_rom_file_cannot_be_written_says_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "board.rom"
    client = Rcb4Client.open(f"rcb4emu://?rom={path}")
    _refuse_writes(monkeypatch, path)
    with contextlib.suppress(RomFileError):  # slow machine: the delayed save came due
        client.write_rom(ROM_PAGE, b"\x22" * 64)
    with pytest.raises(RomFileError, match=str(path)):
        client.close()
    with pytest.raises(TransportError, match="the client is closed"):
        client.acknowledge_check()
