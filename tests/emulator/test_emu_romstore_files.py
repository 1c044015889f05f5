"""The persistent ROM image keeps its file mode and cleans up after an interrupted flush."""

from __future__ import annotations

import os
import stat
from pathlib import Path

from rcb4hv.emulator.romstore import RomStore

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
