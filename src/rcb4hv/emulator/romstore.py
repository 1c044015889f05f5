"""A ROM image file that survives restarts and is never left torn by a crash.

Writes only mark the store dirty; :meth:`RomStore.maybe_flush` (called by the board on every
tick) writes the *whole* current image once ``delay`` seconds of real time have passed since
the first unflushed write, and :meth:`flush` writes it now. A flush writes a temporary file in
the same directory, fsyncs it, ``os.replace``-s it over the image and fsyncs the directory, so
the file on disk is always a complete image: every page holds either its old or its new bytes.

A missing image file is created (from the board's image) when the store is opened; an existing
one is rewritten only when the image differs from what it holds (a write of the bytes already
there, or writes that end where they began, leave the file alone). The file's directory must
exist: a typo in the path is refused, not created.

A save that fails (a read-only directory, a full disk) never stops the board: it runs on with
the image in memory. The failure is a :class:`~rcb4hv.errors.RomFileError` naming the file:
logged once, handed once to the port that serves the board (:meth:`RomStore.take_error`, so the
next host call reports it), retried every ``delay`` seconds and raised by :meth:`flush` (and so
by the board's ``close()``) while the image is still unsaved.
"""

from __future__ import annotations

import contextlib
import logging
import time
from pathlib import Path

from rcb4hv.errors import MissingFileError, RomFileError
from rcb4hv.files import write_atomic
from rcb4hv.rom.layout import ROM_SIZE

__all__ = ["RomStore", "initial_rom"]

log = logging.getLogger(__name__)


class RomStore:
    """Persistence of one 256 KB ROM image at ``path``."""

    def __init__(self, path: str | Path, size: int, delay: float = 0.25) -> None:
        self.path = Path(path)
        directory = self.path.parent
        if not directory.is_dir():
            raise MissingFileError(
                f"no directory {directory} for the ROM image {self.path.name} "
                "(it is not created: check the path)"
            )
        self.size = size
        self.delay = delay
        self._dirty_since: float | None = None
        self._on_disk: bytes | None = None  # the image the file holds, once read or written
        self.flushes = 0
        self.error: RomFileError | None = None
        """The last failed save, until a save succeeds."""
        self._unreported: RomFileError | None = None

    def _stale_temp_files(self) -> list[Path]:
        return list(self.path.parent.glob(f".{self.path.name}.*.tmp"))

    def load(self) -> bytes | None:
        """The stored image, or None if the file does not exist.

        Temporary files left by a crash in the middle of a flush are removed: the image itself
        is always complete (the temp file only replaces it once fully written and synced)."""
        for stale in self._stale_temp_files():
            with contextlib.suppress(OSError):
                stale.unlink()
                log.info("removed %s left by an interrupted flush", stale)
        try:
            data = self.path.read_bytes()
        except FileNotFoundError:
            return None
        if len(data) != self.size:
            raise ValueError(f"{self.path}: a ROM image is {self.size} bytes, not {len(data)}")
        self._on_disk = data
        return data

    def mark_dirty(self) -> None:
        if self._dirty_since is None:
            self._dirty_since = time.monotonic()

    @property
    def dirty(self) -> bool:
        return self._dirty_since is not None

    def seconds_until_flush(self) -> float | None:
        """Real seconds until a pending flush is due (0 if overdue), None if clean."""
        if self._dirty_since is None:
            return None
        return max(0.0, self._dirty_since + self.delay - time.monotonic())

    def maybe_flush(self, image: bytes | bytearray) -> None:
        """Flush when due; a failed save is kept (:attr:`error`) and retried, never raised."""
        wait = self.seconds_until_flush()
        if wait is not None and wait <= 0:
            try:
                self.flush(image)
            except RomFileError:
                self._dirty_since = time.monotonic()  # retry after ``delay``

    def take_error(self) -> RomFileError | None:
        """A save failure not reported yet (once per run of failures), else None."""
        err, self._unreported = self._unreported, None
        return err

    def flush(self, image: bytes | bytearray) -> None:
        """Write ``image`` atomically (:func:`rcb4hv.files.write_atomic`: temp file + fsync +
        os.replace + directory fsync; the image keeps its mode), unless the file holds it
        already."""
        if len(image) != self.size:
            raise ValueError("image size mismatch")
        if self._on_disk is not None and self._on_disk == image and self.path.exists():
            self._dirty_since = None
            log.debug("%s holds the ROM image already: not rewritten", self.path)
            return
        data = bytes(image)
        try:
            write_atomic(self.path, data)
        except OSError as exc:
            why = str(exc.strerror or exc)
            if str(self.path) not in why:
                why = f"{self.path}: {why}"
            err = RomFileError(
                f"the emulator cannot save its ROM image: {why} (the ROM written since the "
                "last save is only in the emulator's memory)",
                str(self.path),
            )
            if self.error is None:
                log.warning("%s", err)
                self._unreported = err
            self.error = err
            raise err from exc
        if self.error is not None:
            log.warning("saved the ROM image %s after all", self.path)
            self.error = self._unreported = None
        self._dirty_since = None
        self._on_disk = data
        self.flushes += 1
        log.debug("flushed ROM image to %s", self.path)


def initial_rom(store: RomStore | None, rom_image: bytes | bytearray | None) -> bytearray:
    """A board's ROM at construction: the persistent image ``store`` holds, else
    ``rom_image`` (padded with erased bytes), else the default image; a new persistent image
    is written at once."""
    image = store.load() if store is not None else None
    if image is None and rom_image is not None:
        if len(rom_image) > ROM_SIZE:
            raise ValueError(f"ROM image of {len(rom_image)} bytes exceeds {ROM_SIZE}")
        image = bytes(rom_image).ljust(ROM_SIZE, b"\xff")
    if image is None:
        from rcb4hv.rom.default import default_image

        image = default_image()
    rom = bytearray(image)
    if store is not None and not store.path.exists():
        store.flush(rom)
    return rom
