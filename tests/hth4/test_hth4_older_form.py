"""The older flowchart form (root ``ArrayOfAnyType``): read into the model, written back byte
for byte, and made from the fixture flowcharts."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv import hth4
from rcb4hv.errors import Hth4FormatError
from rcb4hv.hth4.blocks.flowxml import motion_from_xml, motion_xml
from rcb4hv.hth4.flowchart_older import dump_older_flowchart, to_older_form
from rcb4hv.hth4.model import Point

from ._hth4_fixtures import FIXTURES, fixture

XSI = "{http://www.w3.org/2001/XMLSchema-instance}type"


def _activity(name: str, guid: str, x: int, flag: str, links: str, types: str, code: str) -> str:
    return f"""  <anyType xsi:type="ActivityData">
    <Name>{name}</Name>
    <GUID>{guid}</GUID>
    <Location>
      <X>{x}</X>
      <Y>16</Y>
    </Location>
    <Size>
      <Width>64</Width>
      <Height>48</Height>
    </Size>
    <MotionFlag>{flag}</MotionFlag>
    <PriorityList>
      <anyType xsi:type="xsd:string">00 00 00 00</anyType>
    </PriorityList>
    <BaseName>Pos</BaseName>
    <Description>ポジション設定</Description>
    <Group>Position</Group>
    <Path />
    <ConnectedGuids>{links}</ConnectedGuids>
    <ConnectTypes>{types}</ConnectTypes>
    <ProgramCode>
      <anyType xsi:type="xsd:string">{code}</anyType>
    </ProgramCode>
  </anyType>
"""


def _line(guid: str, x0: int, x1: int) -> str:
    return f"""  <anyType xsi:type="LineData">
    <Name />
    <StartPoint>
      <X>{x0}</X>
      <Y>40</Y>
    </StartPoint>
    <EndPoint>
      <X>{x1}</X>
      <Y>40</Y>
    </EndPoint>
    <GUID>{guid}</GUID>
    <LineType>Straight</LineType>
  </anyType>
"""


G1 = "11111111-2222-4333-8444-555555555555"
Z = "00000000-0000-0000-0000-000000000000"
POSE_A = "0D 10 03 00 00 00 00 14 4C 1D 4C 1D 03"
POSE_B = "0D 10 03 00 00 00 00 28 B0 1D E8 1C 70"


def sample(order: str = "ala") -> bytes:
    """A two-box, one-arrow chart in the older shape, items in ``order`` (a = box, l = arrow)."""
    boxes = iter(
        [
            _activity("Pos1", "aaaaaaaa-0000-4000-8000-000000000001", 16, "Start",
                      f"{Z},{Z},{Z},{G1}", "NotConnected,NotConnected,NotConnected,BeginConnect",
                      POSE_A),
            _activity("Pos2", "aaaaaaaa-0000-4000-8000-000000000002", 96, "None",
                      f"{Z},{Z},{G1},{Z}", "NotConnected,NotConnected,EndConnect,NotConnected",
                      POSE_B),
        ]
    )  # fmt: skip
    body = "".join(next(boxes) if c == "a" else _line(G1, 76, 98) for c in order)
    text = (
        '<?xml version="1.0"?>\n<ArrayOfAnyType xmlns:xsi="http://www.w3.org/2001/XMLSchema-'
        'instance" xmlns:xsd="http://www.w3.org/2001/XMLSchema">\n' + body + "</ArrayOfAnyType>"
    )
    return text.replace("\n", "\r\n").encode("utf-8")


def test_older_form_reads_into_the_flowchart_model() -> None:
    chart = hth4.parse_motion_xml(sample())
    assert chart.item_types == ("ActivityData", "LineData", "ActivityData")
    assert [a.name for a in chart.activities] == ["Pos1", "Pos2"]
    start = chart.start
    assert start is not None and start.name == "Pos1" and start.text is None
    assert start.program_code == (bytes.fromhex(POSE_A),)
    assert start.connections[-1] == (G1, "BeginConnect")
    assert chart.lines == (hth4.FlowchartLine(G1, (Point(76, 40), Point(98, 40)), "Straight"),)
    kept = {(e.parent, e.position, e.node.tag) for e in chart.extra}
    assert kept == {
        ("anyType[1]", 5, "PriorityList"),
        ("anyType[1]", 9, "Path"),
        ("anyType[2]", 0, "Name"),
        ("anyType[3]", 5, "PriorityList"),
        ("anyType[3]", 9, "Path"),
    }


@pytest.mark.parametrize("order", ["ala", "aal", "laa"])
def test_older_form_writes_back_byte_for_byte(order: str) -> None:
    data = sample(order)
    chart = hth4.parse_motion_xml(data)
    assert hth4.dump_motion_xml(chart) == data
    assert hth4.dump_motion_xml(hth4.parse_motion_xml(data.replace(b"\r\n", b"\n"))) == (
        data.replace(b"\r\n", b"\n")
    )


@given(st.lists(st.sampled_from("al"), min_size=0, max_size=6))
def test_any_interleaving_round_trips(kinds: list[str]) -> None:
    order = "".join(kinds)
    data = sample(order) if order.count("a") == 2 else None
    if data is None:  # sample() has two boxes; vary only the arrows around them
        order = "a" + order.replace("a", "") + "a"
        data = sample(order)
    chart = hth4.parse_motion_xml(data)
    assert "".join("a" if t == "ActivityData" else "l" for t in chart.item_types or ()) == order
    assert hth4.dump_motion_xml(chart) == data


FLOWCHARTS = [
    "XL2G_201_挨拶.xml",
    "XL2G_291_ホームポジション.xml",
    "HAC_KXR_STAND_UP.xml",
    "HAC_KXR_TURN_LEFT.xml",
    "HAC_KXR_WALK_FORWARD.xml",
]


@pytest.mark.parametrize("name", FLOWCHARTS)
def test_fixture_flowchart_in_the_older_shape_round_trips(name: str) -> None:
    chart = hth4.load_motion_xml(fixture(name))
    older = to_older_form(chart)
    data = hth4.dump_motion_xml(older)
    root = ET.fromstring(data)
    assert root.tag == "ArrayOfAnyType" and root.find("CanvasData") is None
    kinds = [item.get(XSI) for item in root]
    assert kinds == ["ActivityData"] * len(chart.activities) + ["LineData"] * len(chart.lines)
    for item in root:
        tags = [c.tag for c in item]
        if item.get(XSI) == "ActivityData":
            assert tags[4:6] == ["MotionFlag", "PriorityList"] and tags[9] == "Path"
            assert "Text" not in tags and "Hint" not in tags
        else:
            assert tags == ["Name", "StartPoint", "EndPoint", "GUID", "LineType"]
    back = hth4.parse_motion_xml(data)
    assert back == older
    assert hth4.dump_motion_xml(back) == data
    assert [a.program_code for a in back.activities] == [a.program_code for a in chart.activities]
    assert [(a.guid, a.connections) for a in back.activities] == [
        (a.guid, a.connections) for a in chart.activities
    ]
    assert [(ln.guid, ln.path[0], ln.path[-1]) for ln in back.lines] == [
        (ln.guid, ln.path[0], ln.path[-1]) for ln in chart.lines
    ]
    assert data.startswith(b'<?xml version="1.0"?>\r\n<ArrayOfAnyType xmlns:xsi=')


def test_canvas_form_is_unchanged_by_the_older_reader() -> None:
    raw = fixture(FLOWCHARTS[0]).read_bytes()
    chart = hth4.parse_motion_xml(raw)
    assert chart.item_types is None and hth4.dump_motion_xml(chart) == raw
    assert FIXTURES.is_dir()


def test_older_form_errors_are_typed() -> None:
    bad = sample().replace(b'"LineData"', b'"CommentData"')
    with pytest.raises(Hth4FormatError, match=r"ArrayOfAnyType/anyType\[2\]: expected"):
        hth4.parse_motion_xml(bad)
    with pytest.raises(Hth4FormatError, match="wrong root element"):
        hth4.parse_motion_xml(b'<?xml version="1.0"?>\r\n<ArrayOfString />')
    chart = hth4.parse_motion_xml(sample())
    from dataclasses import replace

    with pytest.raises(ValueError, match="does not match"):
        dump_older_flowchart(replace(chart, item_types=("ActivityData", "ActivityData")))
    three = hth4.FlowchartLine(G1, (Point(), Point(1, 1), Point(2, 2)), "Straight")
    with pytest.raises(ValueError, match="2 points"):
        dump_older_flowchart(replace(chart, lines=(three,)))
    with pytest.raises(ValueError, match="not an older-form chart"):
        dump_older_flowchart(replace(chart, item_types=None))


@pytest.fixture(scope="module")
def kxr(kxr_project_path: Path) -> hth4.Project:
    return hth4.load_project(kxr_project_path)


@pytest.mark.parametrize(
    ("name", "slot"),
    [
        ("HAC_KXR_TURN_LEFT.xml", 69),  # a button loop: one CmpButton box, one True arrow
        ("HAC_KXR_WALK_FORWARD.xml", 66),  # two button branches
        (None, 69),  # the chart rcb4hv draws of that motion (project motion-xml)
    ],
)
def test_older_form_keeps_the_true_arrow_of_a_compare_box(
    kxr: hth4.Project, name: str | None, slot: int
) -> None:
    """to_older_form set every arrow's LineType to Straight, so the result no longer compiled
    ("flowchart box CmpButton4: two arrows leave it and none is marked True"): the older form's
    reader takes LineType as the arrow's ConnectMode, True marking the branch taken."""
    raw = fixture(name).read_bytes() if name else motion_xml(kxr, slot)
    chart = hth4.parse_motion_xml(raw)
    assert any(line.connect_mode == "True" for line in chart.lines)
    data = hth4.dump_motion_xml(to_older_form(chart))
    back = hth4.parse_motion_xml(data)
    assert back.item_types is not None
    branch = {"True", "False"}

    def marks(c: hth4.Flowchart) -> list[tuple[str | None, str]]:
        return [(ln.guid, ln.connect_mode) for ln in c.lines if ln.connect_mode in branch]

    assert marks(back) == marks(chart)
    assert {ln.connect_mode for ln in back.lines} - branch <= {"Straight"}
    assert motion_from_xml(kxr, slot, data) == kxr.motion(slot).frames
