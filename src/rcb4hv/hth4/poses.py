"""The blocks of a project motion, its poses, and pose edits on the list of stored entries.

HeartToHeart4 compiles each "Pos" box of a flowchart into one ``MotionData`` entry holding a
single RunConstFrameServo frame (10h: one speed, in output periods, for all the servos it
names; spec 8). Those entries are a motion's **poses**. Every other entry (SetStretch /
SetSpeed, MOVE, arithmetic, JUMP, CALL, RETURN, the closing ``03 0D 10 FF``) is a
**block** that the editor shows and keeps byte for byte but does not edit.

The functions here work on the entry list of one motion and say, for each new entry, which
old entry it came from (:class:`EntryEdit`); :mod:`rcb4hv.hth4.edit` turns that into new ROM
addresses for every JUMP / CALL in the project. The rule: a branch keeps pointing at the
instruction it pointed at; a branch to a deleted pose goes to what followed it; the motion's
start (its first byte, where the remote, the startup hook and CALLs enter) stays its start.

Value checks (:class:`Checks`): speeds inside 1-255 (:mod:`rcb4hv.protocol.ranges`),
positions the ICS wire carries and, given a robot model, joint angles inside the joints' hard
(mechanical) limits are required; a position outside the documented 3500-11500 or an angle
outside a joint's narrower advisory range only warns (the robot maker's own motions use
both). A motion value ``v`` is the servo's output before the board adds the trim (spec 9:
value sent = output + base), so its joint angle is :meth:`RobotModel.motion_angle` ``(i, v)``,
whatever the trim.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from rcb4hv.errors import EditError, JointLimitError, ProtocolError
from rcb4hv.hth4.argcheck import as_int, as_model, as_positions
from rcb4hv.hth4.model import Motion
from rcb4hv.hth4.motioncode import branch_target, split_frames
from rcb4hv.ics.codec import WIRE_MAX
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD, RunConstFrameServo, decode_command
from rcb4hv.protocol.describe import describe_command
from rcb4hv.protocol.ranges import documented_position, documented_servo_speed
from rcb4hv.robot.model import RobotModel

__all__ = [
    "DEFAULT_CHECKS",
    "Block",
    "Checks",
    "EntryEdit",
    "Pose",
    "delete_pose_entries",
    "insert_pose_entries",
    "motion_blocks",
    "motion_poses",
    "move_pose_entries",
    "pose_entry",
    "set_pose_entries",
]

_log = logging.getLogger(__name__)

SPECIAL_POSITIONS = (POSITION_HOLD, POSITION_FREE)
"""Hold (7FFFh) and free (8000h) are commands, not angles (spec 8): never converted."""


@dataclass(frozen=True)
class Pose:
    """One pose: the ``index``-th pose of its motion, stored in entry ``entry``."""

    index: int
    entry: int
    speed: int
    positions: tuple[tuple[int, int], ...]
    set_update_flag: bool = True

    @property
    def values(self) -> dict[int, int]:
        """ICS number -> position."""
        return dict(self.positions)

    @property
    def frames(self) -> int:
        """Frame count of the move (= :attr:`speed`, in output periods)."""
        return self.speed


@dataclass(frozen=True)
class Block:
    """One stored entry of a motion: a pose or a read-only block (``pose`` is None)."""

    entry: int
    kind: str
    text: str
    pose: Pose | None = None
    target: int | None = None
    """The ROM address a JUMP / CALL goes to."""

    @property
    def editable(self) -> bool:
        return self.pose is not None


def motion_blocks(motion: Motion) -> tuple[Block, ...]:
    """Every stored entry of ``motion`` in ROM order, poses numbered from 0."""
    out: list[Block] = []
    count = 0
    for i, entry in enumerate(motion.frames):
        try:
            frames, tail = split_frames(entry)
        except ProtocolError as exc:
            out.append(Block(i, "invalid", f"not a command frame: {exc}"))
            continue
        if len(frames) != 1:
            kind = "invalid" if not frames else "frames"
            out.append(Block(i, kind, " ; ".join(_describe(f) for f in frames) or entry.hex(" ")))
            continue
        try:
            cmd = decode_command(frames[0])
        except ProtocolError as exc:
            out.append(Block(i, "invalid", f"not a valid command: {exc}"))
            continue
        if isinstance(cmd, RunConstFrameServo) and not tail:
            pose = Pose(count, i, cmd.speed, cmd.positions, cmd.set_update_flag)
            out.append(Block(i, "pose", f"pose {count + 1}: frame {cmd.speed}", pose))
            count += 1
            continue
        kind = type(cmd).__name__
        out.append(Block(i, kind, describe_command(cmd), target=branch_target(frames[0])))
    return tuple(out)


def _describe(frame: bytes) -> str:
    try:
        return describe_command(decode_command(frame))
    except ProtocolError:
        return frame.hex(" ").upper()


def motion_poses(motion: Motion) -> tuple[Pose, ...]:
    """The poses of ``motion`` in ROM order."""
    return tuple(b.pose for b in motion_blocks(motion) if b.pose is not None)


def pose_entry(pose_positions: Mapping[int, int], speed: int, update: bool = True) -> bytes:
    """The stored entry of a pose: one RunConstFrameServo frame."""
    return RunConstFrameServo(speed, dict(sorted(pose_positions.items())), update).encode()


@dataclass(frozen=True)
class Checks:
    """What pose values must respect. ``force`` keeps refused values (an override).

    Refused (:class:`EditError`; :class:`JointLimitError` when a joint's hard limit is
    among the reasons): frame counts outside 1..255, positions the ICS wire cannot carry
    (above 3FFFh, besides hold and free) and, given a robot model, joint angles beyond the
    joint's hard (mechanical) limits. Only warned (:meth:`advisories`, logged by
    :meth:`check`): positions outside the documented 3500..11500 (the servo stops at the end
    of its travel; Kondo's own motions command 2100 or 12700 to push a joint to its end) and
    joint angles inside the hard limits but outside the joint's advisory range
    (:meth:`RobotModel.limit_check`). The robot maker's own motions are never refused."""

    model: RobotModel | None = None
    force: bool = False

    def __post_init__(self) -> None:
        as_model(self.model, "Checks.model")

    def _angles(self, positions: Mapping[int, int]) -> list[tuple[int, int, str, float]]:
        """(ics, value, joint, angle) of every mapped servo at a position (not hold/free)."""
        if self.model is None:
            return []
        mapped = set(self.model.indices)
        return [
            (ics, v, self.model.servo(ics).joint, self.model.motion_angle(ics, v))
            for ics, v in sorted(positions.items())
            if ics in mapped and v not in SPECIAL_POSITIONS and 0 <= v <= WIRE_MAX
        ]

    def _limit_text(self, ics: int, value: int, joint: str, angle: float, hard: bool) -> str:
        assert self.model is not None
        j = self.model.joint(joint)
        lo, hi = (j.lower, j.upper) if hard else j.advisory_range
        what = "hard (mechanical) limits" if hard else "advisory range"
        return (
            f"ICS {ics} ({joint}): {value} is {_deg(angle)} deg, outside the joint's {what} "
            f"{_deg(lo)}..{_deg(hi)} deg"
        )

    def problems(self, positions: Mapping[int, int], speed: int | None) -> list[str]:
        """What is refused (see the class docstring)."""
        out: list[str] = []
        if speed is not None and not documented_servo_speed(speed):
            out.append(f"frame count {speed} outside the documented 1..255")
        for ics, value in sorted(positions.items()):
            if value not in SPECIAL_POSITIONS and not 0 <= value <= WIRE_MAX:
                out.append(f"ICS {ics}: {value} is no ICS position (0..{WIRE_MAX})")
        for ics, value, joint, angle in self._angles(positions):
            assert self.model is not None
            if self.model.limit_check(joint, angle) == "hard":
                out.append(self._limit_text(ics, value, joint, angle, hard=True))
        return out

    def advisories(self, positions: Mapping[int, int]) -> list[str]:
        """What only warns: positions outside the documented range, angles outside a joint's
        advisory range (inside its hard limits)."""
        out: list[str] = []
        for ics, value in sorted(positions.items()):
            if not documented_position(value) and 0 <= value <= WIRE_MAX:
                out.append(
                    f"ICS {ics}: {value} outside the documented 3500..11500 (the servo stops "
                    "at the end of its travel)"
                )
        for ics, value, joint, angle in self._angles(positions):
            assert self.model is not None
            if self.model.limit_check(joint, angle) == "advisory":
                out.append(self._limit_text(ics, value, joint, angle, hard=False))
        return out

    def check(self, positions: Mapping[int, int], speed: int | None, what: str) -> list[str]:
        """Raise naming every problem, unless :attr:`force`; log the advisories (a warning
        each) and return them."""
        problems = self.problems(positions, speed)
        if problems and not self.force:
            text = f"{what}: " + "; ".join(problems) + " (force keeps them: --force)"
            if any("hard (mechanical) limits" in p for p in problems):
                raise JointLimitError(text)
            raise EditError(text)
        advisories = self.advisories(positions)
        for line in advisories:
            _log.warning("%s: %s (kept: only a warning)", what, line)
        return advisories


def _deg(radians: float) -> str:
    return f"{math.degrees(radians):.1f}"


DEFAULT_CHECKS = Checks()
"""Documented ranges checked, no robot model, no override."""


# ----------------------------------------------------------------------------- entry edits


@dataclass(frozen=True)
class EntryEdit:
    """A motion's new entries and, for each, the index of the old entry it came from (None
    for a new entry). Old entries missing from ``origins`` were deleted."""

    entries: tuple[bytes, ...]
    origins: tuple[int | None, ...]


def _identity(motion: Motion) -> list[int | None]:
    return list(range(len(motion.frames)))


def _pose(motion: Motion, index: int) -> Pose:
    index = as_int("pose index", index)
    poses = motion_poses(motion)
    if not 0 <= index < len(poses):
        raise EditError(f"motion {motion.slot} has {len(poses)} poses; no pose {index + 1}")
    return poses[index]


def set_pose_entries(
    motion: Motion,
    index: int,
    positions: Mapping[int, int] | None = None,
    speed: int | None = None,
    checks: Checks = DEFAULT_CHECKS,
) -> EntryEdit:
    """Pose ``index`` with the servos in ``positions`` changed (servos it did not name are
    added) and/or its frame count set to ``speed``."""
    index = as_int("pose index", index)
    positions = as_positions(f"motion {motion.slot} pose {index + 1}", positions)
    speed = None if speed is None else as_int("frame count", speed)
    pose = _pose(motion, index)
    values = pose.values
    values.update(positions or {})
    new_speed = pose.speed if speed is None else speed
    checks.check(positions or {}, speed, f"motion {motion.slot} pose {index + 1}")
    entries = list(motion.frames)
    if values != pose.values or new_speed != pose.speed:
        entries[pose.entry] = pose_entry(values, new_speed, pose.set_update_flag)
    return EntryEdit(tuple(entries), tuple(_identity(motion)))


def insert_pose_entries(
    motion: Motion,
    at: int,
    positions: Mapping[int, int],
    speed: int,
    checks: Checks = DEFAULT_CHECKS,
) -> EntryEdit:
    """A new pose inserted as pose ``at`` (0 = first; the number of poses = after the last,
    before the block that follows it)."""
    at = as_int("pose index", at)
    positions = as_positions(f"motion {motion.slot} new pose {at + 1}", positions)
    speed = as_int("frame count", speed)
    poses = motion_poses(motion)
    if not 0 <= at <= len(poses):
        raise EditError(f"motion {motion.slot}: insert at 1..{len(poses) + 1}, not {at + 1}")
    if not positions:
        raise EditError("a pose needs at least one servo position")
    checks.check(positions, speed, f"motion {motion.slot} new pose {at + 1}")
    if at < len(poses):
        where = poses[at].entry
    elif poses:
        where = poses[-1].entry + 1
    else:
        where = _body_end(motion)
    entries: list[bytes] = list(motion.frames)
    origins = _identity(motion)
    entries.insert(where, pose_entry(positions, speed))
    origins.insert(where, None)
    return EntryEdit(tuple(entries), tuple(origins))


def _body_end(motion: Motion) -> int:
    """Where the first pose of a motion without poses goes: before its final RETURNs."""
    blocks = motion_blocks(motion)
    end = len(blocks)
    while end > 0 and blocks[end - 1].kind == "Return":
        end -= 1
    return end


def delete_pose_entries(motion: Motion, index: int) -> EntryEdit:
    """Pose ``index`` removed."""
    pose = _pose(motion, index)
    entries = list(motion.frames)
    origins = _identity(motion)
    del entries[pose.entry]
    del origins[pose.entry]
    return EntryEdit(tuple(entries), tuple(origins))


def _chain(motion: Motion, index: int) -> list[Pose]:
    """The poses of the linear chain pose ``index`` belongs to: the run of consecutive pose
    and settings entries (SetStretch / SetSpeed) with no branch, MOVE or RETURN between."""
    blocks = motion_blocks(motion)
    pose = _pose(motion, index)
    lo = hi = pose.entry
    linear = ("pose", "SetStretch", "SetSpeed")
    while lo > 0 and blocks[lo - 1].kind in linear:
        lo -= 1
    while hi + 1 < len(blocks) and blocks[hi + 1].kind in linear:
        hi += 1
    return [b.pose for b in blocks[lo : hi + 1] if b.pose is not None]


def move_pose_entries(motion: Motion, index: int, to: int) -> EntryEdit:
    """Pose ``index`` moved to be pose ``to``, inside its linear chain (swapping places with
    the poses between); EditError if ``to`` lies in another chain."""
    index, to = as_int("pose index", index), as_int("target pose index", to)
    chain = _chain(motion, index)
    numbers = [p.index for p in chain]
    if to not in numbers:
        raise EditError(
            f"motion {motion.slot}: pose {index + 1} can move within poses "
            f"{numbers[0] + 1}..{numbers[-1] + 1} (its chain has no branch in between), "
            f"not to {to + 1}"
        )
    slots = [p.entry for p in chain]
    order = [p.entry for p in chain]
    moved = order.pop(numbers.index(index))
    order.insert(numbers.index(to), moved)
    entries = list(motion.frames)
    origins = _identity(motion)
    for place, source in zip(slots, order, strict=True):
        entries[place] = motion.frames[source]
        origins[place] = source
    return EntryEdit(tuple(entries), tuple(origins))


def replace_pose_values(
    motion: Motion, updates: Iterable[tuple[int, Mapping[int, int]]], checks: Checks
) -> EntryEdit:
    """Several poses' servo values replaced at once (mirroring): (pose index, values)."""
    poses = motion_poses(motion)
    entries = list(motion.frames)
    for index, values in updates:
        pose = poses[index]
        checks.check(values, None, f"motion {motion.slot} pose {index + 1}")
        if dict(values) != pose.values:
            entries[pose.entry] = pose_entry(values, pose.speed, pose.set_update_flag)
    return EntryEdit(tuple(entries), tuple(_identity(motion)))
