"""rcb4hv.files.write_atomic: the one writer of a user's file. A save over a file keeps its
mode; a new file gets 0666 & ~umask (not mkstemp's 0600); a symlink is written through; a
failed write leaves the old file and no temporary file."""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Iterator
from pathlib import Path

import pytest

from rcb4hv import files
from rcb4hv.files import write_atomic


@pytest.fixture
def umask_022() -> Iterator[None]:
    old = os.umask(0o022)
    try:
        yield
    finally:
        os.umask(old)


def _mode(path: Path) -> int:
    return stat.S_IMODE(path.stat().st_mode)


@pytest.mark.parametrize("mode", [0o640, 0o755, 0o600, 0o664])
def test_a_save_over_a_file_keeps_its_mode(tmp_path: Path, umask_022: None, mode: int) -> None:
    target = tmp_path / "project.h4p"
    target.write_bytes(b"old")
    target.chmod(mode)
    write_atomic(target, b"new")
    assert target.read_bytes() == b"new"
    assert _mode(target) == mode


def test_a_new_file_gets_the_usual_mode_under_the_umask(tmp_path: Path, umask_022: None) -> None:
    target = tmp_path / "new.h4p"
    write_atomic(target, b"data")
    assert _mode(target) == 0o644


def test_a_new_file_follows_a_stricter_umask(tmp_path: Path) -> None:
    old = os.umask(0o077)
    try:
        write_atomic(tmp_path / "private", b"x")
    finally:
        os.umask(old)
    assert _mode(tmp_path / "private") == 0o600


def test_text_is_written_as_utf8_and_nothing_is_left_beside(tmp_path: Path) -> None:
    target = tmp_path / "robot.urdf"
    write_atomic(target, "ロボット\n")
    write_atomic(target, "two")
    assert target.read_text(encoding="utf-8") == "two"
    assert [p.name for p in tmp_path.iterdir()] == ["robot.urdf"]


def test_a_symlink_is_written_through(tmp_path: Path) -> None:
    real = tmp_path / "real.h4p"
    real.write_bytes(b"old")
    real.chmod(0o640)
    link = tmp_path / "link.h4p"
    link.symlink_to(real.name)
    write_atomic(link, b"new")
    assert link.is_symlink() and real.read_bytes() == b"new" and _mode(real) == 0o640


def test_a_failed_write_keeps_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    target = tmp_path / "project.h4p"
    target.write_bytes(b"old")

    def fail(*args: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(files.os, "fsync", fail)
    with pytest.raises(OSError, match="disk full"):
        write_atomic(target, b"new")
    assert target.read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["project.h4p"]


def test_every_save_in_src_goes_through_write_atomic() -> None:
    """No second writer: nothing under src/ writes a file by itself."""
    src = Path(files.__file__).resolve().parent
    writer = re.compile(r"mkstemp\(|\.write_(bytes|text)\(|open\(.*[\"'][wax]b?\+?[\"']\)")
    found = [
        f"{path.relative_to(src)}:{n}"
        for path in sorted(src.rglob("*.py"))
        if path.name != "files.py" or path.parent != src
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if writer.search(line)
    ]
    assert found == []
