"""Real-project quirks written into the fixture's XML: each builds, simulates and shows in info.

Quirks: SetStretch values of 0, priority checks with ``Address`` -1, ``LowPowerMotionAddress``
-1 or set, a startup motion in an empty slot (see ``rcb4hv.project.options``).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.project.image import build_project_image, read_image
from rcb4hv.project.options import BuildOptions
from rcb4hv.project.run import run_motions
from rcb4hv.project.simulate import Simulator
from rcb4hv.protocol import (
    ALWAYS,
    SYS,
    Call,
    Condition,
    Data,
    Ics,
    Jump,
    Move,
    Ram,
    Return,
    SetStretch,
    Sub,
    decode_command,
    encode_command,
    frame_at,
)
from rcb4hv.protocol.memory import ADDR, SERVO
from rcb4hv.rom import layout
from tests.project.quirks import (
    EMPTY_ADDRESS,
    edit_frame,
    fixture_xml,
    frames_at,
    load,
    motion_frames,
    set_motion_frames,
    set_priority_address,
    set_setting,
)

BATTERY_MOTION = 82816  # slot 40, the fixture's low-battery priority motion


@pytest.fixture(scope="module")
def xml(kxr_project_path: Path) -> str:
    return fixture_xml(kxr_project_path)


def _write(tmp_path: Path, xml: str) -> Path:
    path = tmp_path / "quirk.h4p"
    path.write_bytes(xml.encode("utf-8"))
    return path


def _board(image: bytes) -> Board:
    ics = [n for n in range(35) if image[layout.ALLOC_IMAGE + 2 * n] != 0xFF]
    board = Board(EmulatorConfig(virtual_servos=tuple(ics)), clock=VirtualClock(), rom_image=image)
    board.run_for(4.0)
    return board


def test_stretch_zero_builds_decodes_and_plays(xml: str) -> None:
    frames = motion_frames(xml, 39)
    assert frames[0].startswith("1B 12")  # SetStretch; ICS 18 and 19 are its last two values
    frames[0] = edit_frame(frames[0], b24=0, b25=0)
    project = load(set_motion_frames(xml, 39, frames))
    image = build_project_image(project)
    cmd = decode_command(frame_at(image, layout.motion_address(39)))
    assert isinstance(cmd, SetStretch) and dict(cmd.values)[18] == 0
    sim = Simulator(image)
    assert sim.boot().status == "completed"  # the startup motion is slot 39 itself
    assert sim.board.stretch[18] == 0 and sim.board.stretch[2] == 0x14
    result = sim.play(layout.motion_address(39), name="home")
    assert result.status == "completed", result


def test_priority_address_minus_one_is_none(xml: str) -> None:
    quirk = set_priority_address(xml, 0, -1)
    project = load(quirk)
    ((index, pm),) = project.active_priority_motions
    assert (index, pm.address, pm.port) == (0, -1, "Battery")
    stub = build_project_image(project)
    assert read_image(stub).priority[0]["address"] == layout.STARTUP_STUB
    skip = build_project_image(project, options=BuildOptions(priority_none="skip"))
    assert read_image(skip).priority == {}
    # low battery: the configured check fires and calls nothing; the original calls slot 40
    for image, depth in ((stub, 0), (skip, 0), (build_project_image(load(xml)), 1)):
        board = _board(image)
        board.set_ad_input(0, 100)  # about 2.4 V: below the check's 223
        board.run_for(0.5)
        assert board.system_register & SYS.ROM_RUN
        assert not board.system_register & SYS.ROM_ERROR
        assert board.ram[5] == depth


def test_low_power_motion_minus_one_and_set(xml: str) -> None:
    project = load(xml)
    assert project.low_power_motion_address == -1
    assert list(read_image(build_project_image(project)).priority) == [0]
    quirk = set_setting(
        set_setting(xml, "LowPowerMotionAddress", BATTERY_MOTION), "LowPowerValue", 200
    )
    checks = read_image(build_project_image(load(quirk))).priority
    assert checks[1] == {
        "port": "Battery",
        "compare_type": "LessThan",
        "value": 201,
        "address": BATTERY_MOTION,
    }


def test_startup_in_empty_slot_boot_fails_and_motions_still_play(xml: str) -> None:
    project = load(set_setting(xml, "StartupMotionAddress", EMPTY_ADDRESS))
    image = build_project_image(project)
    call = decode_command(frame_at(image, layout.STARTUP_CALL))
    assert call == Call(EMPTY_ADDRESS)
    sim = Simulator(image)
    boot = sim.boot()
    assert boot.status == "error"
    assert boot.error is not None
    assert boot.error.startswith("startup motion 09380h: slot 18 holds no motion; ROMERR")
    assert boot.pc == EMPTY_ADDRESS
    results = run_motions(image, (39, 9)).results
    assert [r.status for r in results] == ["completed", "completed"]
    stubbed = build_project_image(project, options=BuildOptions(empty_startup="stub"))
    assert decode_command(frame_at(stubbed, layout.STARTUP_CALL)) == Call(layout.STARTUP_STUB)
    assert Simulator(stubbed).boot().status == "completed"


def test_simulate_cli_reports_the_boot_cause_and_keeps_going(xml: str, tmp_path: Path) -> None:
    path = _write(tmp_path, set_setting(xml, "StartupMotionAddress", EMPTY_ADDRESS))
    r = CliRunner().invoke(cli, ["project", "simulate", str(path), "--motion", "39", "--json"])
    assert r.exit_code == 1, r.output  # documented: 1 on any error, the boot included
    data = json.loads(r.output)
    assert data["boot"]["status"] == "error"
    assert "startup motion 09380h: slot 18 holds no motion" in data["boot"]["error"]
    assert [m["status"] for m in data["motions"]] == ["completed"]
    text = CliRunner().invoke(cli, ["project", "simulate", str(path), "--motion", "39"])
    assert "boot: error" in text.output and "slot 18 holds no motion" in text.output
    assert "1 motions: 1 completed" in text.output
    ok = CliRunner().invoke(
        cli, ["project", "simulate", str(path), "--motion", "39", "--empty-startup", "stub"]
    )
    assert ok.exit_code == 0, ok.output
    assert "boot: completed" in ok.output


def test_build_cli_takes_the_none_options(xml: str, tmp_path: Path) -> None:
    path = _write(tmp_path, set_priority_address(xml, 0, -1))
    out = tmp_path / "image.bin"
    r = CliRunner().invoke(cli, ["project", "build", str(path), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert read_image(out.read_bytes()).priority[0]["address"] == layout.STARTUP_STUB
    r = CliRunner().invoke(
        cli, ["project", "build", str(path), "-o", str(out), "--priority-none", "skip"]
    )
    assert r.exit_code == 0, r.output
    assert read_image(out.read_bytes()).priority == {}


def test_info_shows_none_settings(xml: str, tmp_path: Path) -> None:
    quirk = set_setting(set_priority_address(xml, 0, -1), "StartupMotionAddress", -1)
    path = _write(tmp_path, quirk)
    r = CliRunner().invoke(cli, ["project", "info", str(path)])
    assert r.exit_code == 0, r.output
    assert "startup motion: none" in r.output
    assert "low-power motion: none" in r.output
    assert "priority check 0: Battery LessThanOrEqualTo 223 -> none" in r.output
    data = json.loads(CliRunner().invoke(cli, ["project", "info", str(path), "--json"]).output)
    settings = data["settings"]
    assert settings["startup_motion"] is None and settings["low_power_motion"] is None
    assert settings["priority_motions"][0]["address"] is None
    empty = _write(tmp_path, set_setting(xml, "StartupMotionAddress", EMPTY_ADDRESS))
    r = CliRunner().invoke(cli, ["project", "info", str(empty)])
    assert "startup motion: 09380h (slot 18 holds no motion)" in r.output
    r = CliRunner().invoke(cli, ["project", "info", str(_write(tmp_path, xml))])
    assert "startup motion: 13B80h (slot 39, XL2G_291_" in r.output
    assert "priority check 0: Battery LessThanOrEqualTo 223 -> 14380h (slot 40, XL2G_292_" in (
        r.output
    )


def test_boot_failure_inside_the_startup_motion_names_it(xml: str) -> None:
    frames = motion_frames(xml, 39)
    frames.insert(1, encode_command(Move(Ram(0x0462), Ics(4, 30), 2)).hex(" ").upper())
    image = build_project_image(load(set_motion_frames(xml, 39, frames)))
    sim = Simulator(image)
    boot = sim.boot()
    assert boot.status == "error"
    assert boot.error == "startup motion 13B80h (slot 39): command error: ICS 30 is not allocated"
    assert boot.instruction == "MOVE RAM[VAR[0]], ICS[30].MEASURED, 2"
    assert sim.play(layout.motion_address(9)).status == "completed"


# --------------------------------------------------------------- the last real projects' loops

HOLD_SLOT = 2  # replaced by each pattern below; the fixture's motion 2 is a short walk


def _replace_motion(xml: str, commands: list[object]) -> bytes:
    frames = frames_at(layout.motion_address(HOLD_SLOT), commands)
    return build_project_image(load(set_motion_frames(xml, HOLD_SLOT, frames)))


def test_gyro_mixed_hold_loop_is_holding(xml: str, tmp_path: Path) -> None:
    """The wheeled KXR balance projects: a pose, then an endless loop that (re)sets servo
    mixing from the gyro's AD channel and reads nothing itself; the board balances through
    the mixing every output period."""
    pose = motion_frames(xml, HOLD_SLOT)[1]
    gyro = ADDR.AD_VALUES + 2 * 1  # AD1
    loop = [
        pose,
        Move(Ics(SERVO.MIX1_SOURCE, 2), Data(gyro.to_bytes(2, "little"))),
        Move(Ics(SERVO.MIX1_METHOD, 2), Data(b"\x05")),  # + 5 x AD1
        lambda at: Jump(at[1], ALWAYS),
    ]
    image = _replace_motion(xml, loop)
    sim = Simulator(image)
    assert sim.boot().status == "completed"
    r = sim.play(layout.motion_address(HOLD_SLOT))
    assert r.status == "holding", r
    assert r.inputs == ("AD1",) and r.ok
    assert "servos mixed from AD1" in r.detail
    # the same loop without the mixing is an endless loop: stalled
    r = Simulator(_replace_motion(xml, [pose, lambda at: Jump(at[1], ALWAYS)]))
    r.boot()
    assert r.play(layout.motion_address(HOLD_SLOT)).status == "stalled"
    # and the command line says holding and exits 0
    path = _write(
        tmp_path,
        set_motion_frames(xml, HOLD_SLOT, frames_at(layout.motion_address(HOLD_SLOT), loop)),
    )
    res = CliRunner().invoke(cli, ["project", "simulate", str(path), "--motion", "2"])
    assert res.exit_code == 0, res.output
    assert "holding" in res.output and "servos mixed from AD1" in res.output


def test_long_counted_loop_finishes_past_the_old_limit(xml: str, tmp_path: Path) -> None:
    """The KHR-3HV project: a counter counted down from 256, two poses per pass: 77 s of
    virtual time, past the fixed 60 s of the old default limit, and it completes."""
    frames = motion_frames(xml, HOLD_SLOT)
    speed = 10  # output periods per pose: 150 ms at the fixture's 15 ms period
    there, back = (edit_frame(f, b7=speed) for f in frames[1:3])
    var = ADDR.user_variable(0)
    loop = [
        Move(Ram(var), Data((256).to_bytes(2, "little"))),
        there,
        back,
        Sub(Ram(var), Data(b"\x01\x00")),
        lambda at: Jump(at[1], Condition.if_not_zero()),
        Return(),
    ]
    image = _replace_motion(xml, loop)
    sim = Simulator(image)
    assert sim.boot().status == "completed"
    t0 = time.perf_counter()
    r = sim.play(layout.motion_address(HOLD_SLOT))
    took = time.perf_counter() - t0
    assert r.status == "completed", r
    assert 256 * 2 * speed * 0.015 <= r.duration < 256 * 2 * (speed + 1) * 0.015 + 1
    assert took < 30  # virtual time is cheap (about a second here)
    # an explicit limit is still a hard one
    sim2 = Simulator(image)
    sim2.boot()
    assert sim2.play(layout.motion_address(HOLD_SLOT), limit=60.0).status == "timeout"
    path = _write(
        tmp_path,
        set_motion_frames(xml, HOLD_SLOT, frames_at(layout.motion_address(HOLD_SLOT), loop)),
    )
    res = CliRunner().invoke(cli, ["project", "simulate", str(path), "--motion", "2"])
    assert res.exit_code == 0, res.output
    assert "1 completed" in res.output
