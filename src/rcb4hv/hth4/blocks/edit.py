"""Block edits of a motion: pure functions from a project to a new one (undoable in an
:class:`~rcb4hv.hth4.session.EditSession`, as :mod:`rcb4hv.hth4.edit`).

Each reads the motion as a program (:func:`~rcb4hv.hth4.blocks.program.motion_program`),
changes its block list and compiles it back (:func:`~rcb4hv.hth4.blocks.program.put_program`),
so every branch keeps going to the block it names, wherever that block moves; branches of
other motions into it, and the start-up and priority addresses, move with the entry they
point into, as for pose edits (:func:`rcb4hv.hth4.edit.apply_entry_edit`).
:func:`insert_block`, :func:`remove_block`, :func:`move_block`, :func:`set_block`,
:func:`connect_block`. Blocks are addressed by their 0-based index in the program.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace

from rcb4hv.errors import EditError
from rcb4hv.hth4.blocks.encode import encode_block
from rcb4hv.hth4.blocks.fields import Json
from rcb4hv.hth4.blocks.kinds import KINDS, Block
from rcb4hv.hth4.blocks.program import (
    Program,
    block_spans,
    compile_program,
    motion_program,
    put_program,
)
from rcb4hv.hth4.edit import layout_map
from rcb4hv.hth4.model import Project
from rcb4hv.hth4.motioncode import retarget_project
from rcb4hv.hth4.poses import EntryEdit

__all__ = [
    "BLOCK_HINTS",
    "BLOCK_TEMPLATES",
    "connect_block",
    "insert_block",
    "move_block",
    "remove_block",
    "set_block",
]

BLOCK_TEMPLATES: dict[str, dict[str, Json]] = {
    "pose": {"frames": 10, "positions": {}},
    "servo_stretch": {"values": {}},
    "servo_speed": {"values": {}},
    "servo_single": {"ics": 0, "frames": 10, "position": 7500},
    "servo_series": {"moves": []},
    "jump": {"to": 0},
    "call": {"to": {"motion": 1}},
    "return": {},
    "end": {},
    "button_branch": {"buttons": ["UP"], "if": "equal", "to": 0},
    "ad_branch": {"channel": 1, "value": 0, "if": "greater_or_equal", "to": 0},
    "variable_branch": {"variable": 0, "value": 0, "if": "equal", "to": 0},
    "counter_branch": {"counter": 0, "value": 0, "if": "equal", "to": 0},
    "pa_branch": {"pa": 1, "value": 0, "if": "equal", "to": 0},
    "timer_branch": {"timer": 0, "value": 0, "if": "equal", "to": 0},
    "compare_branch": {"dst": "VAR0", "src": "VAR1", "size": 2, "if": "equal", "to": 0},
    "counter_loop": {"counter": 0, "if": "equal", "to": 0},
    "compare": {"dst": "VAR0", "src": "VAR1", "size": 2},
    "counter_set": {"counter": 0, "value": 3},
    "variable_set": {"variable": 0, "value": 0},
    "timer_set": {"timer": 0, "value": 10},
    "wait": {"timer": 0, "ms": 1000},
    "ad_reference": {"channel": 1, "value": 0},
    "mixing": {"ics": 0, "field": "mix1_source", "value": 0xFFFF},
    "servo_setting": {"ics": 0, "field": "speed", "value": 127},
    "variable_arith": {"op": "add", "variable": 0, "value": 1},
    "move": {"dst": "VAR0", "src": "VAR1", "size": 2},
    "arith": {"op": "and", "dst": "VAR0", "src": "#FF 00"},
    "ics_comm": {"ics": 0, "tx_count": 1, "tx_address": 0x0462, "rx_address": 0x0464},
    "raw": {"hex": "03 FE 01"},
}
"""The fields a new block of each kind starts with (``to`` 0: the program's first block)."""

BLOCK_HINTS: dict[str, str] = {
    "counter_loop": "counts the counter down by one, then branches to `to` when the test holds "
    "(`equal`: it reached zero). As in Kondo's samples: set the counter before the loop, point "
    "`to` at the block after the loop, and end the loop with a jump back to its first block",
    "counter_set": "the number of passes of a counter_loop that counts this counter down",
    "jump": "`to`: a block number or a label",
    "call": '`to`: {"motion": N} calls motion N and comes back; a block number or label',
}
"""What a user needs to know to fill in a block of these kinds (the dashboard shows it)."""
assert set(BLOCK_TEMPLATES) == set(KINDS)


def _program(project: Project, slot: int) -> Program:
    program = motion_program(project, slot)
    if not program.blocks:
        raise EditError(f"motion slot {slot} is empty: create the motion first")
    return program


def _index(program: Program, index: int, what: str = "block") -> None:
    if not 0 <= index < len(program.blocks):
        raise EditError(f"the motion has {len(program.blocks)} blocks; no {what} {index}")


def _put(
    project: Project,
    slot: int,
    program: Program,
    blocks: list[Block],
    origins: list[int | None] | None = None,
) -> Project:
    """``program`` with ``blocks`` compiled into ``slot``; ``origins`` (for each new block, the
    index of the old block it is, None for a new one; default: the same blocks) moves every
    branch of another motion, and the start-up and priority addresses, into the motion with
    the entry they point into (:func:`rcb4hv.hth4.edit.layout_map`)."""
    new = replace(program, blocks=tuple(blocks))
    old = project.motion(slot)
    entries = compile_program(project, slot, new)
    spans = block_spans(old)
    made = [len(encode_block(b, lambda t, w: 0, "", 0)) for b in blocks]
    entry_origins: list[int | None] = []
    for n, count in enumerate(made):
        k = n if origins is None else origins[n]
        if k is None or k >= len(spans):
            entry_origins += [None] * count
            continue
        first, old_count = spans[k]
        same = count == old_count
        entry_origins += [first + j if same or j == 0 else None for j in range(count)]
    where = layout_map(old, EntryEdit(entries, tuple(entry_origins)))
    others = replace(  # the motion's own branches are compiled from its labels
        project, motions=tuple(replace(m, frames=()) if m is old else m for m in project.motions)
    )
    return put_program(retarget_project(others, where), slot, new)


def _labelled(blocks: list[Block], index: int) -> tuple[list[Block], str]:
    """``blocks`` with block ``index`` labelled (a new ``L<n>`` if it has none), and the label."""
    label = blocks[index].label
    if label is None:
        used = {b.label for b in blocks}
        n = 1
        while f"L{n}" in used:
            n += 1
        label = f"L{n}"
        blocks = list(blocks)
        blocks[index] = replace(blocks[index], label=label)
    return blocks, label


def _numbered_targets(blocks: list[Block]) -> list[Block]:
    """Branches to a block index made branches to its label (so the index cannot go stale)."""
    out = list(blocks)
    for i, b in enumerate(out):
        to = b.fields.get("to")
        if isinstance(to, int) and not isinstance(to, bool) and 0 <= to < len(out):
            out, label = _labelled(out, to)
            out[i] = replace(out[i], fields={**out[i].fields, "to": label})
    return out


def insert_block(
    project: Project, slot: int, at: int, kind: str, fields: Mapping[str, Json] | None = None
) -> Project:
    """A new block of ``kind`` (fields: ``fields``, else :data:`BLOCK_TEMPLATES`) inserted as
    block ``at`` of motion ``slot``."""
    if kind not in KINDS:
        raise EditError(f"{kind!r} is not a block kind ({', '.join(KINDS)})")
    program = _program(project, slot)
    if not 0 <= at <= len(program.blocks):
        raise EditError(f"the motion has {len(program.blocks)} blocks; cannot insert at {at}")
    blocks = _numbered_targets(list(program.blocks))
    new = Block(kind, dict(BLOCK_TEMPLATES[kind] if fields is None else fields))
    blocks.insert(at, new)
    origins: list[int | None] = list(range(len(program.blocks)))
    origins.insert(at, None)
    return _put(project, slot, program, _numbered_targets(blocks), origins)


def remove_block(project: Project, slot: int, index: int) -> Project:
    """Block ``index`` of motion ``slot`` removed (EditError if a branch goes to it)."""
    program = _program(project, slot)
    _index(program, index)
    blocks = _numbered_targets(list(program.blocks))
    label = blocks[index].label
    for i, b in enumerate(blocks):
        if i != index and label is not None and b.fields.get("to") == label:
            raise EditError(f"block {i} branches to block {index}; connect it elsewhere first")
    del blocks[index]
    origins: list[int | None] = [k for k in range(len(program.blocks)) if k != index]
    return _put(project, slot, program, blocks, origins)


def move_block(project: Project, slot: int, index: int, to: int) -> Project:
    """Block ``index`` moved to position ``to``; branches follow the blocks they name."""
    program = _program(project, slot)
    _index(program, index)
    _index(program, to, "position")
    blocks = _numbered_targets(list(program.blocks))
    blocks.insert(to, blocks.pop(index))
    origins: list[int | None] = list(range(len(program.blocks)))
    origins.insert(to, origins.pop(index))
    return _put(project, slot, program, blocks, origins)


def set_block(project: Project, slot: int, index: int, fields: Mapping[str, Json]) -> Project:
    """Block ``index``'s fields replaced by ``fields`` (its kind and label stay)."""
    program = _program(project, slot)
    _index(program, index)
    blocks = list(program.blocks)
    blocks[index] = replace(blocks[index], fields=dict(fields))
    return _put(project, slot, program, _numbered_targets(blocks))


def connect_block(project: Project, slot: int, index: int, target: int) -> Project:
    """Block ``index`` (a jump, call or branch) sent to block ``target``."""
    program = _program(project, slot)
    _index(program, index)
    _index(program, target, "target block")
    if "to" not in program.blocks[index].fields:
        raise EditError(f"block {index} ({program.blocks[index].kind}) does not branch")
    blocks, label = _labelled(list(program.blocks), target)
    blocks[index] = replace(blocks[index], fields={**blocks[index].fields, "to": label})
    return _put(project, slot, program, blocks)
