"""Which HeartToHeart4 layout a board's ROM holds, read over the link.

Two 9-byte ROM reads are enough: every HeartToHeart4 main loop starts with a system-register
write (a literal MOVE to RAM 0000h), at 0044Bh in a 2.2 image and at 003FDh in the older ones
(:mod:`rcb4hv.rom.older`). 1.3 and 2.0/2.1 share the older main loop and differ only in the
motion stride, which the boot region does not show: an older board is reported as 2.1 (give
``Robot(layout=LAYOUTS["1.3"])`` for a 1.3 board).
"""

from __future__ import annotations

from typing import Protocol

from rcb4hv.errors import NakError
from rcb4hv.rom.layout import HTH4_22, OLDER_MAIN_LOOP, MotionLayout
from rcb4hv.rom.older import main_loop_layout

__all__ = ["detect_board_layout"]


class _RomReader(Protocol):
    def read_rom(self, address: int, size: int) -> bytes: ...


def detect_board_layout(client: _RomReader) -> MotionLayout | None:
    """The layout whose main loop the board's ROM holds; None if neither (or the board
    refuses the reads)."""
    try:
        older = client.read_rom(OLDER_MAIN_LOOP, 9)
        newer = client.read_rom(HTH4_22.main_loop, 9)
    except NakError:
        return None
    return main_loop_layout(older, newer)
