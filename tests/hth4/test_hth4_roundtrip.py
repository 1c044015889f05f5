"""Model → file → model round trips for generated documents, and unknown elements kept."""

from __future__ import annotations

from decimal import Decimal

from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import hth4
from rcb4hv.hth4._xml import INT32_MAX, INT32_MIN, XSI, is_xml_text
from tests.hth4._hth4_fixtures import canonical, fixture

xml_text = st.text(
    st.characters(blacklist_categories=("Cs", "Cc"), whitelist_characters="\t\n\r"), max_size=12
).filter(is_xml_text)
opt_text = st.none() | xml_text
i32 = st.integers(INT32_MIN, INT32_MAX)
frames = st.lists(st.binary(min_size=1, max_size=24), max_size=4).map(tuple)
points = st.builds(hth4.Point, i32, i32)
layouts = st.sampled_from(
    [
        hth4.PROJECT_LAYOUT,
        hth4.XSI_FIRST_LAYOUT,
        hth4.XmlLayout(newline="\n", bom=True, final_newline=True),
        hth4.XmlLayout(declaration='<?xml version="1.0" encoding="utf-8"?>'),
    ]
)
tags = st.from_regex(r"[A-Za-z_][A-Za-z0-9_.-]{0,6}", fullmatch=True)
attr_names = tags | st.sampled_from([f"{{{XSI}}}type", "{urn:example}flag"])


@st.composite
def xml_nodes(draw: st.DrawFn, depth: int = 0) -> hth4.XmlNode:
    names = draw(st.lists(attr_names, max_size=2, unique=True))
    attrib = tuple((n, draw(xml_text)) for n in names)
    children: tuple[hth4.XmlNode, ...] = ()
    if depth < 2:
        children = tuple(draw(st.lists(xml_nodes(depth + 1), max_size=2)))
    text = "" if children else draw(xml_text)
    tag = draw(tags | st.just("{urn:example}Thing"))
    return hth4.XmlNode(tag, attrib, text, children)


raw_lists = st.none() | st.lists(xml_nodes(), max_size=2).map(tuple)

motions = st.builds(
    hth4.Motion,
    key=xml_text,
    number=i32,
    name=opt_text,
    date=xml_text,
    button_data=i32,
    compare_type=xml_text,
    frames=frames,
    address=i32,
    key_code=xml_text,
)
servos = st.builds(
    hth4.ServoConfig,
    key=xml_text,
    name=opt_text,
    device_number=i32,
    id=i32,
    port=xml_text,
    mode=xml_text,
    count=i32,
    rom_address=i32,
    ram_address=i32,
    code=i32,
    trim=i32,
    position=i32,
    mixing1_address=i32,
    mixing1_rate=i32,
    mixing2_address=i32,
    mixing2_rate=i32,
    display_rate=st.decimals(-(10**6), 10**6, allow_nan=False, allow_infinity=False, places=3),
    location=points,
    group=xml_text,
    fore_color=xml_text,
    back_color=xml_text,
)
kri3 = st.builds(
    hth4.Kri3Settings,
    name=opt_text,
    **{
        f: i32
        for f in [
            "count",
            "rom_address",
            "ram_address",
            "device_number",
            "code",
            "id",
            "receive_data_address",
            "receive_data_size",
            "button_value",
            "pa1",
            "pa2",
            "pa3",
            "pa4",
            "checksum",
        ]
    },
)
priority = st.builds(
    hth4.PriorityMotionSlot,
    key=xml_text,
    motion=st.none()
    | st.builds(
        hth4.PriorityMotion,
        name=opt_text,
        port=xml_text,
        compare_type=xml_text,
        value=i32,
        address=i32,
    ),
)
projects = st.builds(
    hth4.Project,
    config=st.binary(max_size=4),
    adc_reference=st.binary(max_size=24),
    kri3=kri3,
    motions=st.lists(motions, max_size=3).map(tuple),
    servos=st.lists(servos, max_size=2).map(tuple),
    startup_motion_address=i32,
    low_power_motion_address=i32,
    low_power_value=i32,
    priority_motions=st.lists(priority, max_size=3).map(tuple),
    picture_file_name=opt_text,
    link_file_list=raw_lists,
    convert_file_list=raw_lists,
    project_title=opt_text,
    file_name=opt_text,
    path=opt_text,
    name=opt_text,
    anchors=raw_lists,
    sound_device_number=i32,
    layout=layouts,
)


@settings(max_examples=120)
@given(projects)
def test_project_model_round_trip(project: hth4.Project) -> None:
    data = hth4.dump_project(project)
    again = hth4.parse_project(data)
    assert again == project
    assert hth4.dump_project(again) == data


sizes = st.builds(hth4.Size, i32, i32)
flowcharts = st.builds(
    hth4.Flowchart,
    name=opt_text,
    size=sizes,
    grid_size=i32,
    lines=st.lists(
        st.builds(
            hth4.FlowchartLine,
            guid=opt_text,
            path=st.lists(points, max_size=3).map(tuple),
            connect_mode=xml_text,
        ),
        max_size=2,
    ).map(tuple),
    activities=st.lists(
        st.builds(
            hth4.FlowchartActivity,
            name=opt_text,
            guid=opt_text,
            location=points,
            size=sizes,
            text=opt_text,
            back_color_text=opt_text,
            motion_flag=xml_text,
            base_name=opt_text,
            description=opt_text,
            group=opt_text,
            connected_guids=opt_text,
            connect_types=opt_text,
            program_code=frames,
            hint=opt_text,
        ),
        max_size=2,
    ).map(tuple),
    back_color_text=opt_text,
    layout=layouts,
)


@settings(max_examples=60)
@given(flowcharts)
def test_flowchart_model_round_trip(chart: hth4.Flowchart) -> None:
    assert hth4.parse_motion_xml(hth4.dump_motion_xml(chart)) == chart


trims = st.builds(
    hth4.TrimFile,
    entries=st.lists(
        st.builds(
            hth4.TrimEntry,
            key=xml_text,
            name=opt_text,
            id=i32,
            device_number=i32,
            trim=i32,
            position=i32,
        ),
        max_size=3,
    ).map(tuple),
    layout=layouts,
)


@settings(max_examples=60)
@given(trims)
def test_trim_model_round_trip(trim: hth4.TrimFile) -> None:
    assert hth4.parse_trim(hth4.dump_trim(trim)) == trim


csv_text = st.text(st.sampled_from('abcXYZ 0129,"\n\r\t名前歩行↑↓→←△×○□'), max_size=10)
nat = st.integers(0, 2**40)
entries = st.builds(
    hth4.MotionListEntry,
    key=csv_text,
    name=csv_text,
    button_data=nat,
    button_label=csv_text,
    compare=csv_text,
    date=csv_text,
    used_bytes=nat,
    used_percent=st.integers(0, 10**6).map(lambda n: Decimal(n).scaleb(-1)),
    address=nat,
    extra_cells=st.lists(csv_text, max_size=2).map(tuple),
)


@settings(max_examples=60)
@given(st.lists(entries, max_size=4).map(tuple))
def test_motion_list_model_round_trip(rows: tuple[hth4.MotionListEntry, ...]) -> None:
    mlist = hth4.MotionList(entries=rows)
    assert hth4.parse_motion_list(hth4.dump_motion_list(mlist)) == mlist


@settings(max_examples=60)
@given(xml_nodes(), layouts)
def test_generic_document_round_trip(root: hth4.XmlNode, layout: hth4.XmlLayout) -> None:
    doc = hth4.XmlDocument(hth4.XmlNode("Link", (), root.text, root.children), layout)
    data = hth4.dump_link(doc)
    assert hth4.parse_link(data) == doc


@given(st.integers(0, 0xFFFF))
def test_button_label_lists_set_bits_in_order(value: int) -> None:
    label = hth4.button_label(value)
    expected = [sym for bit, sym in hth4.BUTTON_SYMBOLS if value & bit]
    assert label.split("+") == (expected or [""])


def test_button_labels_seen_in_the_fixture() -> None:
    assert hth4.button_label(514) == "↓+S1"
    assert hth4.button_label(592) == "△+○+S1"
    assert hth4.button_label(9) == "↑+←"
    assert hth4.button_label(0) == ""


# -- unknown elements survive ---------------------------------------------------------------

_KRI3_COUNT = "    <Count>11</Count>\r\n"
_INJECT_KRI3 = '    <Future a="1">\r\n      <Bar xsi:type="xsd:string">x</Bar>\r\n    </Future>\r\n'
_INJECT_ROOT = "  <NewSetting>5</NewSetting>\r\n"


def test_unknown_elements_are_kept_in_place() -> None:
    raw = fixture("HAC_KXR_HTH4_project.h4p").read_bytes().decode("utf-8")
    assert raw.count(_KRI3_COUNT) == 1
    text = raw.replace(_KRI3_COUNT, _KRI3_COUNT + _INJECT_KRI3)
    text = text.replace("</Rcb4>", _INJECT_ROOT + "</Rcb4>")
    key = '<Key xsi:type="xsd:string">M003</Key>\r\n'
    text = text.replace(key, key + "      <Comment>keep me</Comment>\r\n")
    data = text.encode("utf-8")
    project = hth4.parse_project(data)
    assert [(e.parent, e.node.tag) for e in project.extra] == [
        ("", "NewSetting"),
        ("Kri3", "Future"),
        ("MotionDataCollection/DictionaryEntry[3]", "Comment"),
    ]
    assert project.extra[1].node.children[0].attrib == ((f"{{{XSI}}}type", "xsd:string"),)
    assert hth4.dump_project(project) == data
    # Known data is unaffected.
    assert project.kri3.count == 11 and project.motion(3).name == "XL2G_103_微細歩行左"


def test_foreign_namespace_extra_round_trips_canonically() -> None:
    raw = fixture("KXR-L2G標準トリム.h4t").read_bytes().decode("utf-8")
    text = raw.replace(
        "</ArrayOfDictionaryEntry>",
        '  <x:Note xmlns:x="urn:example" x:lang="ja">メモ</x:Note>\r\n</ArrayOfDictionaryEntry>',
    )
    trim = hth4.parse_trim(text)
    assert trim.extra[0].node.tag == "{urn:example}Note"
    out = hth4.dump_trim(trim)
    assert canonical(out) == canonical(text.encode("utf-8"))
    assert hth4.parse_trim(out) == trim
