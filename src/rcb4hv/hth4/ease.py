"""Easing between two poses: "ease in/out over K poses" (``rcb4hv project ease``).

The board moves every servo linearly from one pose to the next over the pose's frame count
(spec 8: RunConstFrameServo), so a move starts and stops at full speed. Easing splits the
move into pose ``I`` into ``K`` shorter linear moves whose end points follow an easing curve
of time: the same time on the board, the same start and end, but the speed rises from rest
and falls back to it. The board takes N + 1 output periods for a pose of N frames (spec 9:
the update flag clears the period after the move ends, and only then does the program
fetch the next pose), so the move of F frames lasts F + 1 periods and its K poses share
those: their frames add up to F + 1 - K. :func:`eased_poses` computes the poses (so the
editor can preview them in 3D); :func:`ease_pose` writes them into the motion (``K - 1``
new poses inserted before pose ``I``, whose frame count becomes the last segment's).

Curves (``t`` from 0 to 1): ``in-out`` = (1 - cos πt) / 2, ``in`` = 1 - cos(πt/2), ``out`` =
sin(πt/2). Servos whose target is hold (7FFFh) or free (8000h) keep that value in every new
pose: those are commands, not positions.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from typing import Literal

from rcb4hv.errors import EditError
from rcb4hv.hth4.edit import insert_pose, set_pose, used_motion
from rcb4hv.hth4.model import Motion, Project
from rcb4hv.hth4.poses import DEFAULT_CHECKS, SPECIAL_POSITIONS, Checks, motion_poses
from rcb4hv.protocol import move_periods

__all__ = ["CURVES", "Curve", "ease_pose", "eased_poses"]

Curve = Literal["in-out", "in", "out"]
CURVES: dict[str, Callable[[float], float]] = {
    "in-out": lambda t: (1.0 - math.cos(math.pi * t)) / 2.0,
    "in": lambda t: 1.0 - math.cos(math.pi * t / 2.0),
    "out": lambda t: math.sin(math.pi * t / 2.0),
}


def _before(motion: Motion, index: int) -> dict[int, int]:
    """The value of every servo just before pose ``index`` (0-based) starts: the last value
    an earlier pose of the motion gave it."""
    values: dict[int, int] = {}
    for pose in motion_poses(motion)[:index]:
        values.update(pose.values)
    return values


def _int(what: str, value: object) -> int:
    """``value`` as an int (numpy integers too); EditError naming ``what`` otherwise."""
    if isinstance(value, bool):
        raise EditError(f"{what} must be an int, not {value!r}")
    try:
        return operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        raise EditError(f"{what} must be an int, not {value!r}") from None


def eased_poses(
    motion: Motion, index: int, over: int, curve: Curve = "in-out"
) -> list[tuple[int, dict[int, int]]]:
    """The ``over`` poses (frames, values by ICS number) that replace the move into pose
    ``index`` (0-based); the last one is pose ``index`` itself, its values unchanged.
    An unknown ``curve`` raises :class:`~rcb4hv.errors.EditError` listing the curves."""
    ease = CURVES.get(curve) if isinstance(curve, str) else None
    if ease is None:
        raise EditError(f"unknown easing curve {curve!r} (known: {', '.join(CURVES)})")
    index = _int("pose index", index)
    over = _int("the number of poses to ease over", over)
    poses = motion_poses(motion)
    if not 0 <= index < len(poses):
        raise EditError(f"motion {motion.slot} has {len(poses)} poses; no pose {index + 1}")
    if index == 0:
        raise EditError(
            f"motion {motion.slot} pose 1 has no pose before it in the motion: nothing to ease from"
        )
    if over < 2:
        raise EditError(f"easing needs 2 or more poses, not {over}")
    target = poses[index]
    periods = move_periods(target.frames)  # on the board (module docstring)
    if 2 * over > periods:
        raise EditError(
            f"motion {motion.slot} pose {index + 1} moves over {target.frames} frames: it "
            f"cannot be split into {over} poses of one frame or more (each takes its frames "
            f"+ 1 output periods on the board; at most {periods // 2} poses)"
        )
    start = _before(motion, index)
    out: list[tuple[int, dict[int, int]]] = []
    done = 0
    for k in range(1, over + 1):
        end = round(periods * k / over)
        s = ease(k / over)
        values: dict[int, int] = {}
        for ics, b in target.values.items():
            a = start.get(ics, b)
            if b in SPECIAL_POSITIONS or a in SPECIAL_POSITIONS:
                values[ics] = b
            else:
                values[ics] = round(a + (b - a) * s)
        out.append((end - done - move_periods(0), values if k < over else dict(target.values)))
        done = end
    return out


def ease_pose(
    project: Project,
    slot: int,
    index: int,
    over: int,
    curve: Curve = "in-out",
    checks: Checks = DEFAULT_CHECKS,
) -> Project:
    """Motion ``slot`` with the move into pose ``index`` (0-based) eased over ``over`` poses
    (:func:`eased_poses`)."""
    motion = used_motion(project, slot)
    steps = eased_poses(motion, index, over, curve)
    for k, (frames, values) in enumerate(steps[:-1]):
        project = insert_pose(project, slot, index + k, values, frames, checks)
    last_frames, _ = steps[-1]
    return set_pose(project, slot, index + over - 1, None, last_frames, checks)
