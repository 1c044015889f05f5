"""Motions as HeartToHeart4 flowchart XML: HeartToHeart4's own flowcharts compile to the
motions it stored, and every motion goes through XML and back unchanged."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import protocol as p
from rcb4hv.errors import EditError
from rcb4hv.hth4 import Project, load_project, parse_motion_xml
from rcb4hv.hth4.blocks import motion_program
from rcb4hv.hth4.blocks.flowxml import EXACT_NAME, motion_from_xml, motion_xml
from rcb4hv.hth4.model import motion_rom_address
from tests.hth4._programs import one_motion_project
from tests.strategies import commands


@pytest.fixture(scope="module")
def kxr(kxr_project_path: Path) -> Project:
    return load_project(kxr_project_path)


@pytest.mark.parametrize(
    ("name", "slot"),
    [
        ("HAC_KXR_STAND_UP.xml", 72),
        ("HAC_KXR_TURN_LEFT.xml", 69),  # a button loop
        ("HAC_KXR_WALK_FORWARD.xml", 66),  # two button branches, True arrows both ways
        ("XL2G_201_挨拶.xml", 21),
        ("XL2G_291_ホームポジション.xml", 39),
    ],
)
def test_hth4_flowcharts_compile_to_the_stored_motion(
    kxr: Project, kxr_dir: Path, name: str, slot: int
) -> None:
    assert motion_from_xml(kxr, slot, (kxr_dir / name).read_bytes()) == kxr.motion(slot).frames


def test_every_motion_goes_through_xml_unchanged(kxr: Project) -> None:
    drawn = 0
    for m in kxr.used_motions:
        xml = motion_xml(kxr, m.slot)
        assert motion_from_xml(kxr, m.slot, xml) == m.frames, m.slot
        chart = parse_motion_xml(xml)
        assert chart.start is not None
        drawn += chart.name != EXACT_NAME
    assert drawn == 64  # motion 12 holds a JUMP a drawing does not compile to


def test_looping_motion_is_drawn_with_true_arrows(kxr: Project) -> None:
    chart = parse_motion_xml(motion_xml(kxr, 69))
    assert chart.name == "canvas"
    assert [line.connect_mode for line in chart.lines].count("True") == 1
    cmp = [a for a in chart.activities if a.base_name == "CmpButton"]
    assert len(cmp) == 1 and cmp[0].program_code[-1].hex() == "070bffffff0514"
    assert len(chart.activities) == sum(
        b.kind not in ("jump", "return", "end") for b in motion_program(kxr, 69).blocks
    )


def test_a_chart_without_start_is_refused(kxr: Project) -> None:
    xml = motion_xml(kxr, 69).replace(
        b"<MotionFlag>Start</MotionFlag>", b"<MotionFlag>None</MotionFlag>"
    )
    with pytest.raises(EditError, match="one Start box"):
        motion_from_xml(kxr, 69, xml)


def test_two_plain_arrows_out_of_a_box_are_refused(kxr: Project) -> None:
    xml = motion_xml(kxr, 69).replace(
        b"<ConnectMode>True</ConnectMode>", b"<ConnectMode>Normal</ConnectMode>"
    )
    with pytest.raises(EditError, match="none is marked True"):
        motion_from_xml(kxr, 69, xml)


@settings(max_examples=120, deadline=None)
@given(st.lists(commands, min_size=1, max_size=10), st.booleans(), st.data())
def test_any_motion_goes_through_xml_unchanged(
    cmds: list[p.Command], end: bool, data: st.DataObject
) -> None:
    base = motion_rom_address(1)
    frames = [p.encode_command(c) for c in cmds]
    # some branches back into the motion, as flowcharts make them
    for i, f in enumerate(frames):
        if f[1] in (p.Op.JUMP, p.Op.CALL) and data.draw(st.booleans()):
            to = data.draw(st.integers(0, len(frames) - 1))
            cond = p.decode_command(f).condition  # type: ignore[union-attr]
            frames[i] = p.Jump(base + sum(map(len, frames[:to])), cond).encode()
    entries = tuple(frames) + ((b"\x03\x0d\x10\xff",) if end else ())
    project = one_motion_project(entries)
    assert motion_from_xml(project, 1, motion_xml(project, 1)) == entries
