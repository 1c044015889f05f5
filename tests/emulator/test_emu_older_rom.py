"""Older-layout ROM images (main loop 003FDh, motions at 0BB8h): builder, parser, detection,
the emulator booting them, and ``rcb4hv emulate --layout`` end to end over a pty."""

from __future__ import annotations

import os
import subprocess
import time
from dataclasses import replace
from pathlib import Path

import pytest
import serial
from hypothesis import given, settings

from rcb4hv.client import Robot
from rcb4hv.emulator import Board, VirtualClock
from rcb4hv.errors import LayoutError
from rcb4hv.protocol import Return
from rcb4hv.rom import ImageDescription, Motion, default_description, default_image, layout
from rcb4hv.rom.layout import HTH4_22, LAYOUTS, MotionLayout
from rcb4hv.rom.older import (
    BOOT_TAIL,
    build_image_for,
    detect_image_layout,
    main_loop_layout,
    parse_image_for,
)
from tests.emulator.test_emu_older_clients import (
    KHR3HV_QUERY,
    KHR3HV_RESTORE,
    KHR3HV_STOP,
    khr3hv_motion,
)
from tests.emulator.test_emu_rom_image import descriptions
from tests.emulator.test_emu_server import run_cli

H = bytes.fromhex
OLDER = LAYOUTS["2.1"]


def test_layout_table_holds_the_established_numbers() -> None:
    for v in ("2.0", "2.1"):
        lay = LAYOUTS[v]
        assert (lay.motion_base, lay.motion_stride, lay.main_loop) == (3000, 2048, 0x03FD)
        assert lay.address(1) == 0x0BB8 and lay.address(2) == 0x13B8 and lay.older
    assert LAYOUTS["1.3"].address(2) == 0x0BB8 + 0x1300 and LAYOUTS["1.3"].motion_count == 50
    assert HTH4_22.startup_stub == layout.STARTUP_STUB and not HTH4_22.older
    assert OLDER.startup_stub == 0x0BB8 + 120 * 2048 and OLDER.version == "2.1"


def test_older_image_addresses_hold_the_documented_instructions() -> None:
    img = default_image(OLDER)
    assert img[: layout.ALL_HOME] == default_image(HTH4_22)[: layout.ALL_HOME]
    assert img[0x03F5:0x03FC] == H("07 0B 6A 05 00 00 81")  # JUMP 0056Ah
    assert img[0x03FC] == 0xFF
    assert img[0x03FD:0x0403] == H("09 00 02 00 00 00")  # main loop: system register write
    assert img[0x0406:0x040B] == H("07 0B 1E 04 00")  # JUMP over the PIO switches
    assert img[0x0563:0x0568] == H("07 0B FD 03 00")  # JUMP back to the main loop
    assert BOOT_TAIL == 0x056A and img[0x056A] == 79 and img[0x056B] == 0x10  # all home
    assert img[0x05B9:0x05BE] == H("07 0C B8 CB 03")  # CALL the stub after slot 120
    assert img[0x05C0:0x05C5] == H("07 0B FD 03 00")
    assert img[0x05C7 : layout.SYSTEM_REGISTER_IMAGE] == b"\xff" * (0x05DC - 0x05C7)
    assert img[0x0B80:0x0BB8] == b"\xff" * 0x38
    assert img[OLDER.startup_stub : OLDER.startup_stub + 3] == H("03 0D 10")
    assert img[layout.STARTUP_STUB : layout.STARTUP_STUB + 3] == b"\xff" * 3
    # data images where 2.2 keeps them (vector packages differ only by their targets)
    new = default_image(HTH4_22)
    assert img[0x05DC : layout.VECTOR_PACKAGE_IMAGES] == new[0x05DC:0x091B]
    assert img[layout.TITLE : layout.PRIORITY_IMAGES] == new[0x0A1B:0x0A3B]


def _fit(d: ImageDescription, lay: MotionLayout) -> ImageDescription:
    return replace(d, motions=tuple(m for m in d.motions if m.slot <= lay.motion_count))


@settings(max_examples=30)
@given(descriptions)
def test_build_parse_round_trip_in_older_layouts(desc: ImageDescription) -> None:
    for lay in (OLDER, LAYOUTS["1.3"]):
        d = _fit(desc, lay)
        image = build_image_for(d, lay)
        assert parse_image_for(image, lay) == d
        assert detect_image_layout(image) in (OLDER, LAYOUTS["1.3"])
        for m in d.motions:
            a = lay.address(m.slot)
            assert image[a : a + sum(map(len, m.frames))] == b"".join(m.frames)


def test_detection() -> None:
    for v in ("2.2", "2.1", "1.3"):
        assert detect_image_layout(default_image(LAYOUTS[v])) == LAYOUTS[v]
    assert detect_image_layout(b"\xff" * layout.ROM_SIZE) is None
    both = H("09 00 02 00 00 00 1B 80 A6")
    assert main_loop_layout(both, both) is None and main_loop_layout(both, b"\xff" * 9) == OLDER


def test_motions_that_do_not_fit_are_refused() -> None:
    d = ImageDescription(motions=(Motion(51, [Return()]),))
    with pytest.raises(LayoutError, match=r"1\.3 has 50 slots"):
        build_image_for(d, LAYOUTS["1.3"])
    with pytest.raises(LayoutError, match="no image builder"):
        build_image_for(d, replace(HTH4_22, motion_base=0x0C00))
    with pytest.raises(Exception, match="not an older image"):
        parse_image_for(default_image(HTH4_22), OLDER)


def test_emulator_boots_the_older_default_board() -> None:
    board = Board(clock=VirtualClock(), rom_image=default_image(OLDER))
    try:
        board.run_for(3.0)
        assert 0x03FD <= board.pc < BOOT_TAIL and board.ram[5] == 0
        assert board.system_register == default_description().system_register
        assert board.servo_state(2) is not None and board.servo_state(2).output == 7500
    finally:
        board.close()


def _pty(proc: subprocess.Popen[str]) -> str:
    assert proc.stdout is not None
    kind, path = proc.stdout.readline().strip().split(" ", 1)
    assert kind == "PTY" and os.path.exists(path)
    return path


def _x(port: serial.Serial, frame: bytes, n: int) -> bytes:
    port.write(frame)
    reply = port.read(n)
    assert len(reply) == n, (frame.hex(" "), reply.hex(" "))
    return reply


def test_emulate_layout_2_1_serves_both_older_and_new_clients(tmp_path: Path) -> None:
    rom = tmp_path / "older.rom"
    proc = run_cli("--pty", "--layout", "2.1", "--rom", str(rom))
    try:
        path = _pty(proc)
        with Robot.open(path, timeout=2.0) as robot:
            robot.wait_ready()
            assert robot.layout == OLDER  # read from the board's ROM
            robot.play_motion(2, wait=True, timeout=10.0)
            assert robot.motion_status().pc < OLDER.motion_base
        port = serial.Serial(path, 115200, parity="E", timeout=2)
        try:  # python-khr3hv's play_motion(0), frame by frame over the pty
            assert _x(port, KHR3HV_STOP, 4) == H("04 00 06 0A")
            assert _x(port, khr3hv_motion(0), 4) == H("04 0C 06 16")
            assert _x(port, KHR3HV_RESTORE, 4) == H("04 00 06 0A")
            polls, t0 = 0, time.monotonic()
            while _x(port, KHR3HV_QUERY, 5)[2] == 0x23:
                polls += 1
                assert time.monotonic() - t0 < 10
                time.sleep(0.05)
            # the motion took its time (0.6 s at 15 ms periods or more, real time: the
            # emulator serves it on its real clock), however few polls a loaded machine made
            assert polls >= 1 and time.monotonic() - t0 >= 0.5
        finally:
            port.close()
    finally:
        proc.terminate()
        _, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err
    assert detect_image_layout(rom.read_bytes()) == OLDER
    proc = run_cli("--pty", "--rom", str(rom))  # the stored older image, no --layout
    try:
        with Robot.open(_pty(proc), timeout=2.0) as robot:
            assert robot.layout == OLDER
            assert robot.system_register().rom_run
    finally:
        proc.terminate()
        proc.communicate(timeout=10)
    assert proc.returncode == 0
