"""A generated walk as a HeartToHeart4 motion, stored in a project.

The walk is sampled at the board's output period; a motion slot holds 2048 bytes, so the
poses are stored every ``m`` output periods (the smallest ``m`` that fits, usually a few:
the board moves each servo linearly between two stored poses). The first pose names every
servo (the arms at home), the others only the legs' servos (the rest hold).

A long walk repeats itself: after the first steps, every two steps (one of each foot) put
the joints through the same angles (the pattern is the same relative to the body, and the
preview controller settles), until the last steps stop it. Stored as one chain of poses, a
walk of many steps would keep a pose only every ``m`` = 10-20 periods, too few to follow the
walk. So when the chain has to be thinned, the motion stores the settled cycle once and
plays it in a loop counted in :data:`LOOP_COUNTER`, as Kondo's own walks loop ("5 steps":
a counter, the poses, a counted branch out and a JUMP back), between the start and the stop
stored as they are; whichever form keeps more poses is stored.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import NamedTuple, Protocol

from rcb4hv.errors import EditError, GaitError
from rcb4hv.gait.generate import Walk
from rcb4hv.gait.pattern import phase_samples, plan_footsteps
from rcb4hv.hth4.blocks.kinds import Block
from rcb4hv.hth4.blocks.program import compile_blocks
from rcb4hv.hth4.keyframes import (
    Keyframe,
    keyframe_frames,
    motion_from_frames,
    now_text,
    pose_commands,
)
from rcb4hv.hth4.model import Motion, Project
from rcb4hv.hth4.newproject import new_project
from rcb4hv.protocol import FRAME_PERIODS_MS, RunConstFrameServo, SystemRegister, move_periods
from rcb4hv.robot.ik import limb
from rcb4hv.robot.model import RobotModel
from rcb4hv.rom.layout import HTH4_22, MOTION_SIZE, MotionLayout

__all__ = [
    "CYCLE_TOLERANCE",
    "FIRST_MOVE_S",
    "LOOP_COUNTER",
    "Loop",
    "StoredWalk",
    "load_or_new",
    "period_ms",
    "play_motion",
    "play_moves",
    "steady_loop",
    "walk_keyframes",
    "walk_motion",
]

FIRST_MOVE_S = 0.5
"""Time to move from wherever the robot stands into the walk's first pose (s)."""
LOOP_COUNTER = 10
"""The board counter (COUNTER10, RAM) a looped walk counts its cycles in: Kondo's samples
count their loops in COUNTER0 only, so a motion of theirs that CALLs the walk inside its
own loop keeps its count."""
CYCLE_TOLERANCE = 4
"""Servo counts (about 0.14 degrees) within which two cycles of a walk are the same: a
documented choice, a few times the settled cycles' own difference (1 count, rounding)."""


@dataclass(frozen=True)
class Loop:
    """The settled cycle of a walk: its first sample, its length (samples: two steps) and
    how many times it repeats back to back."""

    start: int
    length: int
    repeats: int


class StoredWalk(NamedTuple):
    """A walk as a motion: the motion, the output periods between its stored poses, the
    loop it plays (None: one chain of poses) and the poses the board plays, in order (the
    loop unrolled)."""

    motion: Motion
    every: int
    loop: Loop | None
    moves: tuple[RunConstFrameServo, ...]


def period_ms(project: Project) -> int:
    """The project's output period (ms)."""
    return SystemRegister.from_word(project.system_register).frame_period_ms


def walk_keyframes(model: RobotModel, w: Walk, period: int, every: int) -> list[Keyframe]:
    """The walk's poses every ``every`` output periods of ``period`` ms as keyframes."""
    values = [model.motion_values(p) for p in w.poses]
    first = Keyframe(FIRST_MOVE_S, values[0])
    return [first, *_segment(values, _legs(model), 0, len(values) - 1, period, every)]


def _legs(model: RobotModel) -> list[int]:
    legs = {j.name for foot in (_feet(model)) for j in limb(model, foot)}
    return [s.index for s in model.servos if s.joint in legs]


def _segment(
    values: Sequence[Mapping[int, int]], legs: list[int], lo: int, hi: int, period: int,
    every: int,
) -> list[Keyframe]:  # fmt: skip
    """Keyframes for samples ``lo`` (excluded: where the robot already is) to ``hi``, one
    every ``every`` samples (at least 2). A pose of speed N takes N + 1 output periods on
    the board (spec 9: the update flag clears the period after the move ends, and only then
    does the program fetch the next pose), so a pose ``m`` samples after the last one is
    stored with speed ``m - 1``: the walk keeps its own timing."""
    picks = list(range(lo + every, hi, every))
    if picks and hi - picks[-1] < 2:
        picks.pop()
    if hi > lo:
        picks.append(hi)
    out, last = [], lo
    for i in picks:
        speed = max(1, i - last - move_periods(0))  # its move holds the program i - last periods
        time_s = speed * period / 1000.0
        out.append(Keyframe(time_s, {k: values[i][k] for k in legs}))
        last = i
    return out


def steady_loop(w: Walk, values: Sequence[Mapping[int, int]]) -> Loop | None:
    """The longest run of back-to-back cycles of two steps whose servo values agree within
    :data:`CYCLE_TOLERANCE` (None when fewer than two do). ``values``: servo values per
    sample of ``w``."""
    hold, double, single, _ = phase_samples(w.params, w.pattern.dt)
    step = double + single
    length = 2 * step
    n_steps = len(plan_footsteps(w.params)[1])
    starts = [hold + 2 * j * step for j in range(n_steps // 2)]
    starts = [a for a in starts if a + 2 * length < len(values)]

    def same(a: int) -> bool:
        return all(
            abs(values[a + i][k] - values[a + length + i][k]) <= CYCLE_TOLERANCE
            for i in range(length + 1)
            for k in values[a]
        )

    best: Loop | None = None
    run_start, run = 0, 0
    for j, a in enumerate(starts):
        if same(a):
            run_start, run = (run_start, run + 1) if run else (j, 1)
            if best is None or run + 1 > best.repeats:
                best = Loop(starts[run_start], length, run + 1)
        else:
            run = 0
    return best


def _pose_blocks(keyframes: Sequence[Keyframe], period: int) -> list[Block]:
    return [
        Block("pose", {"frames": c.speed, "positions": {str(k): v for k, v in c.positions}})
        for c in pose_commands(keyframes, period, changed_only=True)
    ]


def _looped(
    model: RobotModel, w: Walk, loop: Loop, period: int, every: int, base: int
) -> tuple[tuple[bytes, ...], tuple[RunConstFrameServo, ...]]:
    """The walk's entries with ``loop`` stored once and counted, and the moves it plays."""
    values = [model.motion_values(p) for p in w.poses]
    legs, end = _legs(model), loop.start + loop.repeats * loop.length
    head = [
        Keyframe(FIRST_MOVE_S, values[0]),
        *_segment(values, legs, 0, loop.start, period, every),
    ]
    cycle = _segment(values, legs, loop.start, loop.start + loop.length, period, every)
    tail = _segment(values, legs, end, len(values) - 1, period, every)
    body = _pose_blocks(cycle, period)
    after = _pose_blocks(tail, period)
    body[0] = replace(body[0], label="cycle")
    after[0] = replace(after[0], label="stop")
    blocks = [
        *_pose_blocks(head, period),
        Block("counter_set", {"counter": LOOP_COUNTER, "value": loop.repeats}),
        *body,
        Block("counter_loop", {"counter": LOOP_COUNTER, "if": "equal", "to": "stop"}),
        Block("jump", {"to": "cycle"}),
        *after,
        Block("return"),
        Block("end"),
    ]
    moves = (
        pose_commands(head, period, True)
        + pose_commands(cycle, period, True) * loop.repeats
        + pose_commands(tail, period, True)
    )
    return compile_blocks(blocks, base), tuple(moves)


def walk_motion(
    model: RobotModel,
    w: Walk,
    *,
    slot: int,
    name: str,
    period: int = 15,
    button: int = 0,
    layout: MotionLayout | None = None,
) -> StoredWalk:
    """The walk as a motion for ``slot``: one chain of poses, or its settled cycle in a loop
    when that keeps more of them (module docstring)."""
    lay = HTH4_22 if layout is None else layout
    joints = {j.name for j in model.joints}
    if (w.robot and w.robot != model.name) or (w.poses and not set(w.poses[0]) <= joints):
        raise GaitError(
            f"the walk was made for {w.robot or 'another robot'}, not {model.name}: a walk of "
            "another robot (its joint angles are that robot's)"
        )
    if period not in FRAME_PERIODS_MS:
        raise GaitError(f"the output period is one of {FRAME_PERIODS_MS} ms, not {period!r}")
    motion_from_frames((), slot=slot, name=name, button=button, layout=lay)  # checks them
    chain: tuple[tuple[bytes, ...], tuple[RunConstFrameServo, ...], int] | None = None
    for every in range(2, 64):
        try:
            kfs = walk_keyframes(model, w, period, every)
            frames = keyframe_frames(kfs, period, changed_only=True)
        except ValueError as e:
            if "a motion slot holds" in str(e):
                continue
            raise GaitError(
                f"{e}: the walk takes a joint past its servo's travel; a smaller lift, turn, "
                "stride or width"
            ) from None
        chain = (frames, tuple(pose_commands(kfs, period, True)), every)
        break
    found: tuple[tuple[bytes, ...], tuple[RunConstFrameServo, ...], int, Loop | None] | None
    found = None if chain is None else (*chain, None)
    loop = steady_loop(w, [model.motion_values(p) for p in w.poses])
    if loop is not None:
        for every in range(2, 64 if chain is None else chain[2]):
            try:
                entries, moves = _looped(model, w, loop, period, every, lay.address(slot))
            except EditError:  # a value past a servo's travel: the chain says so above
                break
            if sum(map(len, entries)) <= MOTION_SIZE:
                found = (entries, moves, every, loop)
                break
    if found is None:
        raise GaitError("the walk does not fit a motion slot; take fewer steps")
    motion = motion_from_frames(found[0], slot=slot, name=name, button=button, layout=lay)
    return StoredWalk(replace(motion, date=now_text()), found[2], found[3], found[1])


def _feet(model: RobotModel) -> list[str]:
    from rcb4hv.gait.generate import Body

    b = Body.of(model)
    return [b.left, b.right]


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
    """Send ``motion``'s poses to a board as RunConstFrameServo commands in stored order (a
    chain of poses: a looped walk's :attr:`StoredWalk.moves` play with :func:`play_moves`),
    each timed as the board times it (:func:`play_moves`); the number of poses sent."""
    from rcb4hv.hth4.poses import motion_blocks

    poses = [b.pose for b in motion_blocks(motion) if b.pose is not None]
    return play_moves(client, [RunConstFrameServo(p.speed, p.values) for p in poses], period, sleep)


def play_moves(
    client: FramePlayer,
    moves: Sequence[RunConstFrameServo],
    period: int,
    sleep: Callable[[float], None],
) -> int:
    """Send ``moves`` to a board one by one, waiting out each as the board's own program
    does (``sleep``, seconds): a move of speed N for N + 1 output periods (spec 9: its update
    flag clears the period after it ends)."""
    for move in moves:
        client.run_const_frame_servo(move.speed, dict(move.positions))
        sleep(move_periods(move.speed) * period / 1000.0)
    return len(moves)
