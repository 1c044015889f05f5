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
from typing import Final

from rcb4hv.errors import Hth4FormatError, LayoutError, ProtocolError
from rcb4hv.hth4 import Project
from rcb4hv.hth4 import ServoConfig as Hth4Servo
from rcb4hv.hth4.motioncode import split_frames
from rcb4hv.hth4.newproject import COMPARE, priority_port_source
from rcb4hv.project.options import DEFAULT_OPTIONS, BuildOptions
from rcb4hv.protocol.memory import (
    ADDR,
    Kri3Block,
    button_operand,
    mix_method,
)
from rcb4hv.rom import (
    ImageDescription,
    ImageMotion,
    ImagePriorityMotion,
    ImageServo,
    Kri3Config,
    VectorPackage,
    layout,
)
from rcb4hv.rom.layout import HTH4_22, MotionLayout
from rcb4hv.rom.older import build_image_for

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
        try:
            frames, tail = split_frames(bytes(entry))
        except ProtocolError as exc:  # a bad checksum: the board refuses the frame
            raise ValueError(f"frame {n + 1} ({bytes(entry)[:8].hex(' ')}...): {exc}") from None
        if not frames or tail.strip(b"\xff"):
            raise ValueError(
                f"frame {n + 1} ({bytes(entry)[:8].hex(' ')}...) is not a command frame"
            )
        out.extend(frames)
    return out


def _servo_where(s: Hth4Servo) -> str:
    """The element path of a servo entry, for errors: ``ServoConfigParams/S02 (ICS 2)``."""
    return f"ServoConfigParams/{s.key} (ICS {s.device_number})"


def _in_range(where: str, field: str, value: int, lo: int, hi: int, note: str = "") -> None:
    if not lo <= value <= hi:
        raise Hth4FormatError(f"{where}/{field}", f"{value} outside {lo}..{hi}{note}")


def _rate_to_method(rate: int, where: str, field: str) -> int:
    _in_range(where, field, rate, -127, 127)
    return mix_method(rate)


def _mix_source(where: str, field: str, address: int) -> int:
    """A mixing source RAM address (65535 = none; -1, the same 16 bits, too)."""
    _in_range(where, field, address, -1, 0xFFFF, " (a RAM address; 65535 or -1: no mixing)")
    return address & 0xFFFF


def _servo(s: Hth4Servo) -> ImageServo:
    """The image servo block of one used servo entry; Hth4FormatError naming the servo and
    the field for a value its block cannot hold (nothing is cut to fit)."""
    where = _servo_where(s)
    _in_range(where, "DeviceNumber", s.device_number, 0, 34, " (ICS 35 is the KRI-3 receiver)")
    _in_range(where, "ID", s.id, 0, 0xFF)
    _in_range(where, "Trim", s.trim, -0x8000, 0x7FFF)
    _in_range(where, "Position", s.position, 0, 0xFFFF)
    return ImageServo(
        ics=s.device_number,
        servo_id=s.id,
        trim=s.trim,
        home=s.position,
        mix1_source=_mix_source(where, "Mixing1Address", s.mixing1_address),
        mix1_method=_rate_to_method(s.mixing1_rate, where, "Mixing1Rate"),
        mix2_source=_mix_source(where, "Mixing2Address", s.mixing2_address),
        mix2_method=_rate_to_method(s.mixing2_rate, where, "Mixing2Rate"),
    )


def _servos(project: Project) -> tuple[ImageServo, ...]:
    """The image servo blocks of the used servo entries; an ICS number two entries share is
    refused, naming both."""
    seen: dict[int, Hth4Servo] = {}
    for s in project.servos:
        if not s.in_use:
            continue
        first = seen.setdefault(s.device_number, s)
        if first is not s:
            raise Hth4FormatError(
                f"{_servo_where(s)}/DeviceNumber",
                f"ICS {s.device_number} is also servo {first.key}'s: each ICS number is "
                "configured once",
            )
    return tuple(_servo(s) for s in project.servos if s.in_use)


def _button_raw(buttons: int) -> int:
    """The button word as the little-endian RAM word the board compares (high byte first)."""
    return button_operand(buttons)


def _vector_package(
    buttons: int, compare: str, target: int, where: str = "ButtonData"
) -> VectorPackage:
    try:
        cmp = COMPARE[compare]
    except KeyError:
        known = ", ".join(COMPARE)
        raise Hth4FormatError(
            f"{where}/CompareType", f"unknown CompareType {compare!r} (known: {known})"
        ) from None
    if not 0 < buttons <= 0xFFFF:
        raise Hth4FormatError(f"{where}/ButtonData", f"button word {buttons} outside 1..65535")
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


def _kri3_block(project: Project) -> bytes:
    k = project.kri3
    block = Kri3Block(k.code, k.id, 0, k.button_value, k.pa1, k.pa2, k.pa3, k.pa4, k.checksum)
    try:
        return block.to_bytes()
    except ValueError as exc:
        raise Hth4FormatError("Kri3", f"a value out of range: {exc}") from None


def _title(text: str | None) -> str:
    t = (text or "").replace("\x00", "")
    while len(t.encode("cp932", errors="replace")) > layout.TITLE_SIZE:
        t = t[:-1]
    if t != (text or "").replace("\x00", ""):
        log.warning(
            "project title of %d characters cut to %r (32 bytes in ROM)", len(text or ""), t
        )
    return t.encode("cp932", errors="replace").decode("cp932")


# ----------------------------------------------------------------------------- project -> image


def project_description(
    project: Project,
    motion_layout: MotionLayout = HTH4_22,
    *,
    options: BuildOptions = DEFAULT_OPTIONS,
) -> ImageDescription:
    """The :class:`~rcb4hv.rom.ImageDescription` of ``project`` (see the module docstring).

    A project that cannot be laid out raises :class:`~rcb4hv.errors.LayoutError` (a motion
    stored for another ROM address, i.e. another HeartToHeart4 version, or larger than its
    slot); a value the image cannot hold raises :class:`~rcb4hv.errors.Hth4FormatError`
    naming the element (servo, motion, setting) and the range: an unknown CompareType or
    priority port, more than 32 button bindings, a trim, home, ID or mixing address outside
    its field, an ICS number configured twice. Nothing is cut to fit. Both are ValueErrors.
    """
    servos = _servos(project)
    try:
        system_register = project.system_register
    except ValueError as exc:
        raise Hth4FormatError("Config", str(exc)) from None
    if len(project.adc_reference) != 22:
        raise Hth4FormatError(
            "AdcReference", f"holds {len(project.adc_reference)} bytes, expected 22"
        )
    motions: list[ImageMotion] = []
    packages: list[VectorPackage] = []
    for m in sorted(project.used_motions, key=lambda m: m.slot):
        where = f"MotionDataCollection/{m.key} ({m.name})"
        count = motion_layout.motion_count
        if not 1 <= m.slot <= count:
            raise LayoutError(
                f"{where}/Number: slot {m.slot} outside the HeartToHeart4 "
                f"{motion_layout.version} layout's 1..{count}"
            )
        address = motion_layout.address(m.slot)
        if m.address != address:
            raise LayoutError(
                f"motion {m.key} ({m.name}) is stored for ROM {m.address:05X}h, but the "
                f"HeartToHeart4 {motion_layout.version} layout puts slot {m.slot} at "
                f"{address:05X}h"
            )
        try:
            motions.append(ImageMotion(m.slot, motion_image_frames(m.frames)))
        except ValueError as exc:
            raise Hth4FormatError(f"{where}/MotionData", str(exc)) from None
        if len(m.rom_bytes()) > layout.MOTION_SIZE:
            raise LayoutError(f"motion {m.key} ({m.name}) does not fit its 2048-byte slot")
        if m.button_data:
            packages.append(_vector_package(m.button_data, m.compare_type, address, where))
    if len(packages) > layout.VECTOR_PACKAGE_COUNT:
        raise Hth4FormatError(
            "MotionDataCollection", f"{len(packages)} button bindings; the board holds at most 32"
        )
    priority: list[ImagePriorityMotion | None] = [None] * layout.PRIORITY_COUNT
    for index, pm in project.active_priority_motions:
        where = f"PriorityMotionCollection/{index}"
        if index >= layout.PRIORITY_COUNT:
            raise Hth4FormatError(where, f"priority check {index} outside 0..12")
        try:
            source, size = priority_port_source(pm.port)
        except ValueError as exc:
            raise Hth4FormatError(f"{where}/Port", str(exc)) from None
        try:
            compare = COMPARE[pm.compare_type]
        except KeyError:
            raise Hth4FormatError(
                f"{where}/CompareType",
                f"unknown CompareType {pm.compare_type!r} (known: {', '.join(COMPARE)})",
            ) from None
        target = pm.address
        if target < 0:  # a check configured with no motion
            if options.priority_none == "skip":
                continue
            target = layout.STARTUP_STUB
        _in_range(where, "Address", target, -1, 0xFFFFFF)
        _in_range(where, "Value", pm.value, 0, 0xFFFF if size == 2 else 0xFF)
        priority[index] = _priority(where, source, compare, pm.value, target, size)
    if project.low_power_motion_address >= 0:
        _in_range("Rcb4", "LowPowerMotionAddress", project.low_power_motion_address, -1, 0xFFFFFF)
        _in_range("Rcb4", "LowPowerValue", project.low_power_value, 0, 0xFFFF)
        free = [i for i, p in enumerate(priority) if p is None]
        if not free:
            raise Hth4FormatError(
                "LowPowerMotionAddress", "no free priority check for the low-power motion"
            )
        priority[free[0]] = _priority(
            "Rcb4/LowPowerValue",
            AD0,
            "le",
            project.low_power_value,
            project.low_power_motion_address,
        )
    _in_range("Rcb4", "StartupMotionAddress", project.startup_motion_address, -1, 0xFFFFFF)
    startup = project.startup_motion_address
    if options.empty_startup == "stub" and all(m.address != startup for m in motions):
        startup = -1
    return _description(
        system_register=system_register,
        ad_references=project.adc_reference_words,
        servos=servos,
        kri3=Kri3Config(_kri3_block(project)),
        vector_packages=tuple(packages),
        title=_title(project.project_title),
        startup_motion=startup if startup >= 0 else None,
        priority_motions=tuple(priority),
        motions=tuple(motions),
    )


def _priority(
    where: str, source: int, compare: str, value: int, target: int, size: int = 2
) -> ImagePriorityMotion:
    """One main-loop check; a value it cannot compare is an Hth4FormatError at ``where``."""
    try:
        return ImagePriorityMotion(source, compare, value, target, size)  # type: ignore[arg-type]
    except ValueError as exc:
        raise Hth4FormatError(where, str(exc)) from None


def _description(**fields: object) -> ImageDescription:
    """The ImageDescription of ``fields``: a check it still refuses is an Hth4FormatError."""
    try:
        return ImageDescription(**fields)  # type: ignore[arg-type]
    except ValueError as exc:
        raise Hth4FormatError("Rcb4", f"the ROM image cannot hold it: {exc}") from None


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
    try:
        image = bytearray(build_image_for(desc, motion_layout))
    except LayoutError:
        raise
    except ValueError as exc:
        raise Hth4FormatError("Rcb4", f"the ROM image cannot hold it: {exc}") from None
    for m in project.used_motions:
        data = m.rom_bytes()
        a = m.address
        image[a : a + len(data)] = data
    return bytes(image)


from rcb4hv.project.imageread import (  # noqa: E402 - the reading half, re-exported here
    ButtonBinding,
    ImageContents,
    MotionSlot,
    read_image,
)
from rcb4hv.project.imageread import button_names as button_names  # noqa: E402
