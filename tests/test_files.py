"""rcb4hv.files.write_atomic: the one writer of a user's file. A save over a file keeps its
mode; a new file gets 0666 & ~umask (not mkstemp's 0600); a symlink is written through; a
failed write leaves the old file and no temporary file."""

from __future__ import annotations

import os
import re
import shutil
import stat
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from rcb4hv import files
from rcb4hv.errors import (
    FileAccessError,
    FileIsDirectoryError,
    FilePermissionError,
    MissingFileError,
    Rcb4Error,
)
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


# ------------------------------------------------------------------ refusals and ownership


def _untouched(tmp_path: Path, names: list[str]) -> None:
    """Nothing but ``names`` beside: no temporary file left."""
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(names)


def test_a_read_only_file_is_not_replaced(tmp_path: Path) -> None:
    """The rename needs only the directory's permission: a 0444 file was silently replaced
    (also as root, where open() would write it: no write bit at all is the user's "keep")."""
    target = tmp_path / "project.h4p"
    target.write_bytes(b"old")
    target.chmod(0o444)
    with pytest.raises(FilePermissionError, match=r"project\.h4p: the file is read-only") as info:
        write_atomic(target, b"new")
    assert isinstance(info.value, PermissionError) and info.value.filename == str(target)
    assert target.read_bytes() == b"old" and _mode(target) == 0o444
    _untouched(tmp_path, ["project.h4p"])


def test_a_file_the_caller_may_not_write_is_not_replaced(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Another user's 0644 file (os.access says no): refused although the mode has a w bit."""
    target = tmp_path / "theirs.h4p"
    target.write_bytes(b"old")
    monkeypatch.setattr(files.os, "access", lambda *a, **k: False)
    with pytest.raises(FilePermissionError, match="read-only"):
        write_atomic(target, b"new")
    assert target.read_bytes() == b"old"


@pytest.mark.skipif(
    os.geteuid() != 0 or shutil.which("setpriv") is None, reason="needs root and setpriv"
)
def test_a_read_only_file_is_refused_without_root_override(tmp_path: Path) -> None:
    """As an ordinary user would (root without CAP_DAC_OVERRIDE): 0444 is refused too."""
    target = tmp_path / "ro.h4p"
    target.write_bytes(b"old")
    target.chmod(0o444)
    code = (
        "import sys\nfrom rcb4hv.files import write_atomic\n"
        "from rcb4hv.errors import FilePermissionError\n"
        "try:\n    write_atomic(sys.argv[1], b'new')\nexcept FilePermissionError as e:\n"
        "    print('refused', e)\n"
    )
    out = subprocess.run(
        ["setpriv", "--bounding-set", "-dac_override,-dac_read_search,-fowner",
         sys.executable, "-c", code, str(target)],
        capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    assert out.startswith("refused") and target.read_bytes() == b"old"


@pytest.mark.skipif(os.geteuid() != 0, reason="only root can give a file to another user")
def test_root_saving_a_users_file_keeps_its_owner_and_group(tmp_path: Path) -> None:
    """Was: a user's 0640 file became root:root, unreadable by its owner."""
    target = tmp_path / "users.h4p"
    target.write_bytes(b"old")
    os.chown(target, 65534, 65534)
    target.chmod(0o640)
    write_atomic(target, b"new")
    st = target.stat()
    assert (st.st_uid, st.st_gid, _mode(target)) == (65534, 65534, 0o640)


def test_an_owner_that_cannot_be_kept_is_warned_about(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    target = tmp_path / "theirs.h4p"
    target.write_bytes(b"old")
    real_stat = os.stat_result(target.stat())
    fake = list(real_stat)
    fake[4], fake[5] = real_stat.st_uid + 1, real_stat.st_gid + 1  # st_uid, st_gid
    real_path_stat = Path.stat

    def stat_of(self: Path, **kwargs: object) -> os.stat_result:
        if self == target:
            return os.stat_result(fake)
        return real_path_stat(self, **kwargs)  # type: ignore[arg-type]

    def no_chown(*args: object) -> None:
        raise PermissionError(1, "Operation not permitted")

    monkeypatch.setattr(Path, "stat", stat_of)
    monkeypatch.setattr(files.os, "fchown", no_chown)
    write_atomic(target, b"new")
    assert target.read_bytes() == b"new"
    assert "theirs.h4p: saved with owner" in caplog.text


def test_a_hard_linked_file_is_replaced_atomically_and_warned_about(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """The documented choice: atomic, this name only; the other link keeps the old data."""
    target = tmp_path / "project.h4p"
    target.write_bytes(b"old")
    other = tmp_path / "link.h4p"
    os.link(target, other)
    write_atomic(target, b"new")
    assert target.read_bytes() == b"new" and other.read_bytes() == b"old"
    assert "had 2 hard links" in caplog.text


def test_saving_to_a_directory_names_it_not_the_temporary_file(tmp_path: Path) -> None:
    (tmp_path / "adir").mkdir()
    with pytest.raises(FileIsDirectoryError) as info:
        write_atomic(tmp_path / "adir", b"x")
    expected = f"cannot write {tmp_path / 'adir'}: it is a directory; give a file name"
    assert str(info.value) == expected
    assert ".tmp" not in str(info.value) and isinstance(info.value, IsADirectoryError)
    _untouched(tmp_path, ["adir"])


def test_saving_to_an_empty_name_writes_nothing(tmp_path: Path) -> None:
    """Was: "" resolved to the cwd, and the temporary file went into its parent."""
    with pytest.raises(MissingFileError, match="no file name given"):
        write_atomic("", b"x")


def test_a_missing_directory_is_named(tmp_path: Path) -> None:
    with pytest.raises(MissingFileError, match=f"no directory {tmp_path / 'nodir'}"):
        write_atomic(tmp_path / "nodir" / "x.h4p", b"x")


def test_a_directory_that_refuses_new_files_is_said_to(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The file itself is writable: the message says it is the directory."""
    target = tmp_path / "x.h4p"
    target.write_bytes(b"old")
    real_open = os.open

    def refuse_new(path: object, flags: int, *args: object) -> int:
        if flags & os.O_CREAT:
            raise PermissionError(13, "Permission denied", str(path))
        return real_open(path, flags, *args)  # type: ignore[arg-type]

    monkeypatch.setattr(files.os, "open", refuse_new)
    with pytest.raises(FilePermissionError) as info:
        write_atomic(target, b"new")
    assert f"the directory {tmp_path} does not allow new files" in str(info.value)
    assert target.read_bytes() == b"old"


def test_reading_a_directory_or_a_missing_file_is_typed(tmp_path: Path) -> None:
    with pytest.raises(FileIsDirectoryError, match="it is a directory, not a file"):
        files.read_bytes(tmp_path)
    with pytest.raises(MissingFileError, match=r"nope\.h4p: no such file") as info:
        files.read_bytes(tmp_path / "nope.h4p")
    assert isinstance(info.value, FileNotFoundError) and isinstance(info.value, Rcb4Error)
    (tmp_path / "latin1.json").write_bytes(b"\xe9t\xe9")
    with pytest.raises(FileAccessError, match="not UTF-8 text"):
        files.read_text(tmp_path / "latin1.json")


def test_a_dangling_symlink_names_the_missing_directory(tmp_path: Path) -> None:
    (tmp_path / "dang.h4p").symlink_to("missing/target.h4p")
    with pytest.raises(MissingFileError, match=f"no directory {tmp_path / 'missing'}"):
        write_atomic(tmp_path / "dang.h4p", b"x")
