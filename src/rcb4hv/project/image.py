"""HeartToHeart4 project <-> HeartToHeart4 2.2 ROM image.

:func:`project_description` maps a :class:`rcb4hv.hth4.Project` onto a
:class:`rcb4hv.rom.ImageDescription`, :func:`build_project_image` lays it out with
:func:`rcb4hv.rom.build_image` (256 KB, spec 11.2), and :func:`read_image` reads an image back
into :class:`ImageContents`: the settings and, per motion slot, the frames it holds.

The mapping, field by field:

* ``Config`` -> system register (ROM 05DCh; the boot code writes it with ICS_F clear first).
* ``AdcReference`` (22 bytes) -> the 11 AD reference words.
* ``ServoConfigParams``: every slot whose ``Mode`` is not ``None`` becomes a servo block for
  ICS ``DeviceNumber`` (0-34): ``ID``, ``Trim`` (block +2, the base value), ``Position`` (the
  home position of the boot frame at 03F5h), ``MixingNAddress`` (block +14 / +17, 65535 = none)
  and ``MixingNRate`` (block +16 / +19: bit 7 = sign, bits 6-0 = multiplier; the unit of the
  editor's rate is not documented, so the rate is stored as the multiplier, a negative rate
  with the sign bit). Unused slots stay unallocated (``alloc[n]`` = FFFFh).
* ``Kri3`` -> the KRI-3 block copied to RAM 034Ch (``ICS 35``): bytes ``Code, ID, 0, 0``, the
  button word (high byte first), PA1-PA4, checksum. Bytes +2/+3 are not documented anywhere;
  they are written as 0.
* ``ButtonData`` / ``CompareType`` of each used motion -> a vector package (spec 11.3) that
  CALLs the motion when the button word (RAM 0350h) compares to the value (:data:`COMPARE`);
  in slot order, at most 32.
* ``StartupMotionAddress`` (``-1`` = none: the RETURN stub) -> the CALL at 00444h.
* ``PriorityMotionCollection`` keys ``0``-``12`` -> the 13 main-loop checks (``Address`` ``-1``
  = none, see :mod:`rcb4hv.project.options` for this and an empty startup slot); ``Port``
  ``Battery`` compares AD0 (RAM 0022h), ``AD<n>`` compares AD n, ``PA<n>`` the remote's
  analogue value n (one byte). ``LowPowerMotionAddress`` (older projects), when not ``-1``
  (none), becomes a battery check ``AD0 <= LowPowerValue`` in the first free slot.
* ``ProjectTitle`` -> the 32-byte title (cp932; a longer title is cut at a character boundary).
* ``MotionData`` -> the motion's bytes at 0B80h + 2048 (n - 1), copied exactly as stored,
  including HeartToHeart4's ``FF`` end-of-motion byte after the final RETURN.

Every function takes ``motion_layout`` (default HeartToHeart4 2.2): an older project (motions
at 0BB8h, main loop 003FDh) is laid out with :mod:`rcb4hv.rom.older`. Detecting a project's
layout and moving a project to another layout is :mod:`rcb4hv.project.relocate`.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Final

from rcb4hv.hth4 import Project
from rcb4hv.hth4 import ServoConfig as Hth4Servo
from rcb4hv.hth4.motioncode import split_frames
from rcb4hv.hth4.newproject import COMPARE, priority_port_source
from rcb4hv.project.options import DEFAULT_OPTIONS, BuildOptions
from rcb4hv.protocol import Button
from rcb4hv.protocol.memory import (
    AD_CHANNELS,
    ADDR,
    PA_VALUES,
    Kri3Block,
    button_operand,
    mix_method,
    mix_rate,
    u16_bytes,
)
from rcb4hv.rom import (
    ImageDescription,
    ImageMotion,
    ImagePriorityMotion,
    ImageServo,
    Kri3Config,
    UndecodedSlot,
    VectorPackage,
    layout,
    undecoded_slots,
)
from rcb4hv.rom.layout import HTH4_22, MotionLayout
from rcb4hv.rom.older import build_image_for, parse_image_for

__all__ = [
    "COMPARE",
    "ButtonBinding",
    "ImageContents",
    "MotionSlot",
    "build_project_image",
    "motion_image_frames",
    "project_description",
    "read_image",
    "split_frames",
]

log = logging.getLogger(__name__)

_COMPARE_NAME: Final = {v: k for k, v in COMPARE.items()}

AD0: Final = ADDR.ad(0)
PA1: Final = ADDR.PA[0]
_AD_LAST: Final = ADDR.ad(ADDR.AD_COUNT - 1)


# ----------------------------------------------------------------------------- helpers


def motion_image_frames(entry_frames: Sequence[bytes]) -> list[bytes]:
    """The executable frames of a project motion (each entry cut at its SIZE byte).

    An entry may be a frame followed by FF bytes (HeartToHeart4's end marker); anything else
    after a frame is an error (ValueError).
    """
    out: list[bytes] = []
    for n, entry in enumerate(entry_frames):
        frames, tail = split_frames(bytes(entry))
        if not frames or tail.strip(b"\xff"):
            raise ValueError(
                f"frame {n + 1} ({bytes(entry)[:8].hex(' ')}...) is not a command frame"
            )
        out.extend(frames)
    return out


def _rate_to_method(rate: int, what: str) -> int:
    if not -127 <= rate <= 127:
        raise ValueError(f"{what} {rate} is outside -127..127")
    return mix_method(rate)


def _servo(s: Hth4Servo) -> ImageServo:
    where = f"servo {s.key!r} (ICS {s.device_number})"
    if not 0 <= s.device_number <= 34:
        raise ValueError(f"{where}: ICS number outside 0..34")
    return ImageServo(
        ics=s.device_number,
        servo_id=s.id,
        trim=s.trim,
        home=s.position,
        mix1_source=s.mixing1_address & 0xFFFF,
        mix1_method=_rate_to_method(s.mixing1_rate, f"{where}: mixing 1 rate"),
        mix2_source=s.mixing2_address & 0xFFFF,
        mix2_method=_rate_to_method(s.mixing2_rate, f"{where}: mixing 2 rate"),
    )


def _button_raw(buttons: int) -> int:
    """The button word as the little-endian RAM word the board compares (high byte first)."""
    return button_operand(buttons)


def _vector_package(buttons: int, compare: str, target: int) -> VectorPackage:
    try:
        cmp = COMPARE[compare]
    except KeyError:
        raise ValueError(f"unknown CompareType {compare!r}") from None
    if not 0 < buttons <= 0xFFFF:
        raise ValueError(f"button word {buttons:#x} out of range")
    raw = _button_raw(buttons)
    dst = ADDR.BUTTONS
    if cmp == "le":  # dst <= v  <=>  dst < v + 1
        if raw == 0xFFFF:
            cmp = "ge"
            raw = 0
        else:
            cmp, raw = "lt", raw + 1
    if cmp == "eq":
        return VectorPackage(dst, raw, target)
    if cmp == "ne":
        return VectorPackage(dst, raw, target, z=False)
    if cmp == "ge":  # C = 1 when dst - src >= 0
        return VectorPackage(dst, raw, target, compare_z=False, z=False, compare_c=True, c=True)
    if cmp == "lt":
        return VectorPackage(dst, raw, target, compare_z=False, z=False, compare_c=True, c=False)
    # gt: not zero and no borrow
    return VectorPackage(dst, raw, target, z=False, compare_c=True, c=True)


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


def _kri3_block(project: Project) -> bytes:
    k = project.kri3
    block = Kri3Block(k.code, k.id, 0, k.button_value, k.pa1, k.pa2, k.pa3, k.pa4, k.checksum)
    try:
        return block.to_bytes()
    except ValueError as exc:
        raise ValueError(f"KRI-3 settings hold a value out of range: {exc}") from None


def _title(text: str | None) -> str:
    t = (text or "").replace("\x00", "")
    while len(t.encode("cp932", errors="replace")) > layout.TITLE_SIZE:
        t = t[:-1]
    if t != (text or "").replace("\x00", ""):
        log.warning("project title %r cut to %r (32 bytes in ROM)", text, t)
    return t.encode("cp932", errors="replace").decode("cp932")


# ----------------------------------------------------------------------------- project -> image


def project_description(
    project: Project,
    motion_layout: MotionLayout = HTH4_22,
    *,
    options: BuildOptions = DEFAULT_OPTIONS,
) -> ImageDescription:
    """The :class:`~rcb4hv.rom.ImageDescription` of ``project`` (see the module docstring).

    ValueError when the project cannot be laid out in the 2.2 image: a motion stored for
    another ROM address (another HeartToHeart4 version), a motion larger than its slot,
    an unknown CompareType or priority port, more than 32 button bindings.
    """
    servos = tuple(_servo(s) for s in project.servos if s.in_use)
    if len(project.adc_reference) != 22:
        raise ValueError(f"AdcReference holds {len(project.adc_reference)} bytes, expected 22")
    motions: list[ImageMotion] = []
    packages: list[VectorPackage] = []
    for m in sorted(project.used_motions, key=lambda m: m.slot):
        count = motion_layout.motion_count
        if not 1 <= m.slot <= count:
            raise ValueError(f"motion {m.key}: slot {m.slot} outside 1..{count}")
        address = motion_layout.address(m.slot)
        if m.address != address:
            raise ValueError(
                f"motion {m.key} ({m.name}) is stored for ROM {m.address:05X}h, but the "
                f"HeartToHeart4 {motion_layout.version} layout puts slot {m.slot} at "
                f"{address:05X}h"
            )
        try:
            motions.append(ImageMotion(m.slot, motion_image_frames(m.frames)))
        except ValueError as exc:
            raise ValueError(f"motion {m.key} ({m.name}): {exc}") from None
        if len(m.rom_bytes()) > layout.MOTION_SIZE:
            raise ValueError(f"motion {m.key} ({m.name}) does not fit its 2048-byte slot")
        if m.button_data:
            packages.append(_vector_package(m.button_data, m.compare_type, address))
    if len(packages) > layout.VECTOR_PACKAGE_COUNT:
        raise ValueError(f"{len(packages)} button bindings; the board holds at most 32")
    priority: list[ImagePriorityMotion | None] = [None] * layout.PRIORITY_COUNT
    for index, pm in project.active_priority_motions:
        if index >= layout.PRIORITY_COUNT:
            raise ValueError(f"priority check {index} outside 0..12")
        source, size = priority_port_source(pm.port)
        try:
            compare = COMPARE[pm.compare_type]
        except KeyError:
            raise ValueError(
                f"priority check {index}: unknown CompareType {pm.compare_type!r}"
            ) from None
        target = pm.address
        if target < 0:  # a check configured with no motion
            if options.priority_none == "skip":
                continue
            target = layout.STARTUP_STUB
        priority[index] = ImagePriorityMotion(source, compare, pm.value, target, size)
    if project.low_power_motion_address >= 0:
        free = [i for i, p in enumerate(priority) if p is None]
        if not free:
            raise ValueError("no free priority check for the low-power motion")
        priority[free[0]] = ImagePriorityMotion(
            AD0, "le", project.low_power_value, project.low_power_motion_address
        )
    startup = project.startup_motion_address
    if options.empty_startup == "stub" and all(m.address != startup for m in motions):
        startup = -1
    return ImageDescription(
        system_register=project.system_register,
        ad_references=project.adc_reference_words,
        servos=servos,
        kri3=Kri3Config(_kri3_block(project)),
        vector_packages=tuple(packages),
        title=_title(project.project_title),
        startup_motion=startup if startup >= 0 else None,
        priority_motions=tuple(priority),
        motions=tuple(motions),
    )


def build_project_image(
    project: Project,
    motion_layout: MotionLayout = HTH4_22,
    *,
    options: BuildOptions = DEFAULT_OPTIONS,
) -> bytes:
    """The 256 KB ROM image of ``project`` in ``motion_layout`` (default HeartToHeart4 2.2);
    ``options``: settings that mean "none", :mod:`rcb4hv.project.options`.

    Each motion's bytes are copied exactly as the project stores them (FF end marker
    included) over the builder's output, which holds the same frames.
    """
    desc = project_description(project, motion_layout, options=options)
    image = bytearray(build_image_for(desc, motion_layout))
    for m in project.used_motions:
        data = m.rom_bytes()
        a = m.address
        image[a : a + len(data)] = data
    return bytes(image)


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


def read_image(rom: bytes | bytearray, motion_layout: MotionLayout = HTH4_22) -> ImageContents:
    """The motions and settings of a HeartToHeart4 2.2 image (via :func:`rom.parse_image`).

    :class:`~rcb4hv.errors.ProtocolError` if it is not such an image; ValueError for a wrong
    size.
    """
    desc = parse_image_for(rom, motion_layout)
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
