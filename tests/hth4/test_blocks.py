"""Program blocks: every entry of a motion decodes into a typed block and encodes back exactly."""

from __future__ import annotations

import json
import re
from collections import Counter
from dataclasses import replace
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import protocol as p
from rcb4hv.errors import EditError
from rcb4hv.hth4 import Project, load_project
from rcb4hv.hth4.blocks import (
    Block,
    Program,
    compile_program,
    dump_program,
    motion_program,
    program_from_json,
    put_program,
)
from rcb4hv.hth4.model import motion_rom_address
from tests.hth4._programs import one_motion_project
from tests.strategies import commands


@pytest.fixture(scope="module")
def kxr(kxr_project_path: Path) -> Project:
    return load_project(kxr_project_path)


def _through_json(program: Program) -> Program:
    return program_from_json(json.loads(dump_program(program)))


def test_every_fixture_motion_encodes_back_exactly(kxr: Project) -> None:
    for m in kxr.used_motions:
        program = _through_json(motion_program(kxr, m.slot))
        assert compile_program(kxr, m.slot, program) == m.frames, m.slot


def test_fixture_block_kinds_and_no_raw_blocks(kxr: Project) -> None:
    kinds = Counter(b.kind for m in kxr.used_motions for b in motion_program(kxr, m.slot).blocks)
    assert kinds == {
        "pose": 472,
        "jump": 86,
        "button_branch": 71,
        "return": 68,
        "end": 65,
        "servo_stretch": 57,
        "call": 12,
        "counter_set": 9,
        "counter_loop": 9,
        "wait": 5,
        "ad_branch": 4,
        "servo_speed": 1,
    }


def test_fixture_golden_blocks(kxr: Project) -> None:
    # slot 5, "slow walk forward (5 times)": a counter loop around the steps
    blocks = [b.to_json() for b in motion_program(kxr, 5).blocks]
    assert blocks[0] == {"kind": "counter_set", "counter": 0, "value": 5}
    loop = next(b for b in blocks if b["kind"] == "counter_loop")
    assert loop == {"kind": "counter_loop", "counter": 0, "if": "equal", "to": "L2"}
    assert blocks[-1] == {"kind": "end"}
    # slot 23 waits 1 s on timer 0; slot 41 calls other motions by slot, not by address
    assert {"kind": "wait", "timer": 0, "ms": 1000} in [
        b.to_json() for b in motion_program(kxr, 23).blocks
    ]
    calls = [b for b in motion_program(kxr, 41).blocks if b.kind == "call"]
    assert calls[0].fields == {"to": {"motion": 47}}
    branch = next(b for b in motion_program(kxr, 41).blocks if b.kind == "button_branch")
    assert branch.fields["buttons"] == []  # no button held: word 0


@settings(max_examples=150, deadline=None)
@given(st.lists(commands, min_size=1, max_size=12), st.booleans())
def test_any_command_list_encodes_back_exactly(cmds: list[p.Command], end: bool) -> None:
    frames = tuple(p.encode_command(c) for c in cmds) + ((b"\x03\x0d\x10\xff",) if end else ())
    project = one_motion_project(frames)
    program = _through_json(motion_program(project, 1))
    assert compile_program(project, 1, program) == frames
    # the blocks relocate: the same program compiled into slot 2 keeps internal branches
    moved = compile_program(project, 2, program)
    assert len(b"".join(moved)) == len(b"".join(frames))


def test_branches_follow_their_labels_when_blocks_are_inserted() -> None:
    pose = p.RunConstFrameServo(10, {0: 7500}).encode()
    start = motion_rom_address(1)
    frames = (pose, p.Jump(start, p.ALWAYS).encode(), b"\x03\x0d\x10\xff")
    project = one_motion_project(frames)
    program = motion_program(project, 1)
    assert program.blocks[0].label == "L1"
    assert program.blocks[1].fields == {"to": "L1"}
    extra = Block("pose", {"frames": 5, "positions": {"0": 8000}})
    edited = replace(program, blocks=(extra, *program.blocks))
    out = put_program(project, 1, edited)
    jump = p.decode_command(out.motion(1).frames[2])
    assert jump == p.Jump(start + len(pose), p.ALWAYS)  # follows the labelled pose


def test_hand_written_blocks_encode() -> None:
    project = one_motion_project((b"\x03\x0d\x10\xff",))
    text = {
        "blocks": [
            {"label": "top", "kind": "pose", "frames": 10, "positions": {"0": 7500, "1": 7600}},
            {"kind": "button_branch", "buttons": ["UP", "S1"], "if": "equal", "to": "top"},
            {"kind": "counter_set", "counter": 2, "value": 3},
            {"kind": "counter_loop", "counter": 2, "if": "equal", "to": 5},
            {"kind": "variable_arith", "op": "add", "variable": 1, "value": -1},
            {"kind": "wait", "timer": 0, "ms": 500},
            {"kind": "mixing", "ics": 8, "field": "mix1_source", "value": 0x4024},
            {"kind": "call", "to": {"motion": 2}},
            {"kind": "end"},
        ]
    }
    entries = compile_program(project, 1, program_from_json(text))
    cmds = [p.decode_command(e.rstrip(b"\xff")) for e in entries]
    base = motion_rom_address(1)
    assert cmds[1] == p.Sub(p.Ram(0x0350), p.Data(b"\x02\x01"), no_write=True)
    assert cmds[2] == p.Jump(base, p.Condition.if_zero())
    assert cmds[3] == p.Move(p.Ram(0x0459), p.Data(b"\x03"))
    assert cmds[6] == p.Add(p.Ram(0x0464), p.Data(b"\xff\xff"))
    assert cmds[10] == p.Move(p.Ics(14, 8), p.Data(b"\x24\x40"))
    assert cmds[11] == p.Call(motion_rom_address(2), p.ALWAYS)
    # the counter loop's index 5 is the wait, which branches to its own compare
    wait_at = base + sum(len(e) for e in entries[:7])
    assert cmds[5] == p.Jump(wait_at, p.Condition.if_zero())
    assert cmds[9] == p.Jump(wait_at + 9, p.Condition.if_not_zero())


@pytest.mark.parametrize(
    ("block", "field"),
    [
        ({"kind": "pose", "frames": 300, "positions": {}}, "blocks[0].frames"),
        ({"kind": "pose", "frames": 3, "positions": {"40": 1}}, "blocks[0].positions.40"),
        ({"kind": "button_branch", "buttons": ["UPP"], "to": 0}, "blocks[0].buttons[0]"),
        ({"kind": "jump", "to": "nowhere"}, "blocks[0].to"),
        ({"kind": "move", "dst": "VAR99", "src": "#01"}, "blocks[0].dst"),
        ({"kind": "wait", "timer": 0, "ms": 150}, "blocks[0].ms"),
        ({"kind": "jump", "to": 0, "if": "sometimes"}, "blocks[0].if"),
        ({"kind": "teleport"}, "blocks[0].kind"),
        ({"kind": "pose", "frames": 3, "positions": {}, "speed": 4}, "blocks[0].speed"),
    ],
)
def test_bad_fields_are_named(block: dict[str, object], field: str) -> None:
    project = one_motion_project((b"\x03\x0d\x10\xff",))
    with pytest.raises(EditError, match="^" + re.escape(field)):
        compile_program(project, 1, program_from_json({"blocks": [block]}))


def test_every_kind_has_its_fields() -> None:
    # each kind's template compiles, and every field a decoded block has is a known one
    from rcb4hv.hth4.blocks.edit import BLOCK_TEMPLATES
    from rcb4hv.hth4.blocks.kinds import FIELDS

    project = one_motion_project((b"\x03\x0d\x10\xff",))
    for kind, fields in BLOCK_TEMPLATES.items():
        assert set(fields) <= set(FIELDS[kind]), kind
        program = program_from_json({"blocks": [{"kind": kind, **fields}, {"kind": "end"}]})
        entries = compile_program(project, 1, program)
        back = motion_program(
            replace(project, motions=(replace(project.motions[0], frames=entries),)), 1
        )
        assert back.blocks[0].kind == kind, kind


def test_moves_to_the_host_and_arithmetic_on_rom_encode_back() -> None:
    cmds = [
        p.Move(p.Com(), p.Ram(0x0462), 2),
        p.Add(p.Com(), p.Data(b"\x01\x00")),
        p.Xor(p.Rom(0x1000), p.Ics(2, 5), 1, True),
        p.Shift.left(p.Ram(0x0470), 3, 2),
    ]
    frames = tuple(c.encode() for c in cmds)
    project = one_motion_project(frames)
    program = _through_json(motion_program(project, 1))
    assert [b.kind for b in program.blocks] == ["move", "arith", "arith", "arith"]
    assert program.blocks[0].fields == {"dst": "COM", "src": "VAR0", "size": 2}
    assert compile_program(project, 1, program) == frames


@pytest.mark.parametrize(
    ("hex_", "said"),
    [("03 FE", "not whole command frames"), ("03 FE 02", "checksum"), ("zz", "non-hexadecimal")],
)
def test_a_raw_block_is_whole_frames(hex_: str, said: str) -> None:
    """A raw block that is no whole frame was imported, and the build then refused the
    project it had written."""
    project = one_motion_project((b"\x03\x0d\x10\xff",))
    program = Program(blocks=(Block("raw", {"hex": hex_}), Block("end", {})))
    with pytest.raises(EditError, match=said):
        compile_program(project, 1, program)
    ok = Program(blocks=(Block("raw", {"hex": "03 FE 01"}), Block("end", {})))
    assert compile_program(project, 1, ok)[0] == bytes.fromhex("03 FE 01")


def test_a_counter_outside_the_boards_counters_names_their_range() -> None:
    """Was: "counter: -1 outside 0..99", then "there is no COUNTER99" (counters are 0-10)."""
    project = one_motion_project((b"\x03\x0d\x10\xff",))
    for n in (-1, 11, 99):
        block = {"kind": "counter_loop", "counter": n, "to": 0}
        with pytest.raises(EditError, match=rf"^blocks\[0\]\.counter: {n} outside 0\.\.10$"):
            compile_program(project, 1, program_from_json({"blocks": [block]}))
