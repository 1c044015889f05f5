"""Malformed and foreign input raise Hth4FormatError naming the element; bad models ValueError."""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import replace

import pytest

from rcb4hv import hth4
from rcb4hv.errors import Hth4FormatError, Rcb4Error
from tests.hth4._hth4_fixtures import fixture


def _small_project() -> bytes:
    motions = tuple(
        hth4.Motion(
            key=hth4.motion_key(n),
            number=n - 1,
            name=f"m{n}",
            date="2024-01-01T00:00:00+09:00",
            frames=(bytes((0x10 + n, 0xAB)), bytes((0xCD, 0x20 + n))),
            address=hth4.motion_rom_address(n),
        )
        for n in (1, 2, 3)
    )
    return hth4.dump_project(
        hth4.Project(motions=motions, priority_motions=(hth4.PriorityMotionSlot("0"),))
    )


def _error(data: bytes | str, parse: Callable[[bytes | str], object] = hth4.parse_project) -> str:
    with pytest.raises(Hth4FormatError) as info:
        parse(data)
    assert isinstance(info.value, ValueError) and isinstance(info.value, Rcb4Error)
    return str(info.value)


def test_small_project_parses() -> None:
    project = hth4.parse_project(_small_project())
    assert project.motion(3).frames == (b"\x13\xab", b"\xcd\x23")


def test_non_hex_frame_names_the_element() -> None:
    data = _small_project().replace(b">CD 23<", b">CD 2G<")
    assert _error(data) == (
        "Rcb4/MotionDataCollection/DictionaryEntry[3]/Value/MotionData/anyType[2]: "
        "not a hex byte string: 'CD 2G'"
    )


@pytest.mark.parametrize("bad", [b"", b"CD23", b"CD  23", b" CD 23", b"C D"])
def test_other_malformed_hex_strings(bad: bytes) -> None:
    data = _small_project().replace(b">CD 23<", b">" + bad + b"<")
    assert "MotionData/anyType[2]: not a hex byte string" in _error(data)


def test_truncated_xml() -> None:
    raw = fixture("HAC_KXR_HTH4_project.h4p").read_bytes()
    assert _error(raw[:5000]).startswith("not well-formed XML")


def test_wrong_root_element() -> None:
    raw = fixture("KXR-L2G標準トリム.h4t").read_bytes()
    assert _error(raw) == "ArrayOfDictionaryEntry: wrong root element: expected <Rcb4>"
    assert "CanvasData: wrong root element" in _error(
        raw.replace(b"ArrayOfDictionaryEntry", b"CanvasData")
    )
    proj = fixture("HAC_KXR_HTH4_project.h4p").read_bytes()
    assert _error(proj, hth4.parse_motion_xml).startswith("Rcb4: wrong root element")
    assert _error(proj, hth4.parse_trim).startswith("Rcb4: wrong root element")


def test_wrong_types() -> None:
    data = _small_project()
    assert _error(data.replace(b"<Number>1</Number>", b"<Number>one</Number>")) == (
        "Rcb4/MotionDataCollection/DictionaryEntry[2]/Value/Number: not an integer: 'one'"
    )
    assert _error(
        data.replace(b"<unsignedByte>130</unsignedByte>", b"<unsignedByte>300</unsignedByte>")
    ) == ("Rcb4/Config/unsignedByte[2]: 300 out of range 0..255")
    assert _error(data.replace(b"<Count>11</Count>", b"<Count>99999999999</Count>")).startswith(
        "Rcb4/Kri3/Count: 99999999999 out of range"
    )
    assert "Rcb4/Kri3/Count: expected text, found child elements" in _error(
        data.replace(b"<Count>11</Count>", b"<Count><X /></Count>")
    )


def test_missing_element_and_wrong_xsi_type() -> None:
    data = _small_project()
    no_kri3 = re.sub(rb"<Kri3>.*</Kri3>", b"", data, flags=re.S)
    assert _error(no_kri3) == "Rcb4/Kri3: missing element"
    wrong = data.replace(b'<Value xsi:type="Motion">', b'<Value xsi:type="Servo">', 1)
    assert _error(wrong) == (
        "Rcb4/MotionDataCollection/DictionaryEntry[1]/Value: "
        "expected xsi:type=\"Motion\", found 'Servo'"
    )
    no_value = re.sub(rb'<Value xsi:type="Motion">.*?</Value>', b"", data, count=1, flags=re.S)
    assert _error(no_value) == "Rcb4/MotionDataCollection/DictionaryEntry[1]/Value: missing element"


def test_unexpected_attribute_and_mixed_content() -> None:
    data = _small_project()
    assert (
        _error(data.replace(b"<Kri3>", b'<Kri3 id="x">')) == "Rcb4/Kri3: unexpected attribute 'id'"
    )
    assert "Rcb4/Kri3: mixed text" in _error(data.replace(b"<Kri3>", b"<Kri3>hello"))


def test_flowchart_and_trim_errors() -> None:
    chart = fixture("XL2G_291_ホームポジション.xml").read_bytes()
    bad = chart.replace(b"<GridSize>8</GridSize>", b"<GridSize>8.5</GridSize>")
    assert _error(bad, hth4.parse_motion_xml) == "CanvasData/GridSize: not an integer: '8.5'"
    bad = chart.replace(b"<X>85</X>", b"<X>?</X>")
    assert _error(bad, hth4.parse_motion_xml) == (
        "CanvasData/Lines/anyType[1]/Path/Point[1]/X: not an integer: '?'"
    )
    trim = fixture("KXR-L2G標準トリム.h4t").read_bytes()
    bad = trim.replace(b"<Trim>1350</Trim>", b"<Trim />")
    assert (
        _error(bad, hth4.parse_trim)
        == "ArrayOfDictionaryEntry/DictionaryEntry[3]/Value/Trim: not an integer: ''"
    )


def test_motion_list_errors() -> None:
    raw = fixture("HAC_KXR_HTH4_project.csv").read_bytes()
    text = raw.decode("cp932")
    assert _error(text.replace('"B:514"', '"B:x"'), hth4.parse_motion_list) == (
        "line 11, column 3: not a button word like 'B:0': 'B:x'"
    )
    assert _error(
        text.replace('"2944 (00B80)"', '"2944 (00B81)"'), hth4.parse_motion_list
    ).startswith("line 2, column 8: not an address")
    assert _error(text.replace('"592 (28.9 %)"', '"592"', 1), hth4.parse_motion_list).startswith(
        "line 2, column 7: not a usage"
    )
    short = text.replace(',"2944 (00B80)"', "")
    assert _error(short, hth4.parse_motion_list) == "line 2: expected 8 cells, found 7"
    assert _error(b"\x82", hth4.parse_motion_list) == "byte 0: not Shift-JIS (cp932) text"
    assert _error(b"", hth4.parse_motion_list).startswith("line 1: empty file")
    assert _error(
        fixture("KXR-L2G標準トリム.h4t").read_bytes()[:40], hth4.parse_motion_list
    ).startswith("line 1: not a motion-list header")


def test_generic_document_errors() -> None:
    assert _error(b"<a><b></a>", hth4.parse_link).startswith("not well-formed XML")
    assert "mixed text" in _error(b"<a>x<b /></a>", hth4.parse_link)


# -- writing bad models ---------------------------------------------------------------------


def test_writer_rejects_values_it_cannot_represent() -> None:
    base = hth4.parse_project(_small_project())
    with pytest.raises(ValueError, match="out of range"):
        hth4.dump_project(replace(base, sound_device_number=2**31))
    with pytest.raises(ValueError, match=r"XML 1\.0"):
        hth4.dump_project(replace(base, name="bad\x00name"))
    with pytest.raises(ValueError, match="empty"):
        hth4.dump_project(replace(base, motions=(replace(base.motions[0], frames=(b"",)),)))
    with pytest.raises(ValueError, match="expected an int"):
        hth4.dump_project(replace(base, low_power_value=True))
    with pytest.raises(ValueError, match="Shift-JIS"):
        entry = hth4.MotionListEntry.from_motion(base.motions[0])
        hth4.dump_motion_list(hth4.MotionList((replace(entry, name="\U0001f600"),)))


def test_rom_address_helpers() -> None:
    assert hth4.motion_rom_address(1) == 0x0B80
    assert hth4.motion_rom_address(120) == 0x0B80 + 2048 * 119 == 0x3C380
    assert hth4.motion_rom_address(2, "2.1") == 0x0BB8 + 2048
    assert hth4.motion_rom_address(50, "1.3") == 0x0BB8 + 0x1300 * 49
    for bad in (0, 121, True):
        with pytest.raises(ValueError):
            hth4.motion_rom_address(bad)
    with pytest.raises(ValueError):
        hth4.motion_rom_address(51, "1.3")
    with pytest.raises(ValueError, match="unknown HeartToHeart4 layout"):
        hth4.motion_rom_address(1, "3.0")
    assert hth4.motion_key(7) == "M007" and hth4.slot_from_key("M120") == 120
    for key in ("M000", "X001", "M01", "M١٢٣"):
        with pytest.raises(ValueError):
            hth4.slot_from_key(key)
