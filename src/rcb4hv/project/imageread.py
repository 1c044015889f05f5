"""HeartToHeart4 2.2 ROM image -> project terms: :func:`read_image` (see
:mod:`rcb4hv.project.image`, which re-exports everything here)."""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Final

from rcb4hv.errors import ChecksumError, FrameError, LayoutError, ProtocolError
from rcb4hv.hth4.newproject import COMPARE
from rcb4hv.protocol import Button
from rcb4hv.protocol.memory import AD_CHANNELS, ADDR, PA_VALUES, button_operand, mix_rate, u16_bytes
from rcb4hv.rom import ImageDescription, UndecodedSlot, VectorPackage, undecoded_slots
from rcb4hv.rom.layout import HTH4_22, ROM_SIZE, MotionLayout
from rcb4hv.rom.older import parse_image_for

__all__ = ["ButtonBinding", "ImageContents", "MotionSlot", "button_names", "read_image"]

_COMPARE_NAME: Final = {v: k for k, v in COMPARE.items()}
AD0: Final = ADDR.ad(0)
PA1: Final = ADDR.PA[0]
_AD_LAST: Final = ADDR.ad(ADDR.AD_COUNT - 1)


def _package_compare(p: VectorPackage) -> tuple[str, int] | None:
    """(CompareType, button word) of a package made by :func:`_vector_package`, else None."""
    if p.destination != ADDR.BUTTONS or not p.literal or not p.word:
        return None
    value = button_operand(p.source)  # swapping the bytes back gives the button word
    key = (p.compare_z, p.z, p.compare_c, p.c)
    names = {
        (True, True, False, False): "Equals",
        (True, False, False, False): "NotEquals",
        (False, False, True, True): "GreaterThanOrEqualTo",
        (False, False, True, False): "LessThan",
        (True, False, True, True): "GreaterThan",
    }
    name = names.get(key)
    return None if name is None else (name, value)


def _port_name(source: int, size: int) -> str:
    if size == 2 and source == AD0:
        return "Battery"
    if size == 2 and AD0 < source <= _AD_LAST and (source - AD0) % 2 == 0:
        return f"AD{(source - AD0) // 2}"
    if size == 1 and PA1 <= source < PA1 + PA_VALUES.size:
        return f"PA{source - PA1 + 1}"
    return f"RAM {source:04X}h"


# ----------------------------------------------------------------------------- image -> data


@dataclass(frozen=True)
class ButtonBinding:
    """A vector package: CALL/JUMP ``target`` when the button word compares to ``buttons``."""

    buttons: int
    compare_type: str
    target: int
    jump: bool = False

    @property
    def button_names(self) -> str:
        """``UP|S1`` style names of the button word (``?`` for unknown bits)."""
        return button_names(self.buttons)


def button_names(word: int) -> str:
    """``UP|S1`` style names of a remote's button word (``?`` for unknown bits)."""
    b = Button(word & 0x1F7F)
    names = [x.name for x in Button if x and x in b and x.name]
    if word & ~0x1F7F:
        names.append(f"?{word & ~0x1F7F:#x}")
    return "|".join(names) or "NONE"


@dataclass(frozen=True)
class MotionSlot:
    """One motion slot of an image: its frames (cut by SIZE byte) and what starts it."""

    slot: int
    address: int
    frames: tuple[bytes, ...]
    bindings: tuple[ButtonBinding, ...] = ()
    startup: bool = False
    priority: tuple[int, ...] = ()

    @property
    def size(self) -> int:
        return sum(map(len, self.frames))

    def rom_bytes(self) -> bytes:
        return b"".join(self.frames)


@dataclass(frozen=True)
class ImageContents:
    """What a HeartToHeart4 2.2 image holds, in the project's terms."""

    description: ImageDescription
    motions: tuple[MotionSlot, ...]
    bindings: tuple[ButtonBinding, ...]
    other_packages: tuple[VectorPackage, ...] = ()
    servos: dict[int, dict[str, int]] = field(default_factory=dict)
    priority: dict[int, dict[str, object]] = field(default_factory=dict)
    undecoded: tuple[UndecodedSlot, ...] = ()
    """The slots holding bytes that are neither erased nor frames (a slot with none before
    them is in no :attr:`motions`)."""

    @property
    def system_register(self) -> int:
        return self.description.system_register

    @property
    def config(self) -> bytes:
        """The system register as the project's ``Config`` bytes."""
        return u16_bytes(self.system_register)

    @property
    def adc_reference(self) -> bytes:
        return AD_CHANNELS.pack(*self.description.ad_references)

    @property
    def title(self) -> str:
        return self.description.title

    @property
    def startup_motion_address(self) -> int:
        s = self.description.startup_motion
        return -1 if s is None else s

    def motion(self, slot: int) -> MotionSlot:
        for m in self.motions:
            if m.slot == slot:
                return m
        raise KeyError(f"no motion in slot {slot}")


def _parse(rom: bytes, motion_layout: MotionLayout) -> ImageDescription:
    """parse_image_for, with errors that say the bytes are not an image and why."""
    if len(rom) != ROM_SIZE:
        raise LayoutError(f"a ROM image is {ROM_SIZE} bytes, not {len(rom)}")
    for byte, what in ((0xFF, "erased (every byte FF)"), (0x00, "zeroed (every byte 00)")):
        if rom.count(byte) == len(rom):
            raise FrameError(f"not a HeartToHeart4 image: the whole ROM is {what}")
    try:
        return parse_image_for(rom, motion_layout)
    except ProtocolError as exc:
        why = str(exc)
        at = _offset(why)
        if at is not None and rom[at : at + 16] == b"\xff" * len(rom[at : at + 16]):
            why = f"erased ROM at {at:05X}h, where the system area should hold a frame ({why})"
        message = f"not a HeartToHeart4 {motion_layout.version} image: {why}"
        if isinstance(exc, ChecksumError):
            raise ChecksumError(message, exc.frame) from None
        if isinstance(exc, FrameError):
            raise FrameError(message) from None
        raise ProtocolError(message) from None


def _offset(message: str) -> int | None:
    """The ROM offset a frame error names ("... at offset 1013 ...", "at 003F5h")."""
    m = re.search(r"offset (\d+)|at ([0-9A-Fa-f]{5})h", message)
    if m is None:
        return None
    return int(m.group(1)) if m.group(1) else int(m.group(2), 16)


def read_image(rom: bytes | bytearray, motion_layout: MotionLayout = HTH4_22) -> ImageContents:
    """The motions and settings of a HeartToHeart4 2.2 image (via :func:`rom.parse_image`).

    :class:`~rcb4hv.errors.ProtocolError` (its message starting "not a HeartToHeart4 image",
    naming an erased or zeroed ROM) if it is not such an image;
    :class:`~rcb4hv.errors.LayoutError` (a ValueError) for a wrong size.
    """
    desc = _parse(bytes(rom), motion_layout)
    bindings: list[ButtonBinding] = []
    others: list[VectorPackage] = []
    for p in desc.vector_packages:
        cmp = _package_compare(p)
        if cmp is None:
            others.append(p)
        else:
            bindings.append(ButtonBinding(cmp[1], cmp[0], p.target, p.jump))
    priority: dict[int, dict[str, object]] = {}
    for i, pm in enumerate(desc.priority_motions):
        if pm is not None:
            priority[i] = {
                "port": _port_name(pm.source, pm.size),
                "compare_type": _COMPARE_NAME[pm.compare],
                "value": pm.value,
                "address": pm.target,
            }
    slots: list[MotionSlot] = []
    for m in desc.motions:
        a = motion_layout.address(m.slot)
        slots.append(
            MotionSlot(
                slot=m.slot,
                address=a,
                frames=m.frames,
                bindings=tuple(b for b in bindings if b.target == a),
                startup=desc.startup_motion == a,
                priority=tuple(i for i, p in priority.items() if p["address"] == a),
            )
        )
    servos = {
        s.ics: {
            "id": s.servo_id or 0,
            "trim": s.trim,
            "home": s.home,
            "mixing1_address": s.mix1_source,
            "mixing1_rate": mix_rate(s.mix1_method),
            "mixing2_address": s.mix2_source,
            "mixing2_rate": mix_rate(s.mix2_method),
        }
        for s in desc.servos
    }
    bad = undecoded_slots(rom, motion_layout)
    return ImageContents(desc, tuple(slots), tuple(bindings), tuple(others), servos, priority, bad)
