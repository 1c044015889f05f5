"""Left-right mirroring of poses and motions through a robot model's joint map.

For each servo the model maps, :meth:`RobotModel.mirror_angles` names the mirror joint and
whether the angle changes sign (roll and yaw do, pitch and grip do not). Through each
servo's sign and zero offset (:meth:`RobotModel.motion_angle` /
:meth:`~RobotModel.motion_value`) a motion value ``v`` of servo ``i`` becomes, on the mirror
servo ``j``::

    v' = CENTER + offset_j + sign_j * f * sign_i * (v - CENTER - offset_i)      f = +1 or -1

The trims do not enter: a motion value is the output before the board adds the trim (spec 9),
so its joint angle is ``model.motion_angle(i, v)`` and the value that puts servo ``j`` at an
angle is ``model.motion_value(j, angle)``. The formula is that round trip
without the floating point: all integers, so mirroring twice gives back every value exactly
(``f`` and the signs are ±1 and the joint map is an involution). Hold and free (7FFFh,
8000h) move to the mirror servo unchanged; servos the model does not map keep their value.
SetStretch / SetSpeed entries swap their servos the same way. Every other block is kept.
"""

from __future__ import annotations

from collections.abc import Mapping

from rcb4hv.errors import EditError, NoRobotModelError, ProtocolError
from rcb4hv.hth4.model import Motion
from rcb4hv.hth4.motioncode import split_frames
from rcb4hv.hth4.poses import (
    DEFAULT_CHECKS,
    SPECIAL_POSITIONS,
    Checks,
    EntryEdit,
    motion_blocks,
    pose_entry,
)
from rcb4hv.protocol import SetSpeed, SetStretch, decode_command
from rcb4hv.protocol.memory import CENTER
from rcb4hv.robot.model import RobotModel

__all__ = ["MirrorMap", "mirror_map", "mirror_motion_entries", "mirror_values"]

MirrorMap = Mapping[int, tuple[int, int]]
"""ICS number -> (mirror ICS number, counts factor ±1)."""


def mirror_map(model: RobotModel | None) -> dict[int, tuple[int, int]]:
    """For each servo the model maps: its mirror servo and the factor in counts space
    (``sign_j * f * sign_i``; see the module docstring)."""
    if model is None:
        raise NoRobotModelError(
            "mirroring needs the robot's joint map, and this project's robot has no model: "
            "name one (--robot, e.g. kxr-l2 or khr3hv)"
        )
    out: dict[int, tuple[int, int]] = {}
    for s in model.servos:
        ((target, unit),) = model.mirror_angles({s.joint: 1.0}).items()
        other = model.servo_for_joint(target)
        if other is None:
            raise EditError(
                f"{model.name}: joint {s.joint!r} mirrors onto {target!r}, which no servo drives"
            )
        out[s.index] = (other.index, other.sign * round(unit) * s.sign)
    return out


def _offsets(model: RobotModel) -> dict[int, int]:
    return {s.index: s.offset for s in model.servos}


def mirror_values(model: RobotModel, values: Mapping[int, int]) -> dict[int, int]:
    """The mirror image of one pose (ICS number -> motion value)."""
    table = mirror_map(model)
    offset = _offsets(model)
    out: dict[int, int] = {}
    for ics, v in values.items():
        if ics not in table:
            out[ics] = v
            continue
        j, factor = table[ics]
        if v in SPECIAL_POSITIONS:
            out[j] = v
        else:
            out[j] = CENTER + offset[j] + factor * (v - CENTER - offset[ics])
    return out


def _mirror_settings(table: MirrorMap, entry: bytes) -> bytes | None:
    """A SetStretch / SetSpeed entry with its servos swapped; None for any other entry."""
    try:
        frames, tail = split_frames(entry)
        if len(frames) != 1:
            return None
        cmd = decode_command(frames[0])
    except ProtocolError:
        return None
    if not isinstance(cmd, (SetStretch, SetSpeed)):
        return None
    swapped = {table.get(i, (i, 1))[0]: v for i, v in cmd.values}
    return type(cmd)(dict(sorted(swapped.items()))).encode() + tail


def mirror_motion_entries(
    motion: Motion,
    model: RobotModel | None,
    checks: Checks = DEFAULT_CHECKS,
    pose: int | None = None,
) -> EntryEdit:
    """``motion``'s entries with every pose (or only pose number ``pose``) and every
    SetStretch / SetSpeed entry mirrored; entry lengths do not change."""
    table = mirror_map(model)
    assert model is not None
    entries = list(motion.frames)
    for block in motion_blocks(motion):
        if block.pose is not None:
            if pose is not None and block.pose.index != pose:
                continue
            values = mirror_values(model, block.pose.values)
            checks.check(values, None, f"motion {motion.slot} pose {block.pose.index + 1}")
            entries[block.entry] = pose_entry(values, block.pose.speed, block.pose.set_update_flag)
        elif pose is None and block.kind in ("SetStretch", "SetSpeed"):
            swapped = _mirror_settings(table, motion.frames[block.entry])
            if swapped is not None:
                entries[block.entry] = swapped
    if pose is not None and not any(b.pose and b.pose.index == pose for b in motion_blocks(motion)):
        raise EditError(f"motion {motion.slot} has no pose {pose + 1}")
    return EntryEdit(tuple(entries), tuple(range(len(entries))))
