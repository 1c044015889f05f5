"""``rcb4hv project check``: each finding, built from the fixture with its quirk in the XML."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.project.check import Finding, check_project
from rcb4hv.protocol import Ics, Jump, Move, Ram, encode_command
from rcb4hv.rom import layout
from tests.project.quirks import (
    EMPTY_ADDRESS,
    EMPTY_SLOT,
    edit_frame,
    fixture_xml,
    load,
    motion_frames,
    set_button,
    set_motion_frames,
    set_priority_address,
    set_setting,
    with_checksum,
)


@pytest.fixture(scope="module")
def xml(kxr_project_path: Path) -> str:
    return fixture_xml(kxr_project_path)


def _codes(findings: list[Finding]) -> set[str]:
    return {f.code for f in findings}


def _only(findings: list[Finding], code: str) -> Finding:
    (f,) = [f for f in findings if f.code == code]
    return f


def _new(xml: str, quirk: str) -> list[Finding]:
    """Findings of ``quirk`` that the unchanged fixture does not have."""
    before = {(f.code, f.address, f.reason) for f in check_project(load(xml))}
    return [f for f in check_project(load(quirk)) if (f.code, f.address, f.reason) not in before]


def test_fixture_has_warnings_only(xml: str) -> None:
    findings = check_project(load(xml))
    assert all(f.severity == "warning" for f in findings)
    assert _codes(findings) == {"position-out-of-range", "unreachable-code", "unknown-ics"}
    pos = next(f for f in findings if f.code == "position-out-of-range" and f.slot == 15)
    assert "ICS 4: 12700" in pos.reason and pos.instruction.startswith("SERVOS ")
    dead = next(f for f in findings if f.code == "unreachable-code" and f.slot == 3)
    assert dead.instruction == "JUMP $001B80" and dead.address == 0x1CA1
    assert dead.name == "XL2G_103_微細歩行左"
    head = next(f for f in findings if f.code == "unknown-ics" and f.slot == 2)
    assert head.reason.startswith("ICS 0, 1 not in the servo table but moved by 9 instructions")
    assert head.to_dict() == {
        "severity": "warning",
        "code": "unknown-ics",
        "slot": 2,
        "name": "XL2G_102_微細歩行後",
        "address": f"{head.address:05X}",
        "instruction": head.instruction,
        "reason": head.reason,
    }


def test_startup_in_empty_slot_is_an_error(xml: str) -> None:
    f = _only(
        _new(xml, set_setting(xml, "StartupMotionAddress", EMPTY_ADDRESS)), "target-empty-slot"
    )
    assert (f.severity, f.slot, f.address) == ("error", EMPTY_SLOT, EMPTY_ADDRESS)
    assert f.reason == "startup motion 09380h: slot 18 holds no motion"
    assert f.instruction == "CALL $009380"


def test_priority_and_low_power_targets(xml: str) -> None:
    f = _only(_new(xml, set_priority_address(xml, 0, -1)), "priority-without-motion")
    assert f.severity == "warning" and f.name == "XL2G_292_電圧低下"
    assert "priority check 0 (Battery LessThanOrEqualTo 223) has no motion" in f.reason
    f = _only(_new(xml, set_priority_address(xml, 0, EMPTY_ADDRESS)), "target-empty-slot")
    assert f.reason == "priority check 0 motion 09380h: slot 18 holds no motion"
    low = set_setting(xml, "LowPowerMotionAddress", EMPTY_ADDRESS)
    f = _only(_new(xml, low), "target-empty-slot")
    assert f.reason == "low-power motion 09380h: slot 18 holds no motion"
    mid = set_setting(xml, "StartupMotionAddress", layout.motion_address(39) + 27)
    f = _only(_new(xml, mid), "target-not-motion-start")
    assert f.severity == "warning" and f.slot == 39


def _with_jump(xml: str, target: int) -> str:
    frames = motion_frames(xml, 3)
    i = next(i for i, f in enumerate(frames) if f.startswith("07 0B"))
    frames[i] = encode_command(Jump(target)).hex(" ").upper()
    return set_motion_frames(xml, 3, frames)


@pytest.mark.parametrize(
    ("target", "code", "reason"),
    [
        (EMPTY_ADDRESS, "target-empty-slot", "JUMP target 09380h: slot 18 holds no motion"),
        (0xFFFFFF, "target-outside-rom", "JUMP target FFFFFFh: an unresolved flowchart target"),
        (0x1B81, "target-mid-instruction", "JUMP target 01B81h: lands inside an instruction"),
        (0x1CAC, "target-past-motion", "JUMP target 01CACh: lands after the end of slot 3"),
    ],
)
def test_jump_targets(xml: str, target: int, code: str, reason: str) -> None:
    f = _only(_new(xml, _with_jump(xml, target)), code)
    assert f.severity == "error" and f.slot == 3 and f.reason.startswith(reason)
    assert f.instruction == f"JUMP ${target:06X}"


def test_documented_ranges_are_warnings(xml: str) -> None:
    frames = motion_frames(xml, 39)
    frames[0] = edit_frame(frames[0], b24=0)  # SetStretch ICS 18: 0
    frames[1] = edit_frame(frames[1], b7=0)  # RunConstFrameServo speed 0
    findings = _new(xml, set_motion_frames(xml, 39, frames))
    assert all(f.severity == "warning" for f in findings)
    stretch = _only(findings, "stretch-out-of-range")
    assert stretch.reason == "stretch outside 1-127 (ICS 18: 0)" and stretch.slot == 39
    assert stretch.instruction.startswith("STRETCH 2=20")
    speed = _only(findings, "speed-zero")
    assert speed.instruction.startswith("SERVOS 0, 2=") and "speed 0 for ICS 2, 3" in speed.reason


def test_motion_without_final_return(xml: str) -> None:
    frames = motion_frames(xml, 39)[:2]  # drop both RETURNs
    f = _only(_new(xml, set_motion_frames(xml, 39, frames)), "no-final-return")
    assert f.severity == "error" and "runs past its last instruction" in f.reason


def test_unknown_ics_operand_and_invalid_instruction(xml: str) -> None:
    frames = motion_frames(xml, 39)
    read = encode_command(Move(Ram(0x0462), Ics(4, 30), 2)).hex(" ").upper()
    bad = with_checksum(bytes.fromhex("07 0B 80 B3 01 15"))  # reserved condition bits
    frames[1:1] = [read, bad]
    findings = _new(xml, set_motion_frames(xml, 39, frames))
    ics = next(f for f in findings if f.code == "unknown-ics" and f.severity == "error")
    assert ics.reason.startswith("ICS 30 not in the servo table: the program stops")
    invalid = _only(findings, "invalid-instruction")
    assert invalid.severity == "error" and "bits 7-4" in invalid.reason
    assert invalid.instruction.startswith(".byte 07 0B 80 B3 01 15")


def test_buttons(xml: str) -> None:
    f = _only(_new(xml, set_button(xml, 10, 1)), "button-bound-twice")  # UP, as slot 9
    assert f.slot == 10 and "also starts slot 9" in f.reason
    f = _only(_new(xml, set_button(xml, EMPTY_SLOT, 16)), "button-on-empty-slot")
    assert f.slot == EMPTY_SLOT and f.severity == "warning"


def test_check_cli_exit_status_and_json(xml: str, tmp_path: Path, kxr_project_path: Path) -> None:
    r = CliRunner().invoke(cli, ["project", "check", str(kxr_project_path)])
    assert r.exit_code == 0, r.output
    assert "HAC_KXR_HTH4_project.h4p: 0 errors, 77 warnings" in r.output
    bad = tmp_path / "bad.h4p"
    bad.write_bytes(set_setting(xml, "StartupMotionAddress", EMPTY_ADDRESS).encode("utf-8"))
    r = CliRunner().invoke(cli, ["project", "check", str(bad), "--json"])
    assert r.exit_code == 1, r.output
    data = json.loads(r.output)
    assert data["errors"] == 1 and data["warnings"] == 77
    first = data["findings"][0]
    assert first == {
        "severity": "error",
        "code": "target-empty-slot",
        "slot": 18,
        "name": "M018",  # HeartToHeart4's name for the empty slot
        "address": "09380",
        "instruction": "CALL $009380",
        "reason": "startup motion 09380h: slot 18 holds no motion",
    }
    r = CliRunner().invoke(cli, ["project", "check", str(bad)])
    assert r.exit_code == 1
    assert "slot 18 holds no motion [target-empty-slot]" in r.output


def test_older_layout_project_checks_like_its_22_original(xml: str) -> None:
    """A project stored for the 2.1 layout (motions at 0BB8h) is linted in its own layout: the
    same findings, moved with the motions, and no build error."""
    from rcb4hv.project.relocate import move_address, relocate_project
    from rcb4hv.rom.layout import HTH4_22, LAYOUTS

    project = load(xml)
    older = relocate_project(project, LAYOUTS["2.1"])
    now, then = check_project(project), check_project(older)
    assert "build-error" not in _codes(then)
    assert [(f.code, f.slot) for f in then] == [(f.code, f.slot) for f in now]
    assert [f.address for f in then] == [
        None if f.address is None else move_address(f.address, HTH4_22, LAYOUTS["2.1"]) for f in now
    ]
