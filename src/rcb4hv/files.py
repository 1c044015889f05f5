"""Saving a user's file: all at once, durably, with the mode the user expects.

:func:`write_atomic` is the one writer every save goes through (projects, motions, trims,
links, robot exports, EEPROM backups, ROM images, assembler and CLI outputs):

* all at once: the data goes to a temporary file in the target's own directory (so the
  rename never crosses a file system), which then replaces the target with ``os.replace``;
  a reader, or a crash, sees the old file or the new one, never a part;
* durably: the temporary file is fsync'ed before the rename, the directory after it;
* the mode: a file that exists keeps its permission bits (a project saved over a 0640 file
  stays 0640); a new file gets ``0666 & ~umask``, as ``open(path, "w")`` would give it (the
  temporary file is created with mode 0666, so the kernel applies the umask and the
  directory's default ACL; ``tempfile.mkstemp`` would have left 0600);
* a symbolic link is written through: the file it points to is replaced, the link stays.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import stat
from pathlib import Path

__all__ = ["write_atomic"]

NEW_FILE_MODE = 0o666
"""The mode a new file is created with, before the umask (as ``open()`` creates files)."""


def _create_temporary(target: Path) -> tuple[int, Path]:
    """A new, empty temporary file beside ``target``: (descriptor, path)."""
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    for _ in range(100):
        tmp = target.with_name(f".{target.name}.{secrets.token_hex(4)}.tmp")
        try:
            return os.open(tmp, flags, NEW_FILE_MODE), tmp
        except FileExistsError:  # pragma: no cover - a 32-bit random name taken
            continue
    raise FileExistsError(f"no free temporary name beside {target}")  # pragma: no cover


def _sync_directory(directory: Path) -> None:
    """fsync ``directory`` so the rename itself is on disk (where the platform can)."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:  # pragma: no cover - platforms without directory handles
        return
    try:
        with contextlib.suppress(OSError):  # file systems that cannot sync a directory
            os.fsync(fd)
    finally:
        os.close(fd)


def write_atomic(path: str | os.PathLike[str], data: bytes | str) -> None:
    """Replace ``path`` by ``data`` (``str`` is written as UTF-8) all at once, keeping the
    mode of the file it replaces (a new file: ``0666 & ~umask``)."""
    target = Path(os.path.realpath(path))
    payload = data.encode("utf-8") if isinstance(data, str) else data
    try:
        mode: int | None = stat.S_IMODE(target.stat().st_mode)
    except FileNotFoundError:
        mode = None
    try:
        fd, tmp = _create_temporary(target)
    except OSError as exc:  # name the user's file, not the temporary one beside it
        why = exc.strerror or str(exc)
        if isinstance(exc, FileNotFoundError) and not target.parent.is_dir():
            why = f"no directory {target.parent}"
        raise type(exc)(exc.errno, f"cannot write {path}: {why}") from exc
    try:
        with os.fdopen(fd, "wb") as f:
            if mode is not None:
                os.fchmod(fd, mode)
            f.write(payload)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    _sync_directory(target.parent)
