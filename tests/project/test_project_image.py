"""Project -> ROM image -> project data: layout, round trip, boot in the emulator."""

from __future__ import annotations

from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import hth4
from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.errors import ChecksumError
from rcb4hv.project.image import (
    COMPARE,
    _vector_package,
    build_project_image,
    motion_image_frames,
    project_description,
    read_image,
    split_frames,
)
from rcb4hv.project.imageread import _package_compare
from rcb4hv.protocol import ADDR, ALWAYS, Call, decode_command
from rcb4hv.rom import default_image, layout

ROMERR = 0x0400


def test_image_layout(kxr_project: hth4.Project, kxr_image: bytes) -> None:
    assert len(kxr_image) == layout.ROM_SIZE
    assert kxr_image[layout.SYSTEM_REGISTER_IMAGE : layout.SYSTEM_REGISTER_IMAGE + 2] == bytes(
        (0x1B, 0x82)
    )
    assert kxr_image[layout.AD_REFERENCE_IMAGE : layout.AD_REFERENCE_IMAGE + 22] == (
        kxr_project.adc_reference
    )
    # startup motion CALL (M039 at 13B80h)
    call = decode_command(kxr_image[layout.STARTUP_CALL : layout.STARTUP_CALL + 7])
    assert call == Call(kxr_project.startup_motion_address, ALWAYS)
    assert kxr_project.startup_motion_address == 0x13B80
    for m in kxr_project.used_motions:
        data = m.rom_bytes()
        assert data.endswith(b"\x03\x0d\x10\xff")
        assert kxr_image[m.address : m.address + len(data)] == data, m.key
        # nothing after the motion's own bytes inside its slot
        end = layout.motion_address(m.slot) + layout.MOTION_SIZE
        assert set(kxr_image[m.address + len(data) : end]) == {0xFF}


def test_title_and_vector_packages(kxr_project: hth4.Project, kxr_image: bytes) -> None:
    assert kxr_image[layout.TITLE : layout.TITLE + 8] == b"HAC-KXR\x00"
    bound = [m for m in kxr_project.used_motions if m.button_data]
    desc = project_description(kxr_project)
    assert len(desc.vector_packages) == len(bound) > 0
    walk = next(m for m in bound if m.button_data == 0x0001)
    pkg_at = layout.VECTOR_PACKAGE_IMAGES + 8 * bound.index(walk)
    # CALL if equal (CE=0, ZE=1, Z=1, literal word), RAM 0350 == 00 01, target = motion
    assert kxr_image[pkg_at : pkg_at + 8] == bytes(
        [0x35, 0x50, 0x03, 0x00, 0x01]
    ) + walk.address.to_bytes(3, "little")


def test_image_round_trip(kxr_project: hth4.Project, kxr_image: bytes) -> None:
    c = read_image(kxr_image)
    assert c.config == kxr_project.config
    assert c.adc_reference == kxr_project.adc_reference
    assert c.title == kxr_project.project_title
    assert c.startup_motion_address == kxr_project.startup_motion_address
    used = {m.slot: m for m in kxr_project.used_motions}
    assert [m.slot for m in c.motions] == sorted(used)
    for slot, pm in used.items():
        im = c.motion(slot)
        assert im.address == pm.address
        assert list(im.frames) == motion_image_frames(pm.frames)
        assert im.rom_bytes() + b"\xff" == pm.rom_bytes()
        assert im.startup == (pm.address == kxr_project.startup_motion_address)
        if pm.button_data:
            assert [(b.buttons, b.compare_type) for b in im.bindings] == [
                (pm.button_data, pm.compare_type)
            ]
        else:
            assert im.bindings == ()
    servos = {s.device_number: s for s in kxr_project.servos if s.in_use}
    assert sorted(c.servos) == sorted(servos)
    for ics, s in servos.items():
        got = c.servos[ics]
        assert (got["id"], got["trim"], got["home"]) == (s.id, s.trim, s.position)
        assert (got["mixing1_address"], got["mixing1_rate"]) == (s.mixing1_address, s.mixing1_rate)
        assert (got["mixing2_address"], got["mixing2_rate"]) == (s.mixing2_address, s.mixing2_rate)
    # battery check: AD0 <= 223 is stored as AD0 < 224 (the board has only Z and C)
    ((index, battery),) = kxr_project.active_priority_motions
    assert c.priority == {
        index: {
            "port": "Battery",
            "compare_type": "LessThan",
            "value": battery.value + 1,
            "address": battery.address,
        }
    }
    assert c.motion(layout.motion_number(battery.address) or 0).priority == (index,)


def _boot(image: bytes, ics: tuple[int, ...], seconds: float = 8.0) -> Board:
    board = Board(EmulatorConfig(virtual_servos=ics), clock=VirtualClock(), rom_image=image)
    board.run_for(seconds)
    return board


def test_fixture_image_boots_and_matches_servo_config(
    kxr_project: hth4.Project, kxr_image: bytes
) -> None:
    used = tuple(s.device_number for s in kxr_project.servos if s.in_use)
    board = _boot(kxr_image, used)
    sysreg = board.system_register
    assert not sysreg & ROMERR and sysreg & 0x0002
    assert layout.MAIN_LOOP <= board.pc < layout.MAIN_LOOP_JUMP + 7
    assert board.call_stack == []
    for s in kxr_project.servos:
        ics = s.device_number
        if not s.in_use:
            assert board.alloc(ics) == 0xFFFF
            continue
        blk = board.alloc(ics)
        assert blk == 0x0090 + 20 * ics == s.ram_address
        assert board.ram[blk] == 0 and board.ram[blk + 1] == s.id
        base = int.from_bytes(board.ram[blk + 2 : blk + 4], "little", signed=True)
        assert base == s.trim
        mix1 = int.from_bytes(board.ram[blk + 14 : blk + 16], "little")
        assert mix1 == s.mixing1_address
    assert board.alloc(35) == 0x034C  # KRI-3 receiver
    assert board.ram[0x034C:0x034E] == bytes((1, 31))
    assert int.from_bytes(board.ram[0x008C:0x008E], "little") == ADDR.VECTOR_PACKAGES


def test_default_image_boots_without_romerr() -> None:
    image = default_image()
    board = _boot(image, (0, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19))
    assert not board.system_register & ROMERR and board.system_register & 0x0002
    c = read_image(image)
    assert [m.slot for m in c.motions] == [1, 2]
    assert {b.button_names for b in c.bindings} == {"TRIANGLE", "CIRCLE"}


BUTTON_WORDS = st.integers(1, 0xFFFF)


@settings(max_examples=200)
@given(BUTTON_WORDS, st.sampled_from(sorted(COMPARE)), st.integers(0, 0xFFFF))
def test_vector_package_compares_like_compare_type(value: int, compare: str, word: int) -> None:
    """The package fires (firmware rule of spec 11.3) exactly when ``word <compare> value``."""
    pkg = _vector_package(value, compare, 0x0B80)

    def to_raw(w: int) -> int:
        return int.from_bytes(w.to_bytes(2, "big"), "little")

    diff = to_raw(word) - pkg.source
    z, c = diff == 0, diff >= 0
    fires = (not pkg.compare_z or z == pkg.z) and (not pkg.compare_c or c == pkg.c)
    a, b = to_raw(word), to_raw(value)
    expected = {
        "Equals": a == b,
        "NotEquals": a != b,
        "LessThan": a < b,
        "LessThanOrEqualTo": a <= b,
        "GreaterThan": a > b,
        "GreaterThanOrEqualTo": a >= b,
    }[compare]
    assert fires == expected
    back = _package_compare(pkg)
    assert back is not None
    if compare != "LessThanOrEqualTo":
        assert back == (compare, value)


def test_split_frames() -> None:
    call = bytes.fromhex("070C800B00009E")
    frames, tail = split_frames(b"\x03\x0d\x10" + call + b"\xff\xff")
    assert frames == [b"\x03\x0d\x10", call]
    assert tail == b"\xff\xff"
    with pytest.raises(ChecksumError):
        split_frames(b"\x03\x0d\x11")
    assert motion_image_frames([b"\x03\x0d\x10\xff"]) == [b"\x03\x0d\x10"]
    with pytest.raises(ValueError, match="not a command frame"):
        motion_image_frames([b"\x03\x0d\x10\x01"])


def test_bad_projects_are_refused(kxr_project: hth4.Project) -> None:
    m = kxr_project.motion(1)
    moved = replace(m, address=m.address + 0x38)  # the 2.0/2.1 layout
    p = replace(kxr_project, motions=tuple(moved if x is m else x for x in kxr_project.motions))
    with pytest.raises(ValueError, match=r"HeartToHeart4 2\.2 layout"):
        build_project_image(p)
    odd = replace(m, button_data=1, compare_type="Sometimes")
    p = replace(kxr_project, motions=tuple(odd if x is m else x for x in kxr_project.motions))
    with pytest.raises(ValueError, match="CompareType"):
        build_project_image(p)
    big = replace(m, frames=m.frames * 4)
    p = replace(kxr_project, motions=tuple(big if x is m else x for x in kxr_project.motions))
    with pytest.raises(ValueError, match="2048"):
        build_project_image(p)
