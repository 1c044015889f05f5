"""Block edits on the fixture: insert, remove, move, change and connect blocks; branches keep
going to the blocks they name."""

from __future__ import annotations

from pathlib import Path

import pytest

from rcb4hv.errors import EditError
from rcb4hv.hth4 import Project, load_project
from rcb4hv.hth4.blocks import motion_program
from rcb4hv.hth4.blocks.edit import (
    connect_block,
    insert_block,
    move_block,
    remove_block,
    set_block,
)
from rcb4hv.hth4.diff import diff_projects
from rcb4hv.hth4.session import EditSession

TURN_LEFT = 69  # pose, pose, pose, button branch (back to the first pose), pose, return, ...


@pytest.fixture(scope="module")
def kxr(kxr_project_path: Path) -> Project:
    return load_project(kxr_project_path)


def _kinds(project: Project, slot: int = TURN_LEFT) -> list[str]:
    return [b.kind for b in motion_program(project, slot).blocks]


def test_insert_a_button_branch_and_a_counter_loop(kxr: Project) -> None:
    s = EditSession(kxr)
    s.apply(insert_block, TURN_LEFT, 0, "counter_set", {"counter": 1, "value": 3})
    s.apply(
        insert_block, TURN_LEFT, 3, "button_branch", {"buttons": ["S1"], "if": "equal", "to": 1}
    )
    s.apply(insert_block, TURN_LEFT, 6, "counter_loop", {"counter": 1, "if": "not_equal", "to": 1})
    blocks = motion_program(s.project, TURN_LEFT).blocks
    assert [b.kind for b in blocks][:8] == [
        "counter_set", "pose", "pose", "button_branch", "pose", "button_branch",
        "counter_loop", "pose",
    ]  # fmt: skip
    assert blocks[1].label is not None
    assert blocks[3].fields["to"] == blocks[6].fields["to"] == blocks[1].label
    assert blocks[5].fields["to"] == blocks[1].label  # the old loop still closes on its pose
    changes = diff_projects(kxr, s.project)
    assert {c.slot for c in changes} == {TURN_LEFT}
    s.undo()
    s.undo()
    s.undo()
    assert s.project == kxr


def test_remove_move_set_connect(kxr: Project) -> None:
    with pytest.raises(EditError, match="branches to block 0"):
        remove_block(kxr, TURN_LEFT, 0)
    p = remove_block(kxr, TURN_LEFT, 1)
    assert _kinds(p)[:3] == ["pose", "pose", "button_branch"]
    p = move_block(kxr, TURN_LEFT, 2, 0)
    blocks = motion_program(p, TURN_LEFT).blocks
    assert blocks[3].fields["to"] == blocks[1].label  # the branch follows its pose
    p = set_block(kxr, TURN_LEFT, 3, {"buttons": ["DOWN"], "if": "equal", "to": 0})
    assert motion_program(p, TURN_LEFT).blocks[3].fields["buttons"] == ["DOWN"]
    p = connect_block(kxr, TURN_LEFT, 3, 2)
    blocks = motion_program(p, TURN_LEFT).blocks
    assert blocks[3].fields["to"] == blocks[2].label
    with pytest.raises(EditError, match="does not branch"):
        connect_block(kxr, TURN_LEFT, 0, 2)
    with pytest.raises(EditError, match=r"blocks\[3\]\.buttons"):
        set_block(kxr, TURN_LEFT, 3, {"buttons": "UP", "to": 0})


def test_other_motions_follow_the_blocks_they_branch_into(kxr: Project) -> None:
    # motion 41 calls motion 47 at its start; a CALL into the middle of 47 (its third block)
    # follows that block when a block is inserted before it
    from dataclasses import replace as _replace

    from rcb4hv.hth4.blocks import put_program
    from rcb4hv.protocol import Call, decode_command

    m47 = kxr.motion(47)
    third = m47.address + sum(len(e) for e in m47.frames[:2])
    program = motion_program(kxr, 41)
    blocks = (
        program.blocks[0].__class__("call", {"to": {"motion": 47, "offset": third - m47.address}}),
    )
    p = put_program(kxr, 41, _replace(program, blocks=blocks + program.blocks))
    p = insert_block(p, 47, 1, "wait", {"timer": 0, "ms": 500})
    call = decode_command(p.motion(41).frames[0])
    assert isinstance(call, Call)
    assert call.address == third + 25  # the wait's 25 bytes came before it
    assert p.startup_motion_address == kxr.startup_motion_address
