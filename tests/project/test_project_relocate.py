"""Older HeartToHeart4 layouts: detecting a project's layout, moving its motions, building,
reading back and simulating the older image, and the CLI."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv import hth4
from rcb4hv.cli.main import cli
from rcb4hv.errors import LayoutError
from rcb4hv.project.image import build_project_image, read_image, split_frames
from rcb4hv.project.relocate import (
    image_layout,
    move_address,
    project_image,
    project_layout,
    relocate_project,
)
from rcb4hv.project.run import run_motions
from rcb4hv.project.simulate import Simulator
from rcb4hv.protocol import Op
from rcb4hv.rom.layout import HTH4_22, LAYOUTS

OLDER = LAYOUTS["2.1"]


@pytest.fixture(scope="module")
def older_project(kxr_project: hth4.Project) -> hth4.Project:
    return relocate_project(kxr_project, OLDER)


def _branches(p: hth4.Project) -> list[tuple[int, int, int]]:
    """(slot, opcode, target) of every JUMP/CALL in the project's motions."""
    out = []
    for m in p.used_motions:
        for entry in m.frames:
            for f in split_frames(entry)[0]:
                if len(f) == 7 and f[1] in (Op.JUMP, Op.CALL):
                    out.append((m.slot, f[1], int.from_bytes(f[2:5], "little")))
    return out


def test_fixture_is_a_2_2_project_and_moves_to_2_1(
    kxr_project: hth4.Project, older_project: hth4.Project
) -> None:
    assert project_layout(kxr_project) == HTH4_22
    assert project_layout(older_project) == OLDER
    assert [m.address for m in older_project.used_motions] == [
        0x0BB8 + 0x800 * (m.slot - 1) for m in older_project.used_motions
    ]
    assert older_project.startup_motion_address == kxr_project.startup_motion_address + 0x38
    before, after = _branches(kxr_project), _branches(older_project)
    assert len(before) == len(after) > 50
    for (slot, op, old), (slot2, op2, new) in zip(before, after, strict=True):
        assert (slot, op) == (slot2, op2)
        assert new == old if old == 0xFFFFFF else new == old + 0x38
        assert OLDER.motion_at(new) == HTH4_22.motion_at(old) or old == 0xFFFFFF
    # only branch address bytes and their checksums changed
    for a, b in zip(kxr_project.used_motions, older_project.used_motions, strict=True):
        assert len(a.rom_bytes()) == len(b.rom_bytes())
        diff = [
            i for i, (x, y) in enumerate(zip(a.rom_bytes(), b.rom_bytes(), strict=True)) if x != y
        ]
        assert len(diff) <= 4 * len([t for t in _branches(kxr_project) if t[0] == a.slot])


def test_relocation_round_trips_through_the_file_and_back(
    kxr_project: hth4.Project, older_project: hth4.Project
) -> None:
    data = hth4.dump_project(older_project)
    again = hth4.parse_project(data)
    assert again == older_project and hth4.dump_project(again) == data
    assert project_layout(again) == OLDER
    back = relocate_project(again, HTH4_22)
    assert back == kxr_project
    assert hth4.dump_project(back) == hth4.dump_project(kxr_project)


def test_older_image_builds_reads_back_and_is_detected(older_project: hth4.Project) -> None:
    image, lay = project_image(older_project)
    assert lay == OLDER and image_layout(image) == OLDER
    assert image[0x03FD:0x0403] == bytes.fromhex("09 00 02 00 00 00")  # main loop 03FDh
    assert image[0x0B80:0x0BB8] == b"\xff" * 0x38
    contents = read_image(image, OLDER)
    assert [m.slot for m in contents.motions] == [m.slot for m in older_project.used_motions]
    for slot, m in zip(contents.motions, older_project.used_motions, strict=True):
        assert slot.address == m.address
        assert slot.rom_bytes() == b"".join(split_frames(m.rom_bytes())[0])
    assert contents.startup_motion_address == older_project.startup_motion_address
    assert contents.description.system_register == older_project.system_register


def test_2_2_project_built_for_2_1_on_request(
    kxr_project: hth4.Project, older_project: hth4.Project
) -> None:
    image, lay = project_image(kxr_project, "2.1")
    assert lay == OLDER
    assert image == build_project_image(older_project, OLDER)


def test_older_image_simulates_like_the_2_2_image(
    kxr_project: hth4.Project, older_project: hth4.Project, kxr_image: bytes
) -> None:
    slots = [(m.slot, m.name or "") for m in kxr_project.used_motions]
    old_image = build_project_image(older_project, OLDER)
    assert Simulator(old_image).layout == OLDER and Simulator(kxr_image).layout == HTH4_22
    old, new = (run_motions(i, [s for s, _ in slots], limit=30.0) for i in (old_image, kxr_image))
    assert old.boot.status == new.boot.status == "completed"
    a, b = old.results, new.results
    assert [(r.status, r.duration, r.instructions) for r in a] == [
        (r.status, r.duration, r.instructions) for r in b
    ]
    assert sum(r.status == "completed" for r in a) == 64
    assert [r.address for r in a] == [OLDER.address(s) for s, _ in slots]


def test_moves_that_cannot_be_made_are_refused(kxr_project: hth4.Project) -> None:
    with pytest.raises(LayoutError, match=r"M051 .*only 50 motion slots"):
        relocate_project(kxr_project, LAYOUTS["1.3"])
    m = kxr_project.used_motions[0]
    boot_call = bytes.fromhex("07 0C F5 03 00 00")
    frame = boot_call + bytes([sum(boot_call) & 0xFF])
    bad = replace(kxr_project, motions=(replace(m, frames=(frame, *m.frames)),))
    with pytest.raises(LayoutError, match=r"frame 1: CALL 003F5h .* cannot be moved"):
        relocate_project(bad, OLDER)
    with pytest.raises(LayoutError, match="startup motion 003F5h"):
        relocate_project(replace(kxr_project, startup_motion_address=0x3F5), OLDER)
    assert move_address(0x044B, HTH4_22, OLDER) == 0x03FD
    assert move_address(0x3CB80, HTH4_22, OLDER) == OLDER.startup_stub
    assert move_address(0x0B80 + 0x7FF, HTH4_22, LAYOUTS["1.3"]) == 0x0BB8 + 0x7FF
    assert move_address(0x0BB8 + 0x1000, LAYOUTS["1.3"], HTH4_22) is None  # offset past 2048


def test_a_project_whose_addresses_fit_no_layout_is_refused(kxr_project: hth4.Project) -> None:
    a, b = kxr_project.used_motions[:2]
    odd = replace(kxr_project, motions=(replace(a, address=a.address + 8), b))
    with pytest.raises(LayoutError, match=r"M001 \(slot 1\) is stored for 00B88h"):
        project_layout(odd)
    mixed = replace(kxr_project, motions=(replace(a, address=0x0BB8), b))
    with pytest.raises(LayoutError, match=r"M001 fits 2\.1/1\.3; M002 fits 2\.2"):
        project_layout(mixed)
    assert project_layout(replace(kxr_project, motions=())) == HTH4_22
    with pytest.raises(LayoutError, match=r"unknown HeartToHeart4 layout '3\.0'"):
        project_image(kxr_project, "3.0")


def test_cli_builds_and_simulates_an_older_project(
    older_project: hth4.Project, tmp_path: Path
) -> None:
    h4p = tmp_path / "older.h4p"
    hth4.save_project(older_project, h4p)
    out = tmp_path / "older.bin"
    r = CliRunner().invoke(cli, ["project", "build", str(h4p), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert "HeartToHeart4 2.1 layout" in r.output
    assert out.read_bytes() == build_project_image(older_project, OLDER)
    r = CliRunner().invoke(cli, ["project", "simulate", str(h4p), "--motion", "1", "--json"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    assert data["boot"]["status"] == "completed"
    assert data["motions"][0]["status"] == "completed"
    assert data["motions"][0]["address"] == "00BB8"
    r = CliRunner().invoke(cli, ["project", "simulate", str(out), "--motion", "2", "--json"])
    assert r.exit_code == 0 and json.loads(r.output)["motions"][0]["address"] == "013B8"
    r = CliRunner().invoke(cli, ["project", "image", str(out), "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.output)["motions"][0]["address"] == "00BB8"


def test_cli_moves_a_2_2_project_on_request(kxr_project_path: Path, tmp_path: Path) -> None:
    out = tmp_path / "moved.bin"
    r = CliRunner().invoke(
        cli, ["project", "build", str(kxr_project_path), "-o", str(out), "--layout", "2.1"]
    )
    assert r.exit_code == 0, r.output
    assert image_layout(out.read_bytes()) == OLDER
    r = CliRunner().invoke(
        cli, ["project", "build", str(kxr_project_path), "-o", str(out), "--layout", "1.3"]
    )
    assert r.exit_code != 0
    assert "HeartToHeart4 1.3 has only 50 motion slots" in r.output, r.output


def test_a_slot_past_the_layout_is_named_before_a_jump_into_it(
    kxr_project: hth4.Project,
) -> None:
    """Moving the fixture to 1.3 named a JUMP of motion 49 into slot 56 ("JUMP 1C380h targets
    no motion slot ... that HeartToHeart4 1.3 has") instead of the slots 1.3 lacks."""
    assert max(m.slot for m in kxr_project.used_motions) > 50
    with pytest.raises(LayoutError) as e:
        relocate_project(kxr_project, LAYOUTS["1.3"])
    assert "HeartToHeart4 1.3 has only 50 motion slots" in str(e.value)
    assert "JUMP" not in str(e.value) and "cannot be moved" not in str(e.value)
    with pytest.raises(LayoutError, match="only 50 motion slots"):
        project_image(kxr_project, "1.3")


def test_a_1_3_motion_longer_than_a_2_2_slot_is_not_cut_in_silence(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """A HeartToHeart4 1.3 slot spans 4864 bytes; the reader keeps a motion's first 2048 (the
    2.2 slot it is read into) and says so, where it cut the rest without a word."""
    from rcb4hv.rom.default import default_image
    from rcb4hv.rom.older import parse_image_for

    lay = LAYOUTS["1.3"]
    rom = bytearray(default_image(lay))
    move = bytes.fromhex("07 0F 02 1E 4C 1D 9F")
    body = move * 300 + bytes.fromhex("03 0D 10")  # 2103 bytes
    rom[lay.address(1) : lay.address(1) + len(body)] = body
    with caplog.at_level("WARNING", logger="rcb4hv.rom.older"):
        parse_image_for(bytes(rom), lay)
    assert "motion 1 of this HeartToHeart4 1.3 image is longer than the 2048 bytes" in caplog.text
    caplog.clear()
    short = move * 10 + bytes.fromhex("03 0D 10")
    rom[lay.address(1) : lay.address(1) + len(body)] = short.ljust(len(body), b"\xff")
    with caplog.at_level("WARNING", logger="rcb4hv.rom.older"):
        parse_image_for(bytes(rom), lay)
    assert "longer than" not in caplog.text
