"""The HeartToHeart4 2.2 image builder/parser, the default board, the persistent ROM."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.protocol import Button, Data, Move, Rom, RunSingleServo, encode_command
from rcb4hv.rom import (
    DEFAULT_ICS,
    ImageDescription,
    ImageMotion,
    ImagePriorityMotion,
    ImageServo,
    Kri3Config,
    VectorPackage,
    build_image,
    default_description,
    default_image,
    layout,
    parse_image,
)
from tests.emulator.conftest import x

servo = st.builds(
    ImageServo,
    ics=st.integers(0, 34),
    servo_id=st.integers(0, 17),
    trim=st.integers(-500, 500),
    home=st.integers(3500, 11500),
    mix1_source=st.sampled_from([0xFFFF, 0x4022, 0x8201]),
    mix1_method=st.integers(0, 255),
)
descriptions = st.builds(
    ImageDescription,
    system_register=st.integers(0, 0xFFFF),
    pio_direction=st.integers(0, 0x3FF),
    ad_references=st.tuples(*[st.integers(0, 1023)] * 11),
    servos=st.lists(servo, max_size=8, unique_by=lambda s: s.ics).map(tuple),
    kri3=st.one_of(st.none(), st.just(Kri3Config())),
    vector_packages=st.lists(
        st.builds(
            VectorPackage.button,
            st.sampled_from(list(Button)[1:]),
            st.integers(0x0B80, 0x3FFFF),
            jump=st.booleans(),
        ),
        max_size=4,
    ).map(tuple),
    title=st.text(alphabet="ABCxyz -_ロボ", max_size=12),
    startup_motion=st.one_of(st.none(), st.sampled_from([0x0B80, 0x1380])),
    priority_motions=st.lists(
        st.one_of(
            st.none(),
            st.builds(
                ImagePriorityMotion,
                source=st.just(0x22),
                compare=st.sampled_from(["eq", "ne", "lt", "le", "gt", "ge"]),
                value=st.integers(0, 1000),
                target=st.integers(0x0B80, 0x3FFFF),
            ),
        ),
        max_size=13,
    ).map(tuple),
    motions=st.lists(
        st.builds(
            ImageMotion,
            st.integers(1, 120),
            st.lists(
                st.builds(
                    RunSingleServo,
                    st.integers(0, 35),
                    st.integers(1, 255),
                    st.integers(3500, 11500),
                ),
                max_size=5,
            ),
        ),
        max_size=4,
        unique_by=lambda m: m.slot,
    ).map(tuple),
)


@settings(max_examples=40)
@given(descriptions)
def test_build_parse_round_trip(desc: ImageDescription) -> None:
    image = build_image(desc)
    assert len(image) == layout.ROM_SIZE
    assert parse_image(image) == desc


def test_layout_addresses_hold_the_documented_instructions() -> None:
    img = default_image()
    assert img[layout.MAIN_LOOP] == 9 and img[layout.MAIN_LOOP + 1] == 0x00
    assert img[layout.STARTUP_CALL : layout.STARTUP_CALL + 2] == b"\x07\x0c"
    assert img[layout.MAIN_LOOP_JUMP : layout.MAIN_LOOP_JUMP + 5] == bytes.fromhex("07 0B 4B 04 00")
    assert img[layout.STARTUP_STUB : layout.STARTUP_STUB + 3] == bytes.fromhex("03 0D 10")
    assert img[layout.ALL_FREE] == 79 and img[layout.ALL_HOLD] == 79 and img[layout.ALL_HOME] == 79
    assert img[layout.TIMER_WAIT] == 9 and img[layout.TIMER_WAIT + 25] == 79  # hold follows
    assert layout.motion_address(1) == 0x0B80 and layout.motion_address(120) == 0x3C380
    assert layout.motion_number(0x0B80 + 2048) == 2 and layout.motion_number(0x44B) is None
    with pytest.raises(ValueError):
        layout.motion_address(121)


def test_description_validation() -> None:
    with pytest.raises(ValueError):
        ImageServo(ics=35)
    with pytest.raises(ValueError):
        ImageDescription(servos=(ImageServo(2), ImageServo(2)))
    with pytest.raises(ValueError):
        ImageMotion(1, [RunSingleServo(0, 1, 7500)] * 300)
    assert ImagePriorityMotion(0x22, "le", 223, 0x1000).compare == "lt"
    assert ImagePriorityMotion(0x22, "le", 223, 0x1000).value == 224


def test_default_board_boots_homes_and_runs_the_main_loop(booted: Board) -> None:
    assert sorted(booted.servo_outputs()) == sorted(DEFAULT_ICS)
    assert len(DEFAULT_ICS) == 17
    assert set(booted.servo_outputs().values()) == {7500}
    assert layout.MAIN_LOOP <= booted.pc < layout.MAIN_LOOP_JUMP + 7
    assert booted.ram[0:2] == default_description().system_register.to_bytes(2, "little")
    for ics in DEFAULT_ICS:
        blk = booted.alloc(ics)
        assert blk == 0x90 + 20 * ics
        assert int.from_bytes(booted.ram[blk + 4 : blk + 6], "little") == 7500
    assert booted.alloc(35) == 0x034C and booted.alloc(1) == 0xFFFF


def test_motion_one_plays_from_the_host_and_returns(booted: Board) -> None:
    seen: list[tuple[int, int]] = []
    booted.add_output_listener(lambda t, outs: seen.append((booted.pc, outs[2])))
    # spec 11.4: suspend, reset PC, CALL motion 1, resume
    x(booted, "09 00 02 00 00 00 90 C0 5B")
    x(booted, "11 00 02 02 00 00 4B 04 00 00 00 00 00 00 00 00 64")
    assert x(booted, "07 0C 80 0B 00 00 9E") == bytes.fromhex("04 0C 06 16")
    x(booted, "09 00 02 00 00 00 9B C0 66")
    booted.run_for(2.0)
    assert max(v for _, v in seen) == 7500 + 2700
    assert any(pc >= 0x0B80 for pc, _ in seen)
    assert layout.MAIN_LOOP <= booted.pc < 0x0B80 and booted.ram[5] == 0
    assert booted.servo_outputs()[2] == 7500


def test_triangle_button_plays_motion_one(booted: Board) -> None:
    booted.set_buttons(Button.TRIANGLE)
    booted.run_for(0.05)
    booted.set_buttons(0)
    assert layout.motion_number(booted.pc) == 1 and booted.ram[5] == 1
    booted.run_for(1.5)
    assert booted.pc < 0x0B80 and booted.ram[5] == 0


def test_persistent_rom_survives_restart(tmp_path: Path) -> None:
    path = tmp_path / "rom.bin"
    b = Board(EmulatorConfig(power_on_system_register=0), rom_path=path)
    assert path.read_bytes() == default_image()
    for i in range(64):  # a long upload: many 128-byte page writes, one flush
        data = bytes([i]) * 121
        frame = encode_command(Move(Rom(0x20000 + 121 * i), Data(data)))
        assert b.feed(frame) == bytes.fromhex("04 00 06 0A")
    assert b._store is not None and b._store.flushes == 1  # the initial image only
    b.close()
    assert b._store.flushes == 2
    assert [p.name for p in tmp_path.iterdir()] == ["rom.bin"]  # no temp files left
    b2 = Board(EmulatorConfig(power_on_system_register=0), rom_path=path)
    assert b2.rom[0x20000 + 121 * 5 : 0x20000 + 121 * 6] == bytes([5]) * 121
    assert b2.rom[:0x20000] == default_image()[:0x20000]
    b2.close()


def test_rom_flush_after_debounce(tmp_path: Path) -> None:
    path = tmp_path / "rom.bin"
    b = Board(EmulatorConfig(power_on_system_register=0, rom_flush_delay_s=0), rom_path=path)
    x(b, "0A 00 32 80 0B 00 03 0D 10 E7")
    b.tick()
    assert path.read_bytes()[0x0B80:0x0B83] == bytes.fromhex("03 0D 10")
    b.close()


def test_bad_rom_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "short.bin"
    path.write_bytes(b"\xff" * 10)
    with pytest.raises(ValueError):
        Board(rom_path=path)
    with pytest.raises(ValueError):
        Board(rom_image=b"\xff" * (0x40000 + 1))


def test_rom_image_is_padded_and_used() -> None:
    b = Board(
        EmulatorConfig(), clock=VirtualClock(), rom_image=bytes.fromhex("07 0B 00 00 00 00 12")
    )
    b.run_for(0.1)
    assert b.pc == 0 and b.ram[0] & 0x02 and b.rom[7] == 0xFF
    assert os.path.basename(__file__).startswith("test_emu_")
