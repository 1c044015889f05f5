"""A generated walk as a HeartToHeart4 motion, stored in a project.

The walk is sampled at the board's output period; a motion slot holds 2048 bytes, so the
poses are stored every ``m`` output periods (the smallest ``m`` that fits, usually a few:
the board moves each servo linearly between two stored poses). The first pose names every
servo (the arms at home), the others only the legs' servos (the rest hold).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import Protocol

from rcb4hv.gait.generate import Walk
from rcb4hv.hth4.keyframes import Keyframe, motion_from_keyframes, now_text
from rcb4hv.hth4.model import Motion, Project
from rcb4hv.hth4.newproject import new_project
from rcb4hv.protocol import SystemRegister
from rcb4hv.robot.ik import limb
from rcb4hv.robot.model import RobotModel
from rcb4hv.rom.layout import HTH4_22, MotionLayout

__all__ = [
    "FIRST_MOVE_S",
    "load_or_new",
    "period_ms",
    "play_motion",
    "walk_keyframes",
    "walk_motion",
]

FIRST_MOVE_S = 0.5
"""Time to move from wherever the robot stands into the walk's first pose (s)."""


def period_ms(project: Project) -> int:
    """The project's output period (ms)."""
    return SystemRegister.from_word(project.system_register).frame_period_ms


def walk_keyframes(model: RobotModel, w: Walk, period: int, every: int) -> list[Keyframe]:
    """The walk's poses every ``every`` output periods of ``period`` ms as keyframes."""
    legs = {j.name for foot in (_feet(model)) for j in limb(model, foot)}
    values = [model.motion_values(p) for p in w.poses]
    leg_idx = [s.index for s in model.servos if s.joint in legs]
    out = [Keyframe(FIRST_MOVE_S, values[0])]
    picks = list(range(every, len(values), every))
    if picks[-1] != len(values) - 1:
        picks.append(len(values) - 1)
    last = 0
    for i in picks:
        out.append(Keyframe((i - last) * period / 1000.0, {k: values[i][k] for k in leg_idx}))
        last = i
    return out


def _feet(model: RobotModel) -> list[str]:
    from rcb4hv.gait.generate import Body

    b = Body.of(model)
    return [b.left, b.right]


def walk_motion(
    model: RobotModel,
    w: Walk,
    *,
    slot: int,
    name: str,
    period: int = 15,
    button: int = 0,
    layout: MotionLayout | None = None,
) -> tuple[Motion, int]:
    """The walk as a motion for ``slot`` and the output periods between its stored poses."""
    lay = HTH4_22 if layout is None else layout
    for every in range(1, 64):
        try:
            m = motion_from_keyframes(
                walk_keyframes(model, w, period, every), slot=slot, name=name, period_ms=period,
                button=button, changed_only=True, date="", layout=lay,
            )  # fmt: skip
        except ValueError as e:
            if "a motion slot holds" in str(e):
                continue
            raise ValueError(
                f"{e}: the walk takes a joint past its servo's travel; a smaller lift, turn, "
                "stride or width"
            ) from None
        return replace(m, date=now_text()), every
    raise ValueError("the walk does not fit a motion slot; take fewer steps")


def load_or_new(path: Path, model: RobotModel) -> Project:
    """The project at ``path``, or a new one for ``model`` when there is no file yet. A project
    for another robot (``model`` maps servos it does not use) is refused with
    :class:`~rcb4hv.errors.RobotModelError`, by the rule every command uses
    (:func:`rcb4hv.hth4.robotpick.project_model`): a walk for one robot on another's servos."""
    from rcb4hv.hth4 import load_project
    from rcb4hv.hth4.robotpick import project_model

    if not path.exists():
        return new_project(model)
    project = load_project(path)
    project_model(project, model)
    return project


class FramePlayer(Protocol):
    """What :func:`play_motion` needs of a client (:class:`rcb4hv.client.Rcb4Client`)."""

    def run_const_frame_servo(self, speed: int, positions: Mapping[int, int]) -> None: ...


def play_motion(
    client: FramePlayer, motion: Motion, period: int, sleep: Callable[[float], None]
) -> int:
    """Send ``motion``'s poses to a board as RunConstFrameServo commands, waiting out each
    move (``sleep``, seconds); the number of poses sent."""
    from rcb4hv.hth4.poses import motion_blocks

    sent = 0
    for b in motion_blocks(motion):
        if b.pose is not None:
            client.run_const_frame_servo(b.pose.speed, b.pose.values)
            sleep(b.pose.speed * period / 1000.0)
            sent += 1
    return sent
