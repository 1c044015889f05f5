"""Reading and saving a user's file: all at once, durably, with the mode and owner the user
expects, and errors that name the user's file.

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
* the owner: a file that exists keeps its owner and group where the caller may give them
  (root saving a user's file leaves it the user's; anyone may keep a group they belong to);
  where it may not, the file becomes the caller's and a warning says so;
* a read-only file is not replaced: a file the caller may not write, or one without any write
  bit (``chmod a-w``, refused even for root, as ``open(path, "w")`` refuses it for others),
  raises :class:`~rcb4hv.errors.FilePermissionError` and nothing is written (the rename
  alone would need only the directory's permission);
* a symbolic link is written through: the file it points to is replaced, the link stays;
* hard links: the save stays atomic, so it replaces this name only and other names of the
  file keep the old contents; a warning says so (writing in place would keep the links but
  could leave half a file after a crash).

Every failure is a :class:`~rcb4hv.errors.FileAccessError` (also the builtin ``OSError`` of the
same kind) naming the user's path, never the temporary file; :func:`read_bytes` does the same
for reading.
"""

from __future__ import annotations

import contextlib
import errno as errnos
import logging
import os
import secrets
import stat
from pathlib import Path

from rcb4hv.errors import (
    FileAccessError,
    FileIsDirectoryError,
    FilePermissionError,
    MissingFileError,
)

__all__ = ["file_error", "read_bytes", "read_text", "write_atomic"]

log = logging.getLogger(__name__)

NEW_FILE_MODE = 0o666
"""The mode a new file is created with, before the umask (as ``open()`` creates files)."""


def file_error(exc: OSError, path: str | os.PathLike[str], doing: str) -> FileAccessError:
    """The typed error for ``exc``, raised while ``doing`` (``"read"``, ``"write"``) the user's
    file ``path``: its message names ``path`` and says why in words."""
    name = os.fspath(path)
    shown = name or "''"
    why = exc.strerror or str(exc)
    if isinstance(exc, IsADirectoryError) or (
        doing == "read" and os.path.isdir(name) and name != ""
    ):
        return FileIsDirectoryError(
            f"cannot {doing} {shown}: it is a directory, not a file", name, errnos.EISDIR
        )
    if isinstance(exc, FileNotFoundError):
        parent = Path(name).parent if name else Path()
        why = "no such file" if doing == "read" else why
        if name == "":
            why = "no file name given"
        elif not parent.is_dir():
            why = f"no directory {parent}"
        return MissingFileError(f"cannot {doing} {shown}: {why}", name, exc.errno)
    if isinstance(exc, NotADirectoryError):
        return MissingFileError(
            f"cannot {doing} {shown}: a part of the path is a file, not a directory",
            name,
            exc.errno,
        )
    if isinstance(exc, PermissionError):
        return FilePermissionError(f"cannot {doing} {shown}: permission denied", name, exc.errno)
    return FileAccessError(f"cannot {doing} {shown}: {why}", name, exc.errno)


def read_bytes(path: str | os.PathLike[str]) -> bytes:
    """The bytes of the user's file ``path``; a missing file, a directory or a file the caller
    may not read raises a :class:`~rcb4hv.errors.FileAccessError` naming ``path``."""
    try:
        return Path(path).read_bytes()
    except OSError as exc:
        raise file_error(exc, path, "read") from None


def read_text(path: str | os.PathLike[str]) -> str:
    """The UTF-8 text of the user's file ``path`` (errors: :func:`read_bytes`; bytes that are
    not UTF-8 raise :class:`~rcb4hv.errors.FileAccessError` naming the file and the offset)."""
    data = read_bytes(path)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise FileAccessError(
            f"cannot read {os.fspath(path)}: not UTF-8 text (byte {exc.start})",
            os.fspath(path),
            errnos.EILSEQ,
        ) from None


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


def _check_target(path: str | os.PathLike[str], target: Path) -> os.stat_result | None:
    """The status of the file a save replaces (None: a new file); a directory or a read-only
    file raises, naming ``path``."""
    shown = os.fspath(path)
    if shown == "":
        raise MissingFileError("cannot write '': no file name given", "", errnos.ENOENT)
    try:
        st = target.stat()
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise file_error(exc, path, "write") from None
    if stat.S_ISDIR(st.st_mode):
        raise FileIsDirectoryError(
            f"cannot write {shown}: it is a directory; give a file name", shown, errnos.EISDIR
        )
    mode = stat.S_IMODE(st.st_mode)
    if mode & 0o222 == 0 or not os.access(target, os.W_OK):
        raise FilePermissionError(
            f"cannot write {shown}: the file is read-only (mode {mode:04o}); nothing written: "
            "make it writable (chmod u+w) or save under another name",
            shown,
            errnos.EACCES,
        )
    return st


def _keep_owner(fd: int, st: os.stat_result, path: str | os.PathLike[str]) -> None:
    """Give the temporary file ``fd`` the owner and group of the file it replaces, as far as
    the caller may; warn when the saved file changes hands."""
    mine = os.fstat(fd)
    if (mine.st_uid, mine.st_gid) == (st.st_uid, st.st_gid):
        return
    try:
        os.fchown(fd, st.st_uid, st.st_gid)
        return
    except OSError:
        pass
    with contextlib.suppress(OSError):  # a group the caller belongs to
        os.fchown(fd, -1, st.st_gid)
    now = os.fstat(fd)
    log.warning(
        "%s: saved with owner %d:%d (was %d:%d); only root can keep another user's ownership",
        os.fspath(path),
        now.st_uid,
        now.st_gid,
        st.st_uid,
        st.st_gid,
    )


def write_atomic(path: str | os.PathLike[str], data: bytes | str) -> None:
    """Replace ``path`` by ``data`` (``str`` is written as UTF-8) all at once, keeping the
    mode, owner and group of the file it replaces (a new file: ``0666 & ~umask``).

    A read-only file, a directory, a missing directory or a directory that refuses a new file
    raises a :class:`~rcb4hv.errors.FileAccessError` naming ``path``; nothing is written. A
    file with several hard links is still replaced atomically: this name gets the new data,
    the other links keep the old, and a warning says so."""
    shown = os.fspath(path)
    target = Path(os.path.realpath(path)) if shown else Path(shown)
    payload = data.encode("utf-8") if isinstance(data, str) else data
    st = _check_target(path, target)
    try:
        fd, tmp = _create_temporary(target)
    except PermissionError as exc:
        raise FilePermissionError(
            f"cannot write {shown}: the directory {target.parent} does not allow new files "
            f"(a save writes a temporary file beside {target.name} first)",
            shown,
            exc.errno,
        ) from exc
    except FileNotFoundError as exc:  # a missing folder, maybe a symlink's target's
        raise MissingFileError(
            f"cannot write {shown}: no directory {target.parent}", shown, exc.errno
        ) from exc
    except OSError as exc:  # name the user's file, not the temporary one beside it
        raise file_error(exc, path, "write") from exc
    try:
        with os.fdopen(fd, "wb") as f:
            if st is not None:
                _keep_owner(fd, st, path)
                os.fchmod(fd, stat.S_IMODE(st.st_mode))
            f.write(payload)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, target)
    except BaseException as exc:
        tmp.unlink(missing_ok=True)
        if isinstance(exc, OSError) and not isinstance(exc, FileAccessError):
            raise file_error(exc, path, "write") from exc
        raise
    if st is not None and st.st_nlink > 1:
        log.warning(
            "%s had %d hard links: the save replaced this name only; the other links keep "
            "the old contents",
            shown,
            st.st_nlink,
        )
    _sync_directory(target.parent)
