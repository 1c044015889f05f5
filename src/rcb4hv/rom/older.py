"""ROM images in the older HeartToHeart4 layouts (2.0/2.1 and 1.3: main loop at 003FDh).

What is established about these layouts (see the spec notes, docs/spec-notes.md, for the evidence):

* the main loop starts at **003FDh** and, as in 2.2, begins with a system-register write that
  re-arms VEC_F: libkondo4 sets the PC to 03FDh and polls until VEC_F is set again;
  python-khr3hv sets the PC to 0003FDh and polls until the register's low byte leaves 23h;
* motion n lives at **0BB8h + 800h (n - 1)** (2.0/2.1; 1.3: 0BB8h + 1300h (n - 1), 50 slots);
* the servo-block images sit at 0626h + 20 n as in 2.2 (a real project of that era stores
  ``RomAddress`` 1574 + 20 n for its servos, the same numbers as a 2.2 project).

What is this project's choice: the boot region is the 2.2 boot sequence (spec 11.2) up to the
all-servos-hold frame, unchanged. 2.2's boot code ends 78 bytes after 03FDh, so the rest of it
moves behind the main loop:

====== ==== ==============================================================================
003F5  7    JUMP :data:`BOOT_TAIL`
003FD  9    **main loop**: system-register write (re-arms VEC_F)
00406  24   JUMP over the reserved PIO-switch bytes (as in 2.2)
0041E  325  13 priority checks of 25 bytes (as in 2.2)
00563  7    JUMP 003FDh
0056A  79   all servos to home (:data:`BOOT_TAIL`)
005B9  7    CALL the startup motion (or the stub after the last motion slot)
005C0  7    JUMP 003FDh
====== ==== ==============================================================================

The data images (05DCh-0B7Fh) are where 2.2 keeps them; 0B80h-0BB7h stays erased. The startup
stub (a RETURN) sits right after the last motion slot (:attr:`MotionLayout.startup_stub`).
"""

from __future__ import annotations

import logging
from dataclasses import replace
from typing import Final

from rcb4hv.errors import LayoutError, ProtocolError
from rcb4hv.protocol import (
    ALWAYS,
    Call,
    Data,
    Jump,
    Move,
    Ram,
    Return,
    decode_command,
    encode_command,
    frame_at,
)
from rcb4hv.protocol.memory import ADDR
from rcb4hv.rom import layout as L
from rcb4hv.rom.image import ImageDescription, build_image, parse_image, priority_bytes, word_write
from rcb4hv.rom.layout import HTH4_22, LAYOUTS, MotionLayout
from rcb4hv.rom.slots import scan_slot

log = logging.getLogger(__name__)

__all__ = [
    "BOOT_TAIL",
    "build_image_for",
    "detect_image_layout",
    "main_loop_layout",
    "parse_image_for",
    "play_layout",
]

BOOT_JUMP: Final = L.ALL_HOME
MAIN_LOOP: Final = L.OLDER_MAIN_LOOP
PIO_SWITCHES: Final = MAIN_LOOP + 9
PRIORITY_CHECKS: Final = PIO_SWITCHES + L.PIO_SWITCHES_SIZE
MAIN_LOOP_JUMP: Final = PRIORITY_CHECKS + L.PRIORITY_COUNT * L.PRIORITY_SIZE
BOOT_TAIL: Final = MAIN_LOOP_JUMP + 7
STARTUP_CALL: Final = BOOT_TAIL + 79
TAIL_JUMP: Final = STARTUP_CALL + 7

assert BOOT_TAIL == L.OLDER_MAIN_LOOP_END
assert TAIL_JUMP + 7 <= L.SYSTEM_REGISTER_IMAGE
_MAIN_22: Final = L.MAIN_LOOP_JUMP + 7 - L.MAIN_LOOP  # bytes of main-loop code (both layouts)
assert BOOT_TAIL - MAIN_LOOP == _MAIN_22

_FF: Final = bytes([L.ERASED])


def _check_fits(desc: ImageDescription, lay: MotionLayout) -> None:
    for m in desc.motions:
        if m.slot > lay.motion_count:
            raise LayoutError(
                f"motion slot {m.slot}: HeartToHeart4 {lay.version} has {lay.motion_count} slots"
            )
        if sum(map(len, m.frames)) > lay.motion_stride:
            raise LayoutError(f"motion {m.slot} does not fit a {lay.motion_stride}-byte slot")


def build_image_for(desc: ImageDescription, lay: MotionLayout = HTH4_22) -> bytes:
    """The 256 KB image of ``desc`` in layout ``lay``: motion ``ImageMotion(n)`` goes to
    ``lay.address(n)``; startup, priority and vector targets are taken as given (absolute)."""
    if not lay.older:
        if lay.motion_base != HTH4_22.motion_base or lay.motion_stride != HTH4_22.motion_stride:
            raise LayoutError(f"no image builder for layout {lay.name}")
        return build_image(desc)
    _check_fits(desc, lay)
    startup = lay.startup_stub if desc.startup_motion is None else desc.startup_motion
    rom = bytearray(build_image(replace(desc, motions=(), startup_motion=None)))

    def put(addr: int, data: bytes) -> None:
        rom[addr : addr + len(data)] = data

    home = bytes(rom[L.ALL_HOME : L.ALL_HOME + 79])
    put(BOOT_JUMP, _FF * (L.SYSTEM_REGISTER_IMAGE - BOOT_JUMP))
    put(L.STARTUP_STUB, _FF * 3)
    put(BOOT_JUMP, encode_command(Jump(BOOT_TAIL, ALWAYS)))
    sysreg = desc.system_register
    put(MAIN_LOOP, word_write(ADDR.SYSTEM, sysreg))
    put(PIO_SWITCHES, encode_command(Jump(PRIORITY_CHECKS, ALWAYS)))
    for i in range(L.PRIORITY_COUNT):
        pm = desc.priority_motions[i] if i < len(desc.priority_motions) else None
        slot = PRIORITY_CHECKS + L.PRIORITY_SIZE * i
        code = priority_bytes(pm, slot, sysreg)
        put(slot, code)
        put(L.PRIORITY_IMAGES + L.PRIORITY_SIZE * i, code)
    put(MAIN_LOOP_JUMP, encode_command(Jump(MAIN_LOOP, ALWAYS)))
    put(BOOT_TAIL, home)
    put(STARTUP_CALL, encode_command(Call(startup, ALWAYS)))
    put(TAIL_JUMP, encode_command(Jump(MAIN_LOOP, ALWAYS)))
    for m in desc.motions:
        put(lay.address(m.slot), b"".join(m.frames))
    put(lay.startup_stub, encode_command(Return()))
    return bytes(rom)


def _slot_bytes(rom: bytes, start: int, size: int) -> bytes:
    """The frames at the start of a motion slot, up to ``size`` bytes (erased-padded)."""
    frames, _ = scan_slot(rom, start, size)
    return b"".join(frames).ljust(size, _FF)


def parse_image_for(rom: bytes | bytearray, lay: MotionLayout = HTH4_22) -> ImageDescription:
    """Read an image in layout ``lay`` back into a description (``ImageMotion(n)`` = slot n).

    ProtocolError when the image does not have that layout's boot region."""
    rom = bytes(rom)
    if not lay.older:
        return parse_image(rom)
    if len(rom) != L.ROM_SIZE:
        raise ValueError(f"a ROM image is {L.ROM_SIZE} bytes, not {len(rom)}")
    jump = decode_command(frame_at(rom, BOOT_JUMP))
    if not isinstance(jump, Jump) or jump.address != BOOT_TAIL:
        raise ProtocolError(f"no JUMP {BOOT_TAIL:05X}h at {BOOT_JUMP:05X}h: not an older image")
    start = decode_command(frame_at(rom, STARTUP_CALL))
    if not isinstance(start, Call):
        raise ProtocolError(f"no startup CALL at {STARTUP_CALL:05X}h")
    # Reshape into the 2.2 layout and let the 2.2 parser read it.
    r = bytearray(rom)
    r[BOOT_JUMP : L.SYSTEM_REGISTER_IMAGE] = _FF * (L.SYSTEM_REGISTER_IMAGE - BOOT_JUMP)
    r[L.ALL_HOME : L.ALL_HOME + 79] = rom[BOOT_TAIL : BOOT_TAIL + 79]
    target = L.STARTUP_STUB if start.address == lay.startup_stub else start.address
    r[L.STARTUP_CALL : L.STARTUP_CALL + 7] = encode_command(Call(target, ALWAYS))
    r[L.MAIN_LOOP : L.MAIN_LOOP + _MAIN_22] = rom[MAIN_LOOP:BOOT_TAIL]
    r[HTH4_22.motion_base :] = _FF * (L.ROM_SIZE - HTH4_22.motion_base)
    for n in range(1, min(lay.motion_count, HTH4_22.motion_count) + 1):
        data = _slot_bytes(rom, lay.address(n), lay.motion_stride)
        if data[L.MOTION_SIZE :].rstrip(_FF):
            log.warning(
                "motion %d of this HeartToHeart4 %s image is longer than the %d bytes a motion is "
                "read with here: only its first %d bytes are read",
                n,
                lay.version,
                L.MOTION_SIZE,
                L.MOTION_SIZE,
            )
        data = data[: L.MOTION_SIZE]
        r[HTH4_22.address(n) : HTH4_22.address(n) + len(data)] = data
    r[L.STARTUP_STUB : L.STARTUP_STUB + 3] = encode_command(Return())
    desc = parse_image(r)
    return desc


def _is_sysreg_write(frame: bytes) -> bool:
    """A 9-byte literal MOVE to RAM 0000h (the first instruction of every main loop)."""
    if len(frame) != 9:
        return False
    cmd = decode_command(frame)
    return isinstance(cmd, Move) and cmd.dst == Ram(ADDR.SYSTEM) and isinstance(cmd.src, Data)


def main_loop_layout(at_03fd: bytes, at_044b: bytes) -> MotionLayout | None:
    """The layout whose main loop starts with a system-register write, from 9 ROM bytes read
    at 003FDh and 9 at 0044Bh (enough for a client to tell the layouts apart); None if
    neither or both hold one. An older main loop is reported as 2.1 (2.0 is the same)."""

    def ok(data: bytes) -> bool:
        try:
            return _is_sysreg_write(frame_at(bytes(data), 0))
        except ProtocolError:
            return False

    older, newer = ok(at_03fd), ok(at_044b)
    if older == newer:
        return None
    return LAYOUTS["2.1"] if older else HTH4_22


def play_layout(rom: bytes | bytearray, given: MotionLayout | None = None) -> MotionLayout:
    """The layout an image is played in: ``given``, else the one its main loop shows
    (:func:`detect_image_layout`), else HeartToHeart4 2.2."""
    return given or detect_image_layout(rom) or HTH4_22


def detect_image_layout(rom: bytes | bytearray) -> MotionLayout | None:
    """The layout of a whole ROM image, by where its main loop starts (None: unknown).

    1.3 (same main loop, other motion stride) cannot be told from 2.0/2.1 by the boot region;
    it is reported when the startup CALL or a vector/priority target is a 1.3 slot start that
    no 2.x slot shares."""
    rom = bytes(rom)
    base = main_loop_layout(rom[MAIN_LOOP : MAIN_LOOP + 9], rom[L.MAIN_LOOP : L.MAIN_LOOP + 9])
    if base is None or not base.older:
        return base
    try:
        desc = parse_image_for(rom, base)
    except ProtocolError:
        return base
    old13, new = LAYOUTS["1.3"], base
    targets = [p.target for p in desc.vector_packages]
    targets += [p.target for p in desc.priority_motions if p is not None]
    if desc.startup_motion is not None:
        targets.append(desc.startup_motion)
    for t in targets:
        n13 = old13.motion_at(t)
        if n13 is not None and t == old13.address(n13) and new.motion_at(t) is not None:
            n = new.motion_at(t)
            assert n is not None
            if t != new.address(n):
                return old13
    return base
