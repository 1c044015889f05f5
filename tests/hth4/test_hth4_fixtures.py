"""The real HeartToHeart4 files: concrete facts and byte-identical round trips."""

from __future__ import annotations

from collections.abc import Callable
from decimal import Decimal
from pathlib import Path
from typing import Any

import pytest

from rcb4hv import hth4
from rcb4hv.protocol import Return, checksum, decode_command
from tests.hth4._hth4_fixtures import canonical, fixture

PROJECT = "HAC_KXR_HTH4_project.h4p"
CSV = "HAC_KXR_HTH4_project.csv"
TRIM = "KXR-L2G標準トリム.h4t"
FLOWCHARTS = (
    "HAC_KXR_STAND_UP.xml",
    "HAC_KXR_TURN_LEFT.xml",
    "HAC_KXR_WALK_FORWARD.xml",
    "XL2G_201_挨拶.xml",
    "XL2G_291_ホームポジション.xml",
)


@pytest.fixture(scope="module")
def project() -> hth4.Project:
    return hth4.load_project(fixture(PROJECT))


# -- project facts ---------------------------------------------------------------------------


def test_project_motion_slots(project: hth4.Project) -> None:
    assert len(project.motions) == 120
    assert len(project.used_motions) == 65  # per ATTRIBUTION.md
    first = project.motions[0]
    assert (first.key, first.number, first.slot) == ("M001", 0, 1)
    assert first.name == "XL2G_101_微細歩行前"
    assert first.date == "2023-09-22T14:06:20.014026+09:00"
    assert first.frames[0] == bytes.fromhex(
        "13 12 00 FF 03 00 00 01 64 64 64 64 64 64 64 64 64 64 10"
    )
    assert len(first.frames) == 21
    assert first.address == 0x0B80
    empty = project.motion(18)
    assert empty.is_empty and empty.name == "M018" and empty.rom_bytes() == b""


def test_every_slot_number_key_and_address_agree(project: hth4.Project) -> None:
    for n, motion in enumerate(project.motions, 1):
        assert motion.slot == n
        assert motion.key == hth4.motion_key(n)
        assert hth4.slot_from_key(motion.key) == n
        assert motion.address == hth4.motion_rom_address(n) == 0x0B80 + 2048 * (n - 1)
        assert motion.address == motion.expected_address("2.2")
        assert len(motion.rom_bytes()) <= hth4.MOTION_SLOT_SIZE


def test_button_bindings(project: hth4.Project) -> None:
    assert project.motion(9).button == (1, "Equals")  # UP
    assert project.motion(10).button == (514, "Equals")  # DOWN + S1
    assert project.motion(17).button_data == 0x0800  # S3
    assert {m.compare_type for m in project.motions} == {"Equals"}


def test_every_frame_has_a_valid_checksum_and_decodes(project: hth4.Project) -> None:
    frames = 0
    for motion in project.used_motions:
        *body, last = motion.frames
        # HeartToHeart4 ends every motion with RETURN followed by one FF byte.
        assert last == bytes.fromhex("03 0D 10 FF")
        assert isinstance(decode_command(last[:3]), Return)
        for frame in body:
            assert frame[0] == len(frame)
            assert frame[-1] == sum(frame[:-1]) & 0xFF == checksum(frame[:-1])
            decode_command(frame)
            frames += 1
    assert frames == 953 - 65


def test_servo_configuration(project: hth4.Project) -> None:
    assert len(project.servos) == 35
    assert [s.ics_number for s in project.servos] == list(range(35))
    s = project.servo(2)
    assert (s.key, s.name, s.id, s.port, s.mode) == (
        "右肩（ピッチ）",
        "右肩（ピッチ）",
        1,
        "SIO1",
        "Normal",
    )
    assert (s.trim, s.home_position, s.count) == (1350, 7500, 20)
    assert (s.rom_address, s.ram_address) == (0x0626 + 20 * 2, 0x0090 + 20 * 2)
    assert s.display_rate == Decimal("1.0") and s.location == hth4.Point(296, 88)
    assert project.servo(3).trim == -1350
    assert project.servo(14).mixing1_rate == 8
    assert not project.servo(0).in_use and project.servo(13).in_use
    assert project.servos_by_ics[12].trim == -1980
    with pytest.raises(KeyError):
        project.servo(35)


def test_config_adc_kri3_and_startup(project: hth4.Project) -> None:
    assert project.config == bytes((27, 130))
    assert project.system_register == 0x821B
    assert len(project.adc_reference) == 22
    assert project.adc_reference_words[:3] == (0, 0x0111, 0x0111)
    k = project.kri3
    assert (k.name, k.count, k.ram_address, k.device_number, k.code, k.id) == (
        "KRI-3",
        11,
        0x034C,
        35,
        1,
        31,
    )
    assert k.receive_data_size == 7
    assert project.startup_motion_address == 80768
    startup = project.startup_motion
    assert startup is not None and startup.slot == 39
    assert startup.name == "XL2G_291_ホームポジション"
    assert project.project_title == "HAC-KXR"
    assert project.link_file_list == () and project.anchors == ()
    assert project.sound_device_number == -1


def test_priority_motions(project: hth4.Project) -> None:
    keys = [p.key for p in project.priority_motions]
    assert keys == [str(i) for i in range(13)] + ["-1"]
    [(index, battery)] = project.active_priority_motions
    assert index == 0
    assert (battery.port, battery.compare_type, battery.value) == (
        "Battery",
        "LessThanOrEqualTo",
        223,
    )
    target = project.motion_at(battery.address)
    assert target is not None and target.name == battery.name == "XL2G_292_電圧低下"


# -- other files -----------------------------------------------------------------------------


def test_flowchart_matches_project_motion(project: hth4.Project) -> None:
    chart = hth4.load_motion_xml(fixture("XL2G_291_ホームポジション.xml"))
    assert (chart.name, chart.size, chart.grid_size) == ("canvas", hth4.Size(640, 480), 8)
    assert len(chart.lines) == 1 and len(chart.activities) == 2
    start = chart.start
    assert start is not None and start.name == "ServoParam2" and start.text == "ホームストレッチ"
    pos = chart.activity("Pos0")
    assert pos.connections == (("961d9112-43e0-4340-aad3-e51d1543a881", "EndConnect"),)
    # The project's compiled motion: the start box, the next box, RETURN, RETURN + FF.
    motion = project.motion(39)
    assert motion.frames[:2] == start.program_code + pos.program_code
    assert motion.frames[2:] == (bytes.fromhex("03 0D 10"), bytes.fromhex("03 0D 10 FF"))


def test_trim_file(project: hth4.Project) -> None:
    trim = hth4.load_trim(fixture(TRIM))
    assert len(trim.entries) == 35
    e = trim.by_ics[3]
    assert (e.key, e.name, e.id, e.trim, e.position) == (
        "左肩（ピッチ）",
        "左肩（ピッチ）",
        1,
        -1350,
        7500,
    )
    differing = {t.ics_number for t in trim.entries if t.trim != project.servo(t.ics_number).trim}
    assert differing == {12, 14, 15}


def test_motion_list_matches_project(project: hth4.Project) -> None:
    mlist = hth4.load_motion_list(fixture(CSV))
    assert mlist.header == hth4.motionlist.DEFAULT_HEADER
    assert len(mlist.entries) == 120
    row = mlist.entries[9]
    assert (row.key, row.name, row.button_data, row.button_label) == (
        "M010",
        "XL2G_110_高速歩行後",
        514,
        "↓+S1",
    )
    assert (row.used_bytes, row.used_percent, row.address) == (592, Decimal("28.9"), 21376)
    assert mlist.entries[17].name == "名称未設定"
    assert tuple(hth4.MotionListEntry.from_motion(m) for m in project.motions) == mlist.entries


# -- round trips -----------------------------------------------------------------------------

_Parse = Callable[[bytes | str], object]
_KINDS: dict[str, tuple[_Parse, Callable[[Any], bytes]]] = {
    ".h4p": (hth4.parse_project, hth4.dump_project),
    ".xml": (hth4.parse_motion_xml, hth4.dump_motion_xml),
    ".h4t": (hth4.parse_trim, hth4.dump_trim),
    ".csv": (hth4.parse_motion_list, hth4.dump_motion_list),
}


@pytest.mark.parametrize("name", [PROJECT, CSV, TRIM, *FLOWCHARTS])
def test_round_trip_is_byte_identical(name: str) -> None:
    raw = fixture(name).read_bytes()
    parse, dump = _KINDS[Path(name).suffix]
    model = parse(raw)
    assert dump(model) == raw
    assert parse(raw.decode("cp932" if name.endswith(".csv") else "utf-8")) == model


@pytest.mark.parametrize("name", [PROJECT, TRIM, *FLOWCHARTS])
def test_xml_files_also_round_trip_as_generic_documents(name: str) -> None:
    raw = fixture(name).read_bytes()
    doc = hth4.parse_link(raw)
    assert hth4.dump_link(doc) == raw
    assert canonical(hth4.dump_link(doc)) == canonical(raw)


def test_save_and_load_through_files(tmp_path: Path, project: hth4.Project) -> None:
    hth4.save_project(project, tmp_path / "p.h4p")
    assert hth4.load_project(tmp_path / "p.h4p") == project
    chart = hth4.load_motion_xml(fixture(FLOWCHARTS[0]))
    hth4.save_motion_xml(chart, tmp_path / "c.xml")
    assert hth4.load_motion_xml(tmp_path / "c.xml") == chart
    trim = hth4.load_trim(fixture(TRIM))
    hth4.save_trim(trim, tmp_path / "t.h4t")
    assert hth4.load_trim(tmp_path / "t.h4t") == trim
    mlist = hth4.load_motion_list(fixture(CSV))
    hth4.save_motion_list(mlist, tmp_path / "m.csv")
    assert hth4.load_motion_list(tmp_path / "m.csv") == mlist
    doc = hth4.load_link(fixture(TRIM))
    hth4.save_link(doc, tmp_path / "l.h4l")
    assert (tmp_path / "l.h4l").read_bytes() == fixture(TRIM).read_bytes()
