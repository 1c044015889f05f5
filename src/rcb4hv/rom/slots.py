"""Reading a motion slot's frames, and the slots whose bytes stop decoding.

A motion slot holds whole command frames from its start up to an erased byte (FF) or the
slot's end. :func:`scan_slot` reads them and says where and why it stopped early when a byte
that is not erased does not start a whole, checked frame; :func:`undecoded_slots` lists the
slots of an image where that happens (the parsers keep the frames before that point, so a slot
that holds garbage from its first byte is no motion at all and would otherwise go unnoticed).
"""

from __future__ import annotations

from dataclasses import dataclass

from rcb4hv.errors import ChecksumError, ProtocolError
from rcb4hv.protocol import MAX_FRAME_SIZE, MIN_FRAME_SIZE, frame_at
from rcb4hv.rom import layout as L
from rcb4hv.rom.layout import HTH4_22, MotionLayout

__all__ = ["UndecodedSlot", "scan_slot", "undecoded_slots"]


@dataclass(frozen=True, slots=True)
class UndecodedSlot:
    """A motion slot whose bytes stop decoding before an erased byte or the slot's end."""

    slot: int
    address: int
    """Where the slot starts."""
    at: int
    """The first byte that does not start a whole, checked frame."""
    reason: str

    @property
    def note(self) -> str:
        """``does not decode from 00B80h: size byte 5Ah cannot start a frame``."""
        return f"does not decode from {self.at:05X}h: {self.reason}"


def _stop_reason(rom: bytes, pc: int, end: int) -> str | None:
    """Why no frame of the slot (ending at ``end``) starts at ``pc``; None if one does."""
    size = rom[pc]
    if not MIN_FRAME_SIZE <= size <= MAX_FRAME_SIZE:
        return f"size byte {size:02X}h cannot start a frame"
    if pc + size > end:
        return f"the {size}-byte frame there runs past the slot's end"
    try:
        frame_at(rom, pc)
    except ChecksumError:
        return f"the {size}-byte frame there fails its checksum"
    except ProtocolError as e:  # pragma: no cover - the checks above leave only the checksum
        return str(e)
    return None


def scan_slot(rom: bytes, start: int, size: int) -> tuple[list[bytes], tuple[int, str] | None]:
    """The whole frames from ``start`` up to an erased byte or ``start + size``, and where and
    why the reading stopped early (None when it reached an erased byte or the end)."""
    frames: list[bytes] = []
    pc, end = start, start + size
    while pc < end and rom[pc] != L.ERASED:
        reason = _stop_reason(rom, pc, end)
        if reason is not None:
            return frames, (pc, reason)
        frames.append(rom[pc : pc + rom[pc]])
        pc += rom[pc]
    return frames, None


def undecoded_slots(
    rom: bytes | bytearray, lay: MotionLayout = HTH4_22
) -> tuple[UndecodedSlot, ...]:
    """The slots of ``rom`` (in layout ``lay``) that hold bytes which are neither erased nor
    whole frames, read as far as the parsers read a slot (:func:`scan_slot`)."""
    rom = bytes(rom)
    out: list[UndecodedSlot] = []
    for n in range(1, min(lay.motion_count, L.MOTION_COUNT) + 1):
        start = lay.address(n)
        _, stop = scan_slot(rom, start, min(lay.motion_stride, L.MOTION_SIZE))
        if stop is not None:
            out.append(UndecodedSlot(n, start, *stop))
    return tuple(out)
