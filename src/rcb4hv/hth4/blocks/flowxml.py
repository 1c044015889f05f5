"""Motions as HeartToHeart4 flowchart XML (``CanvasData``), branches included, and back.

How HeartToHeart4 compiles a flowchart (read from the fixture's flowcharts and the motions
they compiled to): each box holds its frames (``ProgramCode``); a compare box ends in a
conditional ``JUMP FFFFFF`` whose target is the box its ``True`` arrow goes to, its ``False``
arrow (like a ``Normal`` one) is the box that follows. From the ``Start`` box it places each
box's frames and follows the next arrow; reaching a box already placed it writes a JUMP to
it, reaching a box with no next arrow a RETURN (``03 0D 10``). Then it places the ``True``
targets, the last one met first (a stack: the fixture's motion 17, four analog branches,
shows the order; a target already placed gets a JUMP to it too, unreachable but written),
fills in the compare boxes' JUMPs, and closes with ``03 0D 10 FF``.
:func:`compile_flowchart` does exactly that.

:func:`motion_xml` draws a motion as such a flowchart: every block but the plain JUMPs
(arrows), RETURNs (chain ends) and the closing ``end`` is a box. It first compiles the drawing
back; if that does not give the motion's bytes (a motion HeartToHeart4 did not write, or laid
out otherwise) it writes the exact form instead: every block a box in ROM order with its
frames as stored, and the chart named :data:`EXACT_NAME`, which :func:`compile_flowchart` reads
by concatenating the boxes. Either way ``motion_from_xml(motion_xml(m)) == m.frames``.
"""

from __future__ import annotations

import uuid
from dataclasses import dataclass, replace
from typing import Final

from rcb4hv.errors import EditError, ProtocolError
from rcb4hv.hth4.blocks.kinds import BRANCHES, Block
from rcb4hv.hth4.blocks.program import block_spans, motion_program
from rcb4hv.hth4.flowchart import dump_motion_xml, parse_motion_xml
from rcb4hv.hth4.flowchart_model import Flowchart, FlowchartActivity, FlowchartLine, Size
from rcb4hv.hth4.model import Point, Project
from rcb4hv.protocol import Jump, Return, decode_command

__all__ = ["EXACT_NAME", "compile_flowchart", "motion_from_xml", "motion_xml", "put_flowchart"]

EXACT_NAME: Final = "rcb4hv-exact"
"""``CanvasData/Name`` of a chart whose boxes are the motion's blocks in ROM order."""
UNRESOLVED: Final = 0xFFFFFF
RETURN: Final = Return().encode()
END: Final = RETURN + b"\xff"
BOX: Final = Size(64, 48)
PER_ROW: Final = 8

# kind -> (BaseName, Group, Description) as HeartToHeart4's own flowcharts name those boxes
# (the fixture's and Kondo's KHR-3HV sample flowcharts: a "MotionJump" box holds a CALL, a
# "Loop" box the counter step and its branch); other kinds get the kind as BaseName.
_BOXES: Final = {
    "pose": ("Pos", "Position", "ポジション設定"),
    "servo_stretch": ("ServoParam", "Set", "サーボモーターの特性を設定"),
    "servo_speed": ("ServoParam", "Set", "サーボモーターの特性を設定"),
    "button_branch": ("CmpButton", "Compare", "コントローラーボタンで分岐"),
    "counter_loop": ("Loop", "Compare", "繰り返し処理"),
    "counter_set": ("SetCounter", "Set", "パラメーターのセット"),
    "variable_set": ("SetCounter", "Set", "パラメーターのセット"),
    "call": ("MotionJump", "Jump", "Causes the motion flow to jump to the assigned motion"),
}


@dataclass
class _Box:
    code: list[bytes]
    next: int | None = None
    true: int | None = None


class _NotDrawable(Exception):
    """The motion is not what HeartToHeart4 would compile from a drawing of it."""


def _jump_to(address: int, cond: int = 0) -> bytes:
    from rcb4hv.protocol import Condition

    return Jump(address, Condition.from_byte(cond)).encode()


def _patched(frame: bytes, address: int) -> bytes:
    cmd = decode_command(frame)
    assert isinstance(cmd, Jump)
    return Jump(address, cmd.condition).encode()


def _compile(base: int, boxes: list[_Box], start: int) -> tuple[bytes, ...]:
    entries: list[bytes] = []
    at: dict[int, int] = {}
    fixups: list[tuple[int, int]] = []  # (entry index, target box)
    pending: list[int] = []
    addr = base

    def emit(e: bytes) -> None:
        nonlocal addr
        entries.append(e)
        addr += len(e)

    def chain(box: int | None) -> None:
        while box is not None:
            if box in at:
                emit(_jump_to(at[box]))
                return
            at[box] = addr
            b = boxes[box]
            for frame in b.code:
                emit(frame)
            if b.true is not None:
                fixups.append((len(entries) - 1, b.true))
                pending.append(b.true)
            if b.next is None:
                emit(RETURN)
                return
            box = b.next

    chain(start)
    while pending:
        chain(pending.pop())
    emit(END)
    for i, target in fixups:
        entries[i] = _patched(entries[i], at[target])
    return tuple(entries)


def compile_flowchart(chart: Flowchart, base: int) -> tuple[bytes, ...]:
    """The stored entries of the motion ``chart`` draws, placed at ROM ``base``."""
    acts = chart.activities
    if chart.name == EXACT_NAME:
        return tuple(f for a in acts for f in a.program_code)
    ends: dict[str, int] = {}
    for i, a in enumerate(acts):
        for guid, how in a.connections:
            if how == "EndConnect":
                ends[guid] = i
    modes = {line.guid: line.connect_mode for line in chart.lines}
    boxes: list[_Box] = []
    for a in acts:
        box = _Box(list(a.program_code))
        for guid, how in a.connections:
            if how != "BeginConnect" or guid not in ends:
                continue
            if modes.get(guid) == "True":
                box.true = ends[guid]
            elif box.next is None:
                box.next = ends[guid]
            else:
                raise EditError(
                    f"flowchart box {a.name}: two arrows leave it and none is marked True, "
                    "so which one branches is not known"
                )
        if box.true is not None and not _ends_in_jump(box.code):
            raise EditError(f"flowchart box {a.name}: a True arrow but no JUMP to send along it")
        boxes.append(box)
    starts = [i for i, a in enumerate(acts) if a.motion_flag == "Start"]
    if len(starts) != 1:
        raise EditError(f"a flowchart has one Start box, this one {len(starts)}")
    return _compile(base, boxes, starts[0])


def _ends_in_jump(code: list[bytes]) -> bool:
    try:
        return bool(code) and isinstance(decode_command(code[-1]), Jump)
    except ProtocolError:
        return False


def motion_from_xml(project: Project, slot: int, data: bytes | str) -> tuple[bytes, ...]:
    """The entries of the flowchart file ``data`` compiled for slot ``slot`` of ``project``."""
    try:
        base = project.motion(slot).address
    except KeyError:
        raise EditError(f"the project has no motion slot {slot}") from None
    return compile_flowchart(parse_motion_xml(data), base)


# ---------------------------------------------------------------------------- drawing


def _is_arrow(b: Block) -> bool:
    return b.kind == "jump" and isinstance(b.fields.get("to"), str) and "if" not in b.fields


def _drawable(blocks: list[Block], entries: list[tuple[bytes, ...]]) -> tuple[list[_Box], int]:
    """Boxes (indexed by block) of the HeartToHeart4 drawing; _NotDrawable if none fits."""
    labels = {b.label: i for i, b in enumerate(blocks) if b.label is not None}
    if not blocks or blocks[-1].kind != "end" or any(b.kind == "end" for b in blocks[:-1]):
        raise _NotDrawable
    is_box = [not (_is_arrow(b) or b.kind in ("return", "end")) for b in blocks]

    def follow(k: int) -> int | None:
        if k >= len(blocks):
            raise _NotDrawable
        b = blocks[k]
        if is_box[k]:
            return k
        if b.kind in ("return", "end"):
            return None
        target = labels[str(b.fields["to"])]
        if not is_box[target]:
            raise _NotDrawable
        return target

    boxes: list[_Box] = []
    for i, b in enumerate(blocks):
        code = list(entries[i])
        box = _Box(code)
        if is_box[i]:
            box.next = follow(i + 1)
            to = b.fields.get("to")
            branches = b.kind in BRANCHES or (b.kind == "jump" and "if" in b.fields)
            if branches and isinstance(to, str):
                box.true = follow(labels[to])
                if box.true is None:
                    raise _NotDrawable
                code[-1] = _patched(code[-1], UNRESOLVED)
        boxes.append(box)
    if not is_box[0]:
        raise _NotDrawable
    return boxes, 0


def _guid(slot: int, *parts: object) -> str:
    return str(uuid.uuid5(uuid.NAMESPACE_URL, f"rcb4hv:motion{slot}:" + ":".join(map(str, parts))))


def _chart(
    slot: int, blocks: list[Block], boxes: list[_Box], keep: list[int], exact: bool
) -> Flowchart:
    where = {
        i: Point(16 + 88 * (n % PER_ROW), 16 + 80 * (n // PER_ROW)) for n, i in enumerate(keep)
    }
    centre = {i: Point(p.x + BOX.width // 2, p.y + BOX.height // 2) for i, p in where.items()}
    lines: list[FlowchartLine] = []
    links: dict[int, list[tuple[str, str]]] = {i: [] for i in keep}
    for i in keep:
        for mode, target in (("True", boxes[i].true), ("Normal", boxes[i].next)):
            if target is None:
                continue
            if mode == "Normal" and boxes[i].true is not None:
                mode = "False"
            guid = _guid(slot, "line", i, mode)
            lines.append(FlowchartLine(guid, (centre[i], centre[target]), mode))
            links[i].append((guid, "BeginConnect"))
            links[target].append((guid, "EndConnect"))
    acts = []
    for n, i in enumerate(keep):
        b = blocks[i]
        base_name, group, description = _BOXES.get(b.kind, (b.kind, "rcb4hv", b.kind))
        acts.append(
            FlowchartActivity(
                name=f"{base_name}{n + 1}",
                guid=_guid(slot, "box", i),
                location=where[i],
                size=BOX,
                text=b.label or f"{base_name}{n + 1}",
                motion_flag="Start" if n == 0 else "None",
                base_name=base_name,
                description=description,
                group=group,
                connected_guids=",".join(g for g, _ in links[i]),
                connect_types=",".join(t for _, t in links[i]),
                program_code=tuple(boxes[i].code),
                hint=description,
            )
        )
    rows = (len(keep) + PER_ROW - 1) // PER_ROW
    size = Size(max(640, 16 + 88 * PER_ROW), max(480, 16 + 80 * rows))
    return Flowchart(
        name=EXACT_NAME if exact else "canvas",
        size=size,
        lines=tuple(lines),
        activities=tuple(acts),
    )


def motion_xml(project: Project, slot: int) -> bytes:
    """The flowchart file (``.xml``) of motion ``slot``: HeartToHeart4's drawing when it
    compiles back to the motion's bytes, else the exact form (module docstring)."""
    motion = project.motion(slot)
    if motion.is_empty:
        raise EditError(f"motion slot {slot} is empty")
    blocks = list(motion_program(project, slot).blocks)
    entries = [motion.frames[i : i + n] for i, n in block_spans(motion)]
    try:
        boxes, _start = _drawable(blocks, entries)
        keep = [
            i
            for i, b in enumerate(boxes)
            if not (_is_arrow(blocks[i]) or blocks[i].kind in ("return", "end"))
        ]
        chart = _chart(slot, blocks, boxes, keep, exact=False)
        if compile_flowchart(chart, motion.address) == motion.frames:
            return dump_motion_xml(chart)
    except _NotDrawable:
        pass
    exact = [_Box(list(e)) for e in entries]
    for i in range(len(exact) - 1):
        exact[i].next = i + 1
    chart = _chart(slot, blocks, exact, list(range(len(exact))), exact=True)
    return dump_motion_xml(chart)


def put_flowchart(project: Project, slot: int, data: bytes | str) -> Project:
    """``project`` with the flowchart file ``data`` compiled into slot ``slot`` (its name, date
    and button stay: a flowchart holds none of them)."""
    entries = motion_from_xml(project, slot, data)
    return replace(
        project,
        motions=tuple(replace(m, frames=entries) if m.slot == slot else m for m in project.motions),
    )
