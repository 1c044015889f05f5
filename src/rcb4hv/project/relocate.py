"""Which HeartToHeart4 layout a project is stored for, and moving a project to another layout.

A project stores each motion's ROM ``Address``; HeartToHeart4 2.2 puts slot n at
0B80h + 800h (n - 1), 2.0/2.1 at 0BB8h + 800h (n - 1), 1.3 at 0BB8h + 1300h (n - 1)
(:data:`rcb4hv.rom.layout.LAYOUTS`). :func:`project_layout` finds the layout every used motion
agrees with.

:func:`relocate_project` moves every motion to its slot in another layout. Inside a motion,
JUMP and CALL targets are absolute ROM addresses, so each one is rewritten:

* a target inside motion slot n at offset k (of the source layout) moves to slot n, offset k of
  the target layout (a jump within the motion, or a call of another motion);
* the source layout's main loop moves to the target layout's main loop, and its startup stub
  (the RETURN after the last slot) to the target's;
* ``FFFFFFh`` (HeartToHeart4's unresolved target) stays as it is;
* anything else (boot code, data images, a slot the target layout does not have, an offset
  past the target's slot size) cannot be moved: :class:`~rcb4hv.errors.LayoutError` names the
  motion, the frame and the target.

Only the address bytes and the checksum of a JUMP/CALL frame change; every other byte of the
project (other frames, the ``FF`` end markers, the COND byte) is kept. The startup motion,
priority motions and the low-power motion addresses move the same way.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Final

from rcb4hv.errors import LayoutError
from rcb4hv.hth4 import Project
from rcb4hv.hth4.model import Motion as Hth4Motion
from rcb4hv.hth4.model import PriorityMotionSlot
from rcb4hv.project.image import build_project_image, split_frames
from rcb4hv.project.options import DEFAULT_OPTIONS, BuildOptions
from rcb4hv.protocol import Op
from rcb4hv.protocol.frame import seal
from rcb4hv.rom.layout import LAYOUTS, MotionLayout

__all__ = [
    "UNRESOLVED",
    "image_layout",
    "layout_named",
    "move_address",
    "project_image",
    "project_layout",
    "relocate_project",
]

UNRESOLVED: Final = 0xFFFFFF
"""The JUMP/CALL target HeartToHeart4 writes for an unresolved flowchart arrow."""

_ORDER: Final = ("2.2", "2.1", "1.3")  # 2.0 is the same layout as 2.1


def layout_named(version: str) -> MotionLayout:
    """The layout of HeartToHeart4 ``version`` (2.2, 2.1, 2.0, 1.3); LayoutError if unknown."""
    try:
        return LAYOUTS[version]
    except KeyError:
        known = ", ".join(sorted(LAYOUTS))
        raise LayoutError(f"unknown HeartToHeart4 layout {version!r} (known: {known})") from None


def _fits(m: Hth4Motion) -> list[str]:
    """The layouts (of :data:`_ORDER`) that put ``m``'s slot at its stored address."""
    return [
        n
        for n in _ORDER
        if m.slot <= LAYOUTS[n].motion_count and LAYOUTS[n].address(m.slot) == m.address
    ]


def project_layout(project: Project) -> MotionLayout:
    """The layout whose slot addresses match every used motion's stored ``Address``.

    A project without motions is a 2.2 project. LayoutError when no layout fits."""
    used = project.used_motions
    fits = [_fits(m) for m in used]
    for name in _ORDER:
        if all(name in f for f in fits):
            return LAYOUTS[name]
    odd = [m for m, f in zip(used, fits, strict=True) if not f]
    if odd:
        m = odd[0]
        detail = f"motion {m.key} (slot {m.slot}) is stored for {m.address:05X}h"
    else:
        pairs = zip(used[:4], fits, strict=False)
        detail = "; ".join(f"{m.key} fits {'/'.join(f)}" for m, f in pairs)
    raise LayoutError(
        "the motions' stored addresses fit no single HeartToHeart4 layout (2.2: 0B80h + "
        f"800h (n-1), 2.0/2.1: 0BB8h + 800h (n-1), 1.3: 0BB8h + 1300h (n-1)): {detail}"
    )


def move_address(address: int, source: MotionLayout, target: MotionLayout) -> int | None:
    """Where ``address`` of ``source`` lies in ``target`` (see the module docstring); None if it
    cannot be moved."""
    if address == UNRESOLVED:
        return address
    if address == source.main_loop:
        return target.main_loop
    if address == source.startup_stub:
        return target.startup_stub
    slot = source.motion_at(address)
    if slot is None:
        return None
    offset = address - source.address(slot)
    if slot > target.motion_count or offset >= target.motion_stride:
        return None
    return target.address(slot) + offset


def _move_frame(frame: bytes, source: MotionLayout, target: MotionLayout, where: str) -> bytes:
    if len(frame) != 7 or frame[1] not in (Op.JUMP, Op.CALL):
        return frame
    address = int.from_bytes(frame[2:5], "little")
    moved = move_address(address, source, target)
    if moved is None:
        what = "JUMP" if frame[1] == Op.JUMP else "CALL"
        raise LayoutError(
            f"{where}: {what} {address:05X}h targets no motion slot, main loop or startup stub "
            f"of HeartToHeart4 {source.version} that HeartToHeart4 {target.version} has; "
            f"it cannot be moved"
        )
    body = frame[:2] + moved.to_bytes(3, "little") + frame[5:6]
    return seal(body)


def _check_slots(project: Project, target: MotionLayout) -> None:
    """LayoutError naming the first used motion in a slot ``target`` does not have (checked
    before any motion moves, so a JUMP into such a slot is not what the error names)."""
    beyond = [m for m in project.motions if m.slot > target.motion_count and not m.is_empty]
    if beyond:
        m = beyond[0]
        more = f" ({len(beyond)} motions are past slot {target.motion_count})"
        raise LayoutError(
            f"motion {m.key} ({m.name}): HeartToHeart4 {target.version} has only "
            f"{target.motion_count} motion slots" + (more if len(beyond) > 1 else "")
        )


def _move_motion(m: Hth4Motion, source: MotionLayout, target: MotionLayout) -> Hth4Motion:
    if m.slot > target.motion_count:  # empty (_check_slots refuses the others)
        return m
    if len(m.rom_bytes()) > target.motion_stride:
        raise LayoutError(
            f"motion {m.key} ({m.name}): {len(m.rom_bytes())} bytes do not fit a "
            f"{target.motion_stride}-byte slot of HeartToHeart4 {target.version}"
        )
    entries: list[bytes] = []
    for i, entry in enumerate(m.frames):
        frames, tail = split_frames(entry)
        where = f"motion {m.key} ({m.name}) frame {i + 1}"
        entries.append(b"".join(_move_frame(f, source, target, where) for f in frames) + tail)
    return replace(m, frames=tuple(entries), address=target.address(m.slot))


def _move_ref(address: int, source: MotionLayout, target: MotionLayout, what: str) -> int:
    if address < 0:
        return address
    moved = move_address(address, source, target)
    if moved is None:
        raise LayoutError(
            f"{what} {address:05X}h is no motion slot of HeartToHeart4 {source.version} that "
            f"HeartToHeart4 {target.version} has; it cannot be moved"
        )
    return moved


def relocate_project(
    project: Project, target: MotionLayout, source: MotionLayout | None = None
) -> Project:
    """``project`` with every motion moved to its slot in ``target`` and every JUMP/CALL target,
    startup, priority and low-power address rewritten (module docstring).

    ``source`` defaults to :func:`project_layout`. LayoutError where something cannot move."""
    if source is None:
        source = project_layout(project)
    if source == target:
        return project
    _check_slots(project, target)
    motions = tuple(_move_motion(m, source, target) for m in project.motions)
    priority: list[PriorityMotionSlot] = []
    for p in project.priority_motions:
        if p.motion is None:
            priority.append(p)
            continue
        a = _move_ref(p.motion.address, source, target, f"priority motion {p.key}")
        priority.append(replace(p, motion=replace(p.motion, address=a)))
    return replace(
        project,
        motions=motions,
        startup_motion_address=_move_ref(
            project.startup_motion_address, source, target, "the startup motion"
        ),
        low_power_motion_address=_move_ref(
            project.low_power_motion_address, source, target, "the low-power motion"
        ),
        priority_motions=tuple(priority),
    )


def project_image(
    project: Project, version: str | None = None, *, options: BuildOptions = DEFAULT_OPTIONS
) -> tuple[bytes, MotionLayout]:
    """(256 KB image, its layout) of ``project``: in the layout its motions are stored for, or
    in HeartToHeart4 ``version``'s layout, moving the motions there first (``options``: settings
    that mean "none", :mod:`rcb4hv.project.options`)."""
    source = project_layout(project)
    target = source if version is None else layout_named(version)
    if (target.motion_base, target.motion_stride, target.main_loop) != (
        source.motion_base,
        source.motion_stride,
        source.main_loop,
    ):
        project = relocate_project(project, target, source)
    return build_project_image(project, target, options=options), target


def image_layout(
    image: bytes, version: str | None = None, *, default: MotionLayout | None = None
) -> MotionLayout:
    """The layout of a ROM image: HeartToHeart4 ``version``'s, else detected from where its
    main loop starts (:func:`rcb4hv.rom.older.detect_image_layout`); if unknown ``default``,
    or LayoutError without one."""
    from rcb4hv.rom.older import detect_image_layout

    if version is not None:
        return layout_named(version)
    found = detect_image_layout(image)
    if found is None and default is not None:
        return default
    if found is None:
        raise LayoutError(
            "no main loop at 0044Bh (HeartToHeart4 2.2) nor at 003FDh (2.0/2.1/1.3); "
            "give the layout (--layout)"
        )
    return found
