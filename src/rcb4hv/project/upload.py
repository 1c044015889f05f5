"""Write a ROM image to a board: whole, or only the 128-byte pages that differ.

The ROM program is suspended (ROM_F cleared) while the ROM is written, so the board never
fetches a half-written instruction. Each page goes out through
:meth:`rcb4hv.client.Robot.write_rom` (64-byte page-aligned MOVE frames, each read back and
compared: :class:`~rcb4hv.client.VerifyError` on a mismatch). Afterwards the board restarts
the new image from 000000h (PC 0, call depth 0, update flags 0, ROM_F set) unless
``restart=False``, which leaves the program stopped.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

from rcb4hv.client import Robot
from rcb4hv.protocol import sequences as seq
from rcb4hv.rom import layout

__all__ = ["PAGE_SIZE", "UploadResult", "changed_pages", "upload_image"]

log = logging.getLogger(__name__)

PAGE_SIZE: Final = 128
"""Bytes per page compared by ``only_changed``."""


Progress = Callable[[int, int], None]


@dataclass(frozen=True)
class UploadResult:
    """What an upload did."""

    pages_total: int
    pages_written: int
    bytes_written: int
    bytes_read: int

    @property
    def pages_skipped(self) -> int:
        return self.pages_total - self.pages_written


def changed_pages(old: bytes, new: bytes, page: int = PAGE_SIZE) -> list[int]:
    """Start addresses of the ``page``-byte pages where ``old`` and ``new`` differ."""
    if len(old) != len(new):
        raise ValueError("images of different sizes")
    return [a for a in range(0, len(new), page) if old[a : a + page] != new[a : a + page]]


def _runs(pages: list[int], page: int) -> list[tuple[int, int]]:
    """Adjacent pages merged into (address, size) runs."""
    runs: list[tuple[int, int]] = []
    for a in pages:
        if runs and runs[-1][0] + runs[-1][1] == a:
            runs[-1] = (runs[-1][0], runs[-1][1] + page)
        else:
            runs.append((a, page))
    return runs


def upload_image(
    robot: Robot,
    image: bytes,
    *,
    only_changed: bool = False,
    verify: bool = True,
    restart: bool = True,
    progress: Progress | None = None,
    read_progress: Progress | None = None,
    known: bytes | None = None,
) -> UploadResult:
    """Write the 256 KB ``image`` to the board behind ``robot``.

    ``only_changed``: read the whole ROM first and write only the 128-byte pages that differ.
    ``progress(done, total)`` counts bytes written, ``read_progress`` bytes read first.
    ``known``: the board's current ROM, already read (``only_changed`` then reads nothing).
    """
    image = bytes(image)
    if len(image) != layout.ROM_SIZE:
        raise ValueError(f"a ROM image is {layout.ROM_SIZE} bytes, not {len(image)}")
    total_pages = layout.ROM_SIZE // PAGE_SIZE
    word = robot.system_word()
    robot.send_sequence(seq.suspend_program(word))
    read = 0
    if only_changed:
        if known is not None and len(known) != layout.ROM_SIZE:
            raise ValueError("known ROM contents must be the whole 256 KB")
        current = known
        if current is None:
            current = robot.read_rom(0, layout.ROM_SIZE, progress=read_progress)
            read = len(current)
        pages = changed_pages(current, image)
    else:
        pages = list(range(0, layout.ROM_SIZE, PAGE_SIZE))
    runs = _runs(pages, PAGE_SIZE)
    total = len(pages) * PAGE_SIZE
    done = 0
    if progress is not None:
        progress(0, total)
    for address, size in runs:
        base = done

        def step(n: int, _size: int, base: int = base) -> None:
            if progress is not None:
                progress(base + n, total)

        robot.write_rom(address, image[address : address + size], verify=verify, progress=step)
        done += size
    log.info("wrote %d of %d pages (%d bytes)", len(pages), total_pages, total)
    if restart:
        robot.send_sequence(seq.restart_program(word))
    return UploadResult(total_pages, len(pages), total, read)
