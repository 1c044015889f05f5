"""Crash safety of the emulator's persistent ROM image.

* SIGKILL ``rcb4hv emulate --rom FILE`` during long uploads: after each kill every 64-byte
  MOVE page holds its old or its new bytes, the new pages form a prefix of the upload (so a
  128-byte page is old, new, or new-then-old at the single cut), nothing outside the upload
  changed, and the board boots from the file (ACK, system register, no ROMERR).
* In process: a reader never sees a torn file while RomStore flushes; a flush that fails
  half-way leaves the old image and no temporary file.
"""

from __future__ import annotations

import os
import threading
from pathlib import Path

import pytest

from rcb4hv.emulator.romstore import RomStore
from rcb4hv.errors import RomFileError
from tests.reliability.scenarios import (
    PAGE,
    UPLOAD_BASE,
    UPLOAD_SIZE,
    check_image,
    page_pattern,
    run_kill_cycles,
)

SIZE = 0x40000


def test_kill_during_upload_never_tears_the_image(tmp_path: Path) -> None:
    rom = tmp_path / "board.rom"
    stats = run_kill_cycles(rom, cycles=4, seed=7, max_delay=1.0)
    assert stats.cycles == 4
    assert stats.problems == []
    assert stats.torn_pages == 0 and stats.outside_changed == 0 and stats.boot_failures == 0
    assert stats.stale_temp_files == 0


def test_image_checker_detects_torn_and_out_of_order_pages() -> None:
    old = bytes(SIZE)
    new = bytearray(old)
    a = UPLOAD_BASE
    new[a : a + PAGE] = page_pattern(1, 0)
    assert check_image(old, bytes(new), 1)[:3] == (0, 0, 1)
    torn = bytearray(new)
    torn[a + PAGE : a + PAGE + 8] = b"\x01" * 8  # half a page written
    assert check_image(old, bytes(torn), 1)[0] == 1
    gap = bytearray(old)
    gap[a + PAGE : a + 2 * PAGE] = page_pattern(1, 1)  # page 1 new, page 0 old
    assert check_image(old, bytes(gap), 1)[0] == 1
    outside = bytearray(new)
    outside[0] ^= 1
    assert check_image(old, bytes(outside), 1)[1] == 1
    assert check_image(old, bytes(new[: SIZE - 1]), 1)[4]
    assert a + UPLOAD_SIZE <= 0x3CB80


def test_reader_never_sees_a_torn_file(tmp_path: Path) -> None:
    store = RomStore(tmp_path / "img.rom", SIZE, delay=0.0)
    store.flush(bytes(SIZE))
    stop = threading.Event()
    seen: set[int] = set()
    bad: list[str] = []

    def reader() -> None:
        while not stop.is_set():
            data = store.path.read_bytes()
            if len(data) != SIZE or data.count(data[:1]) != SIZE:
                bad.append(f"torn read: {len(data)} bytes, first {data[:1].hex()}")
                return
            seen.add(data[0])

    t = threading.Thread(target=reader)
    t.start()
    try:
        for generation in range(1, 40):
            store.mark_dirty()
            store.maybe_flush(bytes((generation,)) * SIZE)
    finally:
        stop.set()
        t.join(timeout=10)
    assert bad == []
    assert len(seen) > 1  # the reader really raced the writer
    assert store.flushes == 40
    assert store.path.read_bytes() == bytes((39,)) * SIZE
    assert [f.name for f in tmp_path.iterdir()] == ["img.rom"]


def test_failed_flush_keeps_the_old_image(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    store = RomStore(tmp_path / "img.rom", SIZE, delay=0.0)
    store.flush(b"\x11" * SIZE)

    def broken_fsync(fd: int) -> None:
        raise OSError(5, "injected I/O error")

    monkeypatch.setattr(os, "fsync", broken_fsync)
    store.mark_dirty()
    with pytest.raises(RomFileError, match="injected I/O error") as info:
        store.flush(b"\x22" * SIZE)  # typed, naming the file, chained to the OSError
    assert isinstance(info.value.__cause__, OSError) and info.value.path == str(store.path)
    monkeypatch.undo()
    assert store.path.read_bytes() == b"\x11" * SIZE
    assert [f.name for f in tmp_path.iterdir()] == ["img.rom"]
    assert store.dirty
