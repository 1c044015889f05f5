"""Motions from keyframes: what the UI's Teach page and ``rcb4hv project add-motion`` save.

A keyframe is a pose (ICS number -> raw position) and the time in seconds the move to it
takes. :func:`motion_from_keyframes` compiles keyframes the way HeartToHeart4 compiles a chain
of "Pos" boxes: one RunConstFrameServo frame per pose (speed = time in output periods), then
``RETURN`` and HeartToHeart4's closing ``RETURN`` + ``FF`` end marker. The ROM program waits
for each pose to finish on its own (the update flags, spec 9), so no wait frames are needed.
:func:`flowchart_from_keyframes` draws the same chain as a ``CanvasData`` flowchart: one
``Pos`` box per keyframe, left to right, the first marked ``Start``, joined by ``Normal``
lines, as HeartToHeart4's own files lay them out. :func:`add_motion` stores a motion in a
free slot of a project, with an optional remote-button binding.
(A stored motion of any kind draws back as a flowchart with
:func:`rcb4hv.hth4.blocks.flowxml.motion_xml`.)
"""

from __future__ import annotations

import datetime
import math
import numbers
import uuid
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace

from rcb4hv.errors import EditError
from rcb4hv.hth4.argcheck import as_int, as_name, as_positions
from rcb4hv.hth4.flowchart_model import Flowchart, FlowchartActivity, FlowchartLine, Size
from rcb4hv.hth4.model import COMPARE, Motion, Point, Project, motion_key
from rcb4hv.protocol import (
    FRAME_PERIODS_MS,
    POSITION_MAX,
    POSITION_MIN,
    Return,
    RunConstFrameServo,
)
from rcb4hv.rom.layout import HTH4_22, MOTION_SIZE, MotionLayout

__all__ = [
    "END_MARKER",
    "Keyframe",
    "add_motion",
    "flowchart_from_keyframes",
    "free_slots",
    "keyframe_frames",
    "motion_from_frames",
    "motion_from_keyframes",
    "now_text",
    "pose_commands",
]

END_MARKER = Return().encode() + b"\xff"
"""HeartToHeart4's last stored frame: RETURN followed by the FF end marker."""

MAX_SPEED = 255
BOX = Size(64, 48)
"""HeartToHeart4's size of a Pos box."""
STEP_X = 88
ORIGIN = Point(16, 16)


@dataclass(frozen=True)
class Keyframe:
    """A pose reached ``time`` seconds after the previous one (ICS number -> raw position)."""

    time: float
    positions: Mapping[int, int]
    name: str = ""

    def __post_init__(self) -> None:
        """EditError (a ValueError) for a time that is not a finite number >= 0 s, a position
        that is not an integer (numpy integers are taken as ints) or out of range."""
        t = self.time
        if isinstance(t, bool) or not isinstance(t, numbers.Real) or not math.isfinite(t) or t < 0:
            raise EditError(f"keyframe time must be a finite number >= 0 s, not {t!r}")
        if not self.positions:
            raise EditError("a keyframe needs at least one servo position")
        positions = as_positions("keyframe", self.positions)
        for ics, p in positions.items():
            if not 0 <= ics <= 34:
                raise EditError(f"ICS {ics} is not a servo slot (0..34)")
            if not POSITION_MIN <= p <= POSITION_MAX:
                raise EditError(f"ICS {ics}: position {p} outside {POSITION_MIN}..{POSITION_MAX}")
        object.__setattr__(self, "positions", positions)


def _speed(time_s: float, period_ms: int, index: int) -> int:
    frames = max(1, round(time_s * 1000 / period_ms))
    if frames > MAX_SPEED:
        raise ValueError(
            f"keyframe {index + 1}: {time_s:g} s is {frames} output periods of {period_ms} ms; "
            f"one move lasts at most {MAX_SPEED} periods ({MAX_SPEED * period_ms / 1000:g} s)"
        )
    return frames


def pose_commands(
    keyframes: Sequence[Keyframe], period_ms: int, changed_only: bool = False
) -> list[RunConstFrameServo]:
    """One RunConstFrameServo per keyframe (its time in output periods of ``period_ms``); the
    first keyframe must name every servo; ``changed_only``: see :func:`keyframe_frames`."""
    if not keyframes:
        raise ValueError("no keyframes")
    if period_ms not in FRAME_PERIODS_MS:
        raise ValueError(f"output period must be one of {FRAME_PERIODS_MS} ms")
    servos = sorted({k for kf in keyframes for k in kf.positions})
    first = keyframes[0].positions
    missing = [k for k in servos if k not in first]
    if missing:
        raise ValueError(f"the first keyframe has no position for ICS {missing}")
    pose: dict[int, int] = {}
    out = []
    for i, kf in enumerate(keyframes):
        pose.update(kf.positions)
        moved = kf.positions if changed_only and i else pose
        out.append(RunConstFrameServo(_speed(kf.time, period_ms, i), dict(moved)))
    return out


def keyframe_frames(
    keyframes: Sequence[Keyframe], period_ms: int = 15, *, changed_only: bool = False
) -> tuple[bytes, ...]:
    """The motion's frames as HeartToHeart4 stores them (the last one ends with ``FF``).

    Servos a keyframe leaves out keep the previous keyframe's position; the first keyframe
    must name every servo the motion moves. ``changed_only``: a frame after the first carries
    only its own keyframe's servos (the others hold, as on the board), so a long motion of
    few moving servos fits a slot.
    """
    frames = [c.encode() for c in pose_commands(keyframes, period_ms, changed_only)]
    frames += [Return().encode(), END_MARKER]
    if sum(map(len, frames)) > MOTION_SIZE:
        raise ValueError(
            f"{len(keyframes)} keyframes take {sum(map(len, frames))} bytes; "
            f"a motion slot holds {MOTION_SIZE}"
        )
    return tuple(frames)


def now_text() -> str:
    """The current time as HeartToHeart4 writes ``Date`` (7 fraction digits, UTC offset)."""
    now = datetime.datetime.now(datetime.timezone.utc).astimezone()
    text = now.strftime("%Y-%m-%dT%H:%M:%S.%f") + "0"  # .NET writes 7 fraction digits
    offset = now.strftime("%z")
    return f"{text}{offset[:3]}:{offset[3:]}"


def motion_from_keyframes(
    keyframes: Sequence[Keyframe],
    *,
    slot: int,
    name: str,
    period_ms: int = 15,
    button: int = 0,
    compare_type: str = "Equals",
    date: str | None = None,
    layout: MotionLayout = HTH4_22,
    changed_only: bool = False,
) -> Motion:
    """A project motion for ``slot`` that plays ``keyframes``, stored for ``layout`` (the
    project's HeartToHeart4 version; 2.2 by default); ``button`` binds it to a remote button
    word (0: none); ``changed_only``: see :func:`keyframe_frames`."""
    frames = keyframe_frames(keyframes, period_ms, changed_only=changed_only)
    return motion_from_frames(
        frames, slot=slot, name=name, button=button, compare_type=compare_type, date=date,
        layout=layout,
    )  # fmt: skip


def motion_from_frames(
    frames: Sequence[bytes],
    *,
    slot: int,
    name: str,
    button: int = 0,
    compare_type: str = "Equals",
    date: str | None = None,
    layout: MotionLayout = HTH4_22,
) -> Motion:
    """A project motion for ``slot`` of ``layout`` holding the stored ``frames`` as given;
    EditError (a ValueError) naming a bad slot, button word, name or CompareType."""
    slot = as_int("motion slot", slot)
    if not 1 <= slot <= layout.motion_count:
        raise EditError(f"motion slot must be 1..{layout.motion_count}, not {slot}")
    button = as_int("the button word", button)
    if not 0 <= button <= 0xFFFF:
        raise EditError(f"the button word is 16 bits (0..65535), not {button}")
    name = as_name("motion name", name)
    if compare_type not in COMPARE:
        raise EditError(f"unknown CompareType {compare_type!r} (known: {', '.join(COMPARE)})")
    return Motion(
        key=motion_key(slot),
        number=slot - 1,
        name=name,
        date=date or now_text(),
        button_data=button,
        compare_type=compare_type,
        frames=tuple(frames),
        address=layout.address(slot),
    )


def flowchart_from_keyframes(
    keyframes: Sequence[Keyframe],
    period_ms: int = 15,
    *,
    new_guid: Callable[[], str] = lambda: str(uuid.uuid4()),
) -> Flowchart:
    """The HeartToHeart4 flowchart of the motion: a chain of ``Pos`` boxes."""
    commands = pose_commands(keyframes, period_ms)
    boxes = [Point(ORIGIN.x + STEP_X * i, ORIGIN.y) for i in range(len(commands))]
    centre = [Point(b.x + BOX.width // 2, b.y + BOX.height // 2) for b in boxes]
    lines = tuple(
        FlowchartLine(new_guid(), (centre[i], centre[i + 1]), "Normal")
        for i in range(len(boxes) - 1)
    )
    activities = []
    for i, (cmd, kf) in enumerate(zip(commands, keyframes, strict=True)):
        links: list[tuple[str, str]] = []
        if i > 0:
            links.append((lines[i - 1].guid or "", "EndConnect"))
        if i < len(lines):
            links.append((lines[i].guid or "", "BeginConnect"))
        activities.append(
            FlowchartActivity(
                name=f"Pos{i}",
                guid=new_guid(),
                location=boxes[i],
                size=BOX,
                text=kf.name or f"Pos{i + 1}",
                motion_flag="Start" if i == 0 else "None",
                base_name="Pos",
                description="ポジション設定",
                group="Position",
                connected_guids=",".join(g for g, _ in links),
                connect_types=",".join(t for _, t in links),
                program_code=(cmd.encode(),),
                hint=f"Frame = {cmd.speed}",
            )
        )
    width = max(640, ORIGIN.x + STEP_X * len(boxes) + BOX.width)
    return Flowchart(size=Size(width, 480), lines=lines, activities=tuple(activities))


def free_slots(project: Project) -> list[int]:
    """Empty motion slots of ``project`` (1-based, ascending)."""
    return [m.slot for m in project.motions if m.is_empty]


def add_motion(project: Project, motion: Motion, *, replace_used: bool = False) -> Project:
    """``project`` with ``motion`` stored in its slot (which must be empty unless
    ``replace_used``). A project without that slot entry gets it appended."""
    entries = list(project.motions)
    for i, m in enumerate(entries):
        if m.slot == motion.slot:
            if not m.is_empty and not replace_used:
                raise ValueError(f"motion slot {motion.slot} holds {m.name!r}; pick a free slot")
            entries[i] = replace(motion, key=m.key)
            break
    else:
        entries.append(motion)
        entries.sort(key=lambda m: m.slot)
    return replace(project, motions=tuple(entries))
