"""A project motion's stored entries as frames, and rewriting the ROM addresses they jump to.

A :class:`~rcb4hv.hth4.model.Motion` stores ``MotionData`` entries: each is one or more
complete command frames, the last one followed by HeartToHeart4's ``FF`` end byte. The
entries lie one after the other from the motion's ``Address`` (spec 11.2), and JUMP / CALL
frames hold absolute 24-bit ROM addresses (spec 8, 0Ch/0Bh). So an edit that changes the
length of an entry, inserts, deletes or moves one, or moves the motion to another slot,
must rewrite those addresses. :func:`retarget_frame` rewrites one frame, :func:`retarget_motion`
every frame of a motion and :func:`retarget_project` every motion of a project plus the
startup, low-power and priority-motion addresses. Only the three address bytes and the
checksum of a JUMP / CALL frame change.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from rcb4hv.hth4.model import Motion, PriorityMotionSlot, Project
from rcb4hv.protocol import Op
from rcb4hv.protocol.frame import split_frames
from rcb4hv.rom.layout import LAYOUTS

__all__ = [
    "BRANCH_FRAME_SIZE",
    "AddressMap",
    "branch_target",
    "retarget_frame",
    "retarget_motion",
    "retarget_project",
    "slot_size",
    "split_frames",
]

BRANCH_FRAME_SIZE = 7
"""``07 0C|0B ADDR0 ADDR1 ADDR2 COND SUM``: a JUMP or CALL frame (spec 8)."""

AddressMap = Callable[[int], int]
"""Where a ROM address goes after an edit (identity for addresses the edit does not move)."""


def branch_target(frame: bytes) -> int | None:
    """The ROM address a JUMP or CALL frame goes to; None for any other frame."""
    if len(frame) != BRANCH_FRAME_SIZE or frame[1] not in (Op.JUMP, Op.CALL):
        return None
    return int.from_bytes(frame[2:5], "little")


def retarget_frame(frame: bytes, where: AddressMap) -> bytes:
    """``frame`` with its JUMP / CALL target moved by ``where``; other frames unchanged."""
    target = branch_target(frame)
    if target is None:
        return frame
    moved = where(target)
    if moved == target:
        return frame
    body = frame[:2] + moved.to_bytes(3, "little") + frame[5:6]
    return body + bytes([sum(body) & 0xFF])


def _retarget_entry(entry: bytes, where: AddressMap) -> bytes:
    frames, tail = split_frames(entry)
    return b"".join(retarget_frame(f, where) for f in frames) + tail


def retarget_motion(motion: Motion, where: AddressMap) -> Motion:
    """``motion`` with every JUMP / CALL target moved by ``where`` (entries that change
    nothing keep their bytes)."""
    entries = tuple(_retarget_entry(e, where) for e in motion.frames)
    return motion if entries == motion.frames else replace(motion, frames=entries)


def retarget_project(project: Project, where: AddressMap) -> Project:
    """Every motion's JUMP / CALL targets and the startup, low-power and priority-motion
    addresses of ``project`` moved by ``where`` (negative addresses mean none and stay)."""

    def ref(address: int) -> int:
        return address if address < 0 else where(address)

    priority: list[PriorityMotionSlot] = []
    for p in project.priority_motions:
        if p.motion is None or ref(p.motion.address) == p.motion.address:
            priority.append(p)
        else:
            priority.append(replace(p, motion=replace(p.motion, address=ref(p.motion.address))))
    motions = tuple(retarget_motion(m, where) for m in project.motions)
    return replace(
        project,
        motions=motions,
        startup_motion_address=ref(project.startup_motion_address),
        low_power_motion_address=ref(project.low_power_motion_address),
        priority_motions=tuple(priority),
    )


def slot_size(motion: Motion) -> int:
    """Bytes the slot of ``motion`` holds: the stride of the HeartToHeart4 layout that puts
    its slot at its stored address (2048 for 2.x, 4864 for 1.3; spec 11.2); 2048 if none
    matches."""
    for layout in LAYOUTS.values():
        if motion.slot <= layout.motion_count and layout.address(motion.slot) == motion.address:
            return layout.motion_stride
    return LAYOUTS["2.2"].motion_stride
