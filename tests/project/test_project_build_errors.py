"""A project that loads but holds values the ROM image cannot: one typed error naming the
servo or motion and the field (Hth4FormatError, LayoutError for a motion stored elsewhere),
the same from both build entry points, nothing cut to fit; ``project check`` reports them
as findings instead of raising; an erased ROM dump says it is not an image."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import pytest

from rcb4hv import hth4
from rcb4hv.errors import FrameError, Hth4FormatError, LayoutError, ProtocolError
from rcb4hv.project.check import check_project
from rcb4hv.project.image import build_project_image, read_image
from rcb4hv.project.relocate import project_image
from rcb4hv.rom import layout


def _servo(project: hth4.Project, ics: int, **changes: object) -> hth4.Project:
    servos = tuple(
        dataclasses.replace(s, **changes) if s.in_use and s.device_number == ics else s
        for s in project.servos
    )
    return dataclasses.replace(project, servos=servos)


def _both_refuse(project: hth4.Project, error: type[Exception], *words: str) -> None:
    for build in (build_project_image, lambda p: project_image(p)[0]):
        with pytest.raises(error) as info:
            build(project)
        for w in words:
            assert w in str(info.value)


@pytest.mark.parametrize(
    ("changes", "words"),
    [
        ({"trim": 99999}, ("ICS 2", "Trim", "99999", "-32768..32767")),
        ({"position": -5}, ("ICS 2", "Position", "-5", "0..65535")),
        ({"id": 300}, ("ICS 2", "ID", "300", "0..255")),
        ({"mixing1_rate": 999}, ("ICS 2", "Mixing1Rate", "999", "-127..127")),
        ({"device_number": 99}, ("ICS 99", "DeviceNumber", "0..34")),
    ],
)
def test_a_servo_value_the_block_cannot_hold_names_the_servo_and_field(
    kxr_project: hth4.Project, changes: dict[str, object], words: tuple[str, ...]
) -> None:
    _both_refuse(_servo(kxr_project, 2, **changes), Hth4FormatError, *words)


def test_a_mixing_address_past_16_bits_is_refused_not_cut(kxr_project: hth4.Project) -> None:
    """Was masked: 70000 & 0xFFFF = 4464 in the image, and check said nothing."""
    bad = _servo(kxr_project, 2, mixing1_address=70000)
    _both_refuse(bad, Hth4FormatError, "ICS 2", "Mixing1Address", "70000")
    assert any(f.code == "build-error" and "Mixing1Address" in f.reason for f in check_project(bad))
    # 65535 (none) and -1 (the same 16 bits) still build
    build_project_image(_servo(kxr_project, 2, mixing1_address=-1))


def test_an_ics_number_configured_twice_names_it_and_both_servos(
    kxr_project: hth4.Project,
) -> None:
    other = next(s for s in kxr_project.servos if s.in_use and s.device_number == 2)
    bad = _servo(kxr_project, 3, device_number=2)
    _both_refuse(bad, Hth4FormatError, "ICS 2", "DeviceNumber", "configured once", other.key)


def test_settings_out_of_range_name_the_setting(kxr_project: hth4.Project) -> None:
    low = dataclasses.replace(
        kxr_project, low_power_motion_address=layout.motion_address(1), low_power_value=-5
    )
    _both_refuse(low, Hth4FormatError, "LowPowerValue", "-5", "0..65535")
    one = dataclasses.replace(kxr_project, config=b"\x01")
    _both_refuse(one, Hth4FormatError, "Config")


def test_a_motion_stored_elsewhere_is_a_layout_error_from_both(kxr_project: hth4.Project) -> None:
    motions = tuple(
        dataclasses.replace(m, address=m.address + 1) if m.slot == 1 else m
        for m in kxr_project.motions
    )
    _both_refuse(dataclasses.replace(kxr_project, motions=motions), LayoutError, "M001")


def _bad_checksum(project: hth4.Project) -> hth4.Project:
    def spoil(m: hth4.Motion) -> hth4.Motion:
        frames = list(m.frames)
        frames[1] = frames[1][:-1] + bytes([(frames[1][-1] + 1) & 0xFF])
        return dataclasses.replace(m, frames=tuple(frames))

    motions = tuple(spoil(m) if m.slot == 1 else m for m in project.motions)
    return dataclasses.replace(project, motions=motions)


def test_check_reports_a_bad_checksum_frame_instead_of_raising(kxr_project: hth4.Project) -> None:
    """Was: ChecksumError out of check_project (the linter crashed on what it reports)."""
    bad = _bad_checksum(kxr_project)
    findings = check_project(bad)
    invalid = [f for f in findings if f.code == "invalid-instruction"]
    assert invalid and invalid[0].slot == 1 and "checksum" in invalid[0].reason
    build = [f for f in findings if f.code == "build-error"]
    assert build and "M001" in build[0].reason and "checksum" in build[0].reason
    _both_refuse(bad, Hth4FormatError, "M001", "MotionData", "frame 2", "checksum")


@pytest.mark.parametrize("field", ["startup_motion_address", "low_power_motion_address"])
def test_check_reports_a_setting_address_past_24_bits(
    kxr_project: hth4.Project, field: str
) -> None:
    """Was: a plain ValueError from the CALL operand while writing the finding."""
    bad = dataclasses.replace(kxr_project, **{field: 999999999})
    findings = check_project(bad)
    codes = {f.code for f in findings}
    assert {"build-error", "target-outside-rom"} <= codes
    (outside,) = [f for f in findings if f.code == "target-outside-rom"]
    assert "999999999" in outside.instruction


def test_a_long_title_is_logged_once_cut_not_whole(
    kxr_project: hth4.Project, caplog: pytest.LogCaptureFixture
) -> None:
    build_project_image(dataclasses.replace(kxr_project, project_title="x" * 5000))
    assert "5000 characters" in caplog.text and "x" * 100 not in caplog.text


@pytest.mark.parametrize(
    ("make", "words"),
    [
        (lambda: b"\xff" * layout.ROM_SIZE, ("not a HeartToHeart4 image", "erased")),
        (lambda: b"\x00" * layout.ROM_SIZE, ("not a HeartToHeart4 image", "zeroed")),
        (
            lambda: bytes(range(256)) * 2 + b"\xff" * (layout.ROM_SIZE - 512),
            ("not a HeartToHeart4", "erased ROM at 003F5h"),
        ),
    ],
)
def test_an_erased_rom_dump_says_it_is_not_an_image(
    make: Callable[[], bytes], words: tuple[str, ...]
) -> None:
    with pytest.raises(ProtocolError) as info:
        read_image(make())
    assert isinstance(info.value, FrameError)
    for w in words:
        assert w in str(info.value)


def test_a_dump_of_the_wrong_size_is_a_layout_error() -> None:
    with pytest.raises(LayoutError, match="262144 bytes, not 100"):
        read_image(b"\x00" * 100)


def test_a_slot_past_the_layout_is_a_layout_error_from_both(kxr_project: hth4.Project) -> None:
    motions = tuple(
        dataclasses.replace(m, number=999) if m.slot == 1 else m for m in kxr_project.motions
    )
    _both_refuse(dataclasses.replace(kxr_project, motions=motions), LayoutError, "1000")
