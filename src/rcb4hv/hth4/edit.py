"""Edits of a HeartToHeart4 project: pure functions from a :class:`Project` to a new one.

Every function takes a project and returns a new project (the model is immutable), so undo
and redo are a list of projects (:class:`rcb4hv.hth4.session.EditSession`). What an edit
does not touch keeps its objects, and so its bytes when saved.

Poses (:mod:`rcb4hv.hth4.poses`): :func:`set_pose`, :func:`insert_pose`,
:func:`duplicate_pose`, :func:`delete_pose`, :func:`move_pose`. Mirroring
(:mod:`rcb4hv.hth4.mirror`): :func:`mirror_pose`, :func:`mirror_motion` (in place or into a
free slot). Motions: :func:`rename_motion`, :func:`move_motion`, :func:`bind_button`,
:func:`new_motion`. Servos: :func:`set_trim`, :func:`set_home`.

When entries change length or order, every JUMP / CALL into the motion, in any motion, and
the startup / priority / low-power addresses are rewritten (:func:`apply_entry_edit`). Motions
are addressed by their 1-based slot, poses by their 0-based index.
"""

from __future__ import annotations

import bisect
import logging
from collections.abc import Callable, Iterable, Mapping
from dataclasses import replace

from rcb4hv.errors import EditError, NoRobotModelError, RobotModelError
from rcb4hv.hth4.argcheck import as_int, as_model, as_name
from rcb4hv.hth4.keyframes import END_MARKER, now_text
from rcb4hv.hth4.mirror import mirror_motion_entries
from rcb4hv.hth4.model import COMPARE, Motion, Project, ServoConfig
from rcb4hv.hth4.motioncode import AddressMap, retarget_motion, retarget_project, slot_size
from rcb4hv.hth4.motionlist import button_label
from rcb4hv.hth4.poses import (
    DEFAULT_CHECKS,
    Checks,
    EntryEdit,
    delete_pose_entries,
    insert_pose_entries,
    motion_poses,
    move_pose_entries,
    set_pose_entries,
)
from rcb4hv.hth4.robotpick import servo_table
from rcb4hv.protocol import POSITION_MAX, POSITION_MIN, Return
from rcb4hv.protocol.memory import CENTER
from rcb4hv.robot.builtin import check_indices
from rcb4hv.robot.model import RobotModel

log = logging.getLogger(__name__)

__all__ = [
    "TRIM_LIMIT",
    "apply_entry_edit",
    "bind_button",
    "binding_holders",
    "delete_pose",
    "duplicate_pose",
    "insert_pose",
    "layout_map",
    "mirror_model",
    "mirror_motion",
    "mirror_pose",
    "move_motion",
    "move_pose",
    "new_motion",
    "rename_motion",
    "set_home",
    "set_pose",
    "set_trim",
    "used_motion",
]

TRIM_LIMIT = min(CENTER - POSITION_MIN, POSITION_MAX - CENTER)
"""4000: a larger trim would put the servo's centre outside its 3500..11500 range (spec 8)."""


def _motion(project: Project, slot: int) -> Motion:
    slot = as_int("motion slot", slot)
    try:
        return project.motion(slot)
    except KeyError:
        raise EditError(f"the project has no motion slot {slot}") from None


def used_motion(project: Project, slot: int) -> Motion:
    """The motion in ``slot``; EditError if the slot is empty or missing."""
    m = _motion(project, slot)
    if m.is_empty:
        raise EditError(f"motion slot {slot} is empty")
    return m


def _put(project: Project, motion: Motion) -> Project:
    return replace(
        project,
        motions=tuple(motion if m.slot == motion.slot else m for m in project.motions),
    )


def _starts(entries: tuple[bytes, ...]) -> list[int]:
    out = [0]
    for e in entries:
        out.append(out[-1] + len(e))
    return out


def apply_entry_edit(project: Project, slot: int, change: EntryEdit) -> Project:
    """``project`` with motion ``slot``'s entries replaced by ``change`` and every address
    into the motion moved with the entry it points into (poses module docstring)."""
    motion = _motion(project, slot)
    if change.entries == motion.frames:
        return project
    edited = replace(motion, frames=change.entries)
    return retarget_project(_put(project, edited), layout_map(motion, change))


def layout_map(motion: Motion, change: EntryEdit) -> AddressMap:
    """Where each ROM address into ``motion`` goes when its entries become ``change``'s: with
    the entry it points into (a deleted entry's: what followed it; the start stays the
    start); EditError if the new entries do not fit the slot, or for a point inside an entry
    that changed length."""
    slot = motion.slot
    size = sum(map(len, change.entries))
    room = slot_size(motion)
    if size > room:
        raise EditError(f"motion {slot}: {size} bytes do not fit its {room}-byte slot")
    old, new = _starts(motion.frames), _starts(change.entries)
    new_index = {o: n for n, o in enumerate(change.origins) if o is not None}
    base = motion.address
    end = base + old[-1] + (1 if old[-1] < room else 0)

    def where(address: int) -> int:
        if not base < address < end:
            return address  # outside the motion, or its start (which stays its start)
        off = address - base
        i = bisect.bisect_right(old, off) - 1
        if i >= len(motion.frames):
            return base + new[-1]
        inner = off - old[i]
        j = i
        while j < len(motion.frames) and j not in new_index:
            j, inner = j + 1, 0  # a deleted entry: go to what followed it
        if j == len(motion.frames):
            return base + new[-1]
        n = new_index[j]
        if inner and len(change.entries[n]) != len(motion.frames[j]):
            raise EditError(
                f"motion {slot}: a branch targets {address:05X}h inside an entry that changed "
                "length; edit it in HeartToHeart4"
            )
        return base + new[n] + inner

    return where


# ----------------------------------------------------------------------------- poses


def set_pose(
    project: Project,
    slot: int,
    index: int,
    positions: Mapping[int, int] | None = None,
    speed: int | None = None,
    checks: Checks = DEFAULT_CHECKS,
) -> Project:
    """Pose ``index`` of motion ``slot`` with new servo values and/or frame count."""
    m = used_motion(project, slot)
    return apply_entry_edit(project, slot, set_pose_entries(m, index, positions, speed, checks))


def insert_pose(
    project: Project,
    slot: int,
    at: int,
    positions: Mapping[int, int],
    speed: int,
    checks: Checks = DEFAULT_CHECKS,
) -> Project:
    """A new pose inserted as pose ``at`` of motion ``slot``."""
    m = _motion(project, slot)
    if m.is_empty:
        raise EditError(f"motion slot {slot} is empty: create the motion first (new_motion)")
    return apply_entry_edit(project, slot, insert_pose_entries(m, at, positions, speed, checks))


def duplicate_pose(project: Project, slot: int, index: int) -> Project:
    """A copy of pose ``index`` inserted right after it."""
    index = as_int("pose index", index)
    poses = motion_poses(used_motion(project, slot))
    if not 0 <= index < len(poses):
        raise EditError(f"motion {slot} has {len(poses)} poses; no pose {index + 1}")
    p = poses[index]
    return insert_pose(project, slot, index + 1, p.values, p.speed, Checks(force=True))


def delete_pose(project: Project, slot: int, index: int) -> Project:
    """Pose ``index`` of motion ``slot`` removed."""
    return apply_entry_edit(project, slot, delete_pose_entries(used_motion(project, slot), index))


def move_pose(project: Project, slot: int, index: int, to: int) -> Project:
    """Pose ``index`` moved to position ``to`` within its linear chain."""
    return apply_entry_edit(project, slot, move_pose_entries(used_motion(project, slot), index, to))


# ----------------------------------------------------------------------------- mirroring


def mirror_pose(
    project: Project,
    slot: int,
    index: int,
    model: RobotModel | None,
    checks: Checks = DEFAULT_CHECKS,
) -> Project:
    """Pose ``index`` of motion ``slot`` replaced by its left-right mirror image (``model``:
    :func:`mirror_model`)."""
    model = mirror_model(project, model)
    index = as_int("pose index", index)
    m = used_motion(project, slot)
    return apply_entry_edit(project, slot, mirror_motion_entries(m, model, checks, pose=index))


def mirror_model(project: Project, model: object) -> RobotModel | None:
    """``model`` checked for mirroring ``project``: a :class:`RobotModel` (or None, which
    mirroring refuses) whose servo indices the project has, the rule
    :func:`rcb4hv.hth4.robotpick.project_model` applies; another robot's model would mirror
    onto the wrong servos. NoRobotModelError (an EditError and a RobotModelError) otherwise."""
    checked = as_model(model)
    if checked is not None:
        try:
            check_indices(checked, servo_table(project))
        except RobotModelError as exc:
            raise NoRobotModelError(f"cannot mirror with this robot model: {exc}") from None
    return checked


def _free_target(project: Project, to: int) -> Motion:
    target = _motion(project, to)
    if not target.is_empty:
        raise EditError(f"motion slot {to} holds {target.name!r}; pick a free slot")
    return target


def _slot_shift(source: Motion, target: Motion) -> Callable[[int], int]:
    """Addresses inside ``source``'s slot (its whole reserved space) moved to ``target``'s."""
    lo, hi = source.address, source.address + slot_size(source)

    def where(address: int) -> int:
        return target.address + address - lo if lo <= address < hi else address

    return where


def _shift(source: Motion, target: Motion) -> Motion:
    """``source``'s content in ``target``'s slot, its internal branches moved along."""
    where = _slot_shift(source, target)
    moved = replace(
        source, key=target.key, number=target.number, address=target.address, frames=source.frames
    )
    return retarget_motion(moved, where)


def mirror_motion(
    project: Project,
    slot: int,
    model: RobotModel | None,
    *,
    to: int | None = None,
    name: str | None = None,
    checks: Checks = DEFAULT_CHECKS,
    date: str | None = None,
) -> Project:
    """Motion ``slot`` mirrored left-right: in place, or (``to``) as a new motion in free slot
    ``to`` named ``name`` (default: the source name + `` (mirror)``), with no button bound and
    the current ``date``. ``model`` must fit the project (:func:`mirror_model`)."""
    model = mirror_model(project, model)
    m = used_motion(project, slot)
    if name is not None:
        name = as_name("motion name", name)
    change = mirror_motion_entries(m, model, checks)
    if to is None:
        return apply_entry_edit(project, slot, change)
    if as_int("target slot", to) == slot:
        raise EditError(
            f"motion {slot} cannot be mirrored into its own slot as a new motion: leave out "
            "the target slot (--to) to mirror it in place"
        )
    target = _free_target(project, to)
    mirrored = _shift(replace(m, frames=change.entries), target)
    if sum(map(len, mirrored.frames)) > slot_size(target):
        raise EditError(f"motion {slot} does not fit slot {to}")
    new = replace(
        mirrored,
        name=name or f"{m.name} (mirror)",
        date=date or now_text(),
        button_data=0,
        compare_type=target.compare_type,
        key_code=target.key_code,
    )
    return _put(project, new)


# ----------------------------------------------------------------------------- motions


def rename_motion(project: Project, slot: int, name: str) -> Project:
    """Motion ``slot`` renamed (a non-blank name without control characters)."""
    name = as_name("motion name", name)
    return _put(project, replace(used_motion(project, slot), name=name))


def move_motion(project: Project, slot: int, to: int) -> Project:
    """Motion ``slot`` moved to free slot ``to``; every branch, CALL, startup and priority
    address into it follows. The two slots swap their entries, so ``slot`` is left with the
    empty entry (named after its key, as HeartToHeart4 names empty slots)."""
    source = used_motion(project, slot)
    target = _free_target(project, to)
    size = len(source.rom_bytes())
    if size > slot_size(target):
        raise EditError(f"motion {slot} ({size} bytes) does not fit slot {to}")
    moved = replace(source, key=target.key, number=target.number, address=target.address)
    vacated = replace(target, key=source.key, number=source.number, address=source.address)
    vacated = replace(vacated, name=source.key)
    where = _slot_shift(source, target)
    swapped = _put(_put(project, moved), vacated)
    return retarget_project(swapped, where)


def binding_holders(
    project: Project, button: int, compare_type: str = "Equals", *, besides: Iterable[int] = ()
) -> list[Motion]:
    """The used motions a remote ``button`` word (``compare_type``) starts, but for the slots
    ``besides``; none for word 0 (no binding)."""
    skip = set(besides)
    return [
        o
        for o in project.used_motions
        if button and o.slot not in skip and o.button == (button, compare_type)
    ]


def bind_button(
    project: Project,
    slot: int,
    button: int,
    compare_type: str = "Equals",
    *,
    force: bool = False,
) -> Project:
    """Motion ``slot`` started by remote button word ``button`` (0: unbind). EditError if
    another motion already has that binding, unless ``force``: then that motion loses it
    (the board starts the first motion bound to a word, so two would leave one dead)."""
    m = used_motion(project, slot)
    button = as_int("the button word", button)
    if not 0 <= button <= 0xFFFF:
        raise EditError(f"the button word is 16 bits (0..65535), not {button!r}")
    if compare_type not in COMPARE:
        raise EditError(f"unknown CompareType {compare_type!r} (known: {', '.join(COMPARE)})")
    holders = binding_holders(project, button, compare_type, besides=(slot,))
    if holders and not force:
        other = holders[0]
        raise EditError(
            f"{button_label(button)} (button word {button}) already starts motion "
            f"{other.slot} ({other.name}): unbind it first, or take it from that motion "
            "(`project bind --force`, or the Editor's override box)"
        )
    for other in holders:
        log.info("motion %d (%s) loses button word %d", other.slot, other.name, button)
        project = _put(project, replace(other, button_data=0))
    return _put(project, replace(m, button_data=button, compare_type=compare_type))


def new_motion(
    project: Project, slot: int, name: str, *, button: int = 0, date: str | None = None
) -> Project:
    """An empty motion (no poses: HeartToHeart4's closing RETURN only) in free slot ``slot``."""
    name = as_name("motion name", name)
    target = _free_target(project, slot)
    motion = replace(
        target,
        name=name,
        date=date or now_text(),
        frames=(Return().encode(), END_MARKER),
    )
    project = _put(project, motion)
    return bind_button(project, slot, button) if button else project


def new_motion_at_home(
    project: Project, slot: int, name: str, speed: int = 30, checks: Checks = DEFAULT_CHECKS
) -> Project:
    """A new motion in free slot ``slot`` with one pose: every servo in use at its home
    position, reached in ``speed`` output periods (a start to add poses to)."""
    home = {s.device_number: s.home_position for s in project.servos if s.in_use}
    return insert_pose(new_motion(project, slot, name), slot, 0, home, speed, checks)


# ----------------------------------------------------------------------------- servos


def _servo(project: Project, ics: int) -> ServoConfig:
    ics = as_int("ICS number", ics)
    try:
        return project.servo(ics)
    except KeyError:
        raise EditError(f"the project configures no servo ICS {ics}") from None


def _put_servo(project: Project, servo: ServoConfig) -> Project:
    return replace(
        project,
        servos=tuple(
            servo if s.device_number == servo.device_number else s for s in project.servos
        ),
    )


def set_trim(project: Project, ics: int, trim: int) -> Project:
    """Servo ``ics``'s trim set (|trim| <= :data:`TRIM_LIMIT`; numpy integers too)."""
    trim = as_int(f"ICS {ics}: trim", trim)
    if not -TRIM_LIMIT <= trim <= TRIM_LIMIT:
        raise EditError(f"ICS {ics}: trim {trim!r} outside -{TRIM_LIMIT}..{TRIM_LIMIT}")
    return _put_servo(project, replace(_servo(project, ics), trim=trim))


def set_home(project: Project, ics: int, position: int, checks: Checks = DEFAULT_CHECKS) -> Project:
    """Servo ``ics``'s home position set (an int; documented range and joint limits
    checked)."""
    position = as_int(f"ICS {ics}: home position", position)
    checks.check({ics: position}, None, f"home position of ICS {ics}")
    return _put_servo(project, replace(_servo(project, ics), position=position))
