"""Motions from keyframes: frames, flowchart, saving into a project, and playing them."""

from __future__ import annotations

from pathlib import Path

import pytest

from rcb4hv.hth4 import dump_motion_xml, dump_project, load_project, parse_motion_xml, parse_project
from rcb4hv.hth4.keyframes import (
    END_MARKER,
    Keyframe,
    add_motion,
    flowchart_from_keyframes,
    free_slots,
    keyframe_frames,
    motion_from_keyframes,
)
from rcb4hv.project.image import build_project_image
from rcb4hv.project.simulate import Simulator
from rcb4hv.protocol import RunConstFrameServo, decode_command

KF = [
    Keyframe(0.5, {2: 7500, 3: 7500}),
    Keyframe(0.3, {2: 9000}),
    Keyframe(1.0, {2: 7500, 3: 6000}),
]


def test_frames_are_poses_then_hth4_ending() -> None:
    frames = keyframe_frames(KF, period_ms=20)
    cmds = [decode_command(f) for f in frames[:3]]
    assert all(isinstance(c, RunConstFrameServo) for c in cmds)
    assert [c.speed for c in cmds] == [25, 15, 50]  # type: ignore[union-attr]
    assert dict(cmds[1].positions) == {2: 9000, 3: 7500}  # type: ignore[union-attr]
    assert frames[-2:] == (b"\x03\x0d\x10", END_MARKER)
    assert END_MARKER == b"\x03\x0d\x10\xff"


@pytest.mark.parametrize(
    ("keyframes", "message"),
    [
        ([], "no keyframes"),
        ([Keyframe(10.0, {2: 7500})], "at most 255 periods"),
        ([Keyframe(0.1, {2: 7500}), Keyframe(0.1, {3: 7000})], "first keyframe has no position"),
    ],
)
def test_bad_keyframes(keyframes: list[Keyframe], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        keyframe_frames(keyframes)


def test_keyframe_checks_ranges() -> None:
    with pytest.raises(ValueError, match="outside 3500"):
        Keyframe(0.1, {2: 12000})
    with pytest.raises(ValueError, match=">= 0"):
        Keyframe(-1, {2: 7500})
    with pytest.raises(ValueError, match="not a servo slot"):
        Keyframe(0.1, {35: 7500})


def test_too_many_keyframes_do_not_fit_a_slot() -> None:
    pose = {k: 7500 for k in range(20)}
    with pytest.raises(ValueError, match="a motion slot holds 2048"):
        keyframe_frames([Keyframe(0.1, pose)] * 60)


def test_flowchart_has_hth4_shape_and_round_trips() -> None:
    chart = flowchart_from_keyframes(KF, 15)
    assert [a.base_name for a in chart.activities] == ["Pos", "Pos", "Pos"]
    assert chart.start is chart.activities[0]
    assert len(chart.lines) == 2
    first, mid, last = chart.activities
    assert first.connect_types == "BeginConnect"
    assert mid.connect_types == "EndConnect,BeginConnect"
    assert last.connect_types == "EndConnect"
    assert mid.connected_guids == f"{chart.lines[0].guid},{chart.lines[1].guid}"
    assert [a.program_code[0] for a in chart.activities] == list(keyframe_frames(KF, 15)[:3])
    data = dump_motion_xml(chart)
    assert dump_motion_xml(parse_motion_xml(data)) == data


def test_saved_motion_reloads_builds_and_plays(kxr_project_path: Path) -> None:
    project = load_project(kxr_project_path)
    slot = free_slots(project)[0]
    motion = motion_from_keyframes(KF, slot=slot, name="taught", period_ms=15, button=0x0020)
    saved = dump_project(add_motion(project, motion))
    again = parse_project(saved)
    assert dump_project(again) == saved  # byte for byte
    m = again.motion(slot)
    assert m.name == "taught" and m.button_data == 0x0020 and m.frames == motion.frames
    image = build_project_image(again)
    sim = Simulator(image)
    sim.boot()
    result = sim.play(m.address, slot=slot, name="taught")
    assert result.status == "completed", result.detail
    assert result.duration == pytest.approx(1.8, abs=0.1)
    with pytest.raises(ValueError, match="pick a free slot"):
        add_motion(again, motion)


def test_a_stored_chain_of_poses_draws_back_as_its_flowchart(kxr_project_path: Path) -> None:
    from rcb4hv.hth4.blocks.flowxml import motion_from_xml, motion_xml

    project = load_project(kxr_project_path)
    slot = free_slots(project)[0]
    motion = motion_from_keyframes(KF, slot=slot, name="taught", period_ms=15)
    project = add_motion(project, motion)
    xml = motion_xml(project, slot)
    boxes = [a for a in parse_motion_xml(xml).activities if (a.name or "").startswith("Pos")]
    assert len(boxes) == len(KF)
    # a motion with branches draws too, and its flowchart compiles back to the same motion
    walk = next(m for m in project.used_motions if m.button_data == 0x0001)
    assert motion_from_xml(project, walk.slot, motion_xml(project, walk.slot)) == walk.frames
