"""The persistent ROM image keeps its file mode, cleans up after an interrupted flush, is never
rewritten unchanged, and is not created in a directory that does not exist."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.emulator.romstore import RomStore
from rcb4hv.errors import MissingFileError, TransportError
from rcb4hv.rom.default import default_image
from rcb4hv.transport import SerialTransport

SIZE = 0x40000


def test_flush_keeps_the_image_file_mode(tmp_path: Path) -> None:
    path = tmp_path / "rom.bin"
    path.write_bytes(b"\xff" * SIZE)
    os.chmod(path, 0o640)
    store = RomStore(path, SIZE)
    store.flush(b"\x00" * SIZE)
    assert stat.S_IMODE(path.stat().st_mode) == 0o640
    assert path.read_bytes() == b"\x00" * SIZE


def test_new_image_is_not_private(tmp_path: Path) -> None:
    path = tmp_path / "new.bin"
    RomStore(path, SIZE).flush(b"\xff" * SIZE)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644


def test_load_removes_temp_files_of_an_interrupted_flush(tmp_path: Path) -> None:
    path = tmp_path / "rom.bin"
    path.write_bytes(b"\x11" * SIZE)
    stale = tmp_path / ".rom.bin.abc123.tmp"
    stale.write_bytes(b"\x22" * 1000)  # a flush killed half way
    other = tmp_path / ".other.bin.x.tmp"
    other.write_bytes(b"keep")
    assert RomStore(path, SIZE).load() == b"\x11" * SIZE
    assert not stale.exists()
    assert other.exists()


def test_a_missing_directory_is_refused_not_created(tmp_path: Path) -> None:
    """A typo in the directory is a FileNotFoundError naming it; no tree is created."""
    path = tmp_path / "typo" / "dir" / "rom.bin"
    # a typed error (rcb4hv.errors), still a FileNotFoundError
    with pytest.raises(MissingFileError, match=f"no directory {path.parent} for the ROM image"):
        RomStore(path, SIZE)
    with pytest.raises(FileNotFoundError, match=f"no directory {path.parent}"):
        Board(rom_path=path)
    with pytest.raises(TransportError, match=f"no directory {path.parent}"):
        SerialTransport.open(f"rcb4emu://?rom={path}")
    assert list(tmp_path.iterdir()) == []


def _identity(path: Path) -> tuple[int, int]:
    st = path.stat()
    return st.st_ino, st.st_mtime_ns


def test_an_unchanged_image_is_never_rewritten(tmp_path: Path) -> None:
    """Writes that leave the ROM as the file holds it (the same bytes; a change and its undo)
    do not rewrite the file, at the debounced flush or at close; a real change does, keeping
    the file's mode."""
    path = tmp_path / "rom.bin"
    path.write_bytes(default_image())
    os.chmod(path, 0o640)
    before = _identity(path)
    config = EmulatorConfig(rom_flush_delay_s=0)
    board = Board(config, clock=VirtualClock(), rom_path=path)
    board.load_rom(0x3F000, bytes(board.rom[0x3F000:0x3F080]))  # the bytes already there
    board.tick()  # the flush is due
    board.load_rom(0x3F000, b"\x12" * 16)
    board.load_rom(0x3F000, default_image()[0x3F000:0x3F010])  # and back
    board.close()
    assert _identity(path) == before
    board = Board(config, clock=VirtualClock(), rom_path=path)
    board.load_rom(0x3F000, b"\x12" * 16)
    board.close()
    assert _identity(path) != before
    assert path.read_bytes()[0x3F000:0x3F010] == b"\x12" * 16
    assert stat.S_IMODE(path.stat().st_mode) == 0o640
    assert [p.name for p in tmp_path.iterdir()] == ["rom.bin"]


def test_a_missing_image_file_is_created_at_once(tmp_path: Path) -> None:
    path = tmp_path / "new.bin"
    board = Board(rom_path=path)
    assert path.read_bytes() == default_image()
    created = _identity(path)
    board.close()
    assert _identity(path) == created
