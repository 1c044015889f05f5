"""Spec section 14 golden vectors as full request -> reply exchanges."""

from __future__ import annotations

import pytest

from rcb4hv.emulator import Board
from tests.emulator.conftest import h, x

VERSION_REPLY = (
    "23 FD 43 42 2D 34 20 56 31 2E 30 20 20 20 20 20 20 30 39 30 37 31 35 20 20 20 20 20 20 "
    "20 20 20 20 C7 08"
)


def alloc_servo(board: Board, ics: int, block: int) -> None:
    board.ram[0x44 + 2 * ics : 0x46 + 2 * ics] = block.to_bytes(2, "little")


def test_ack_check_both_forms(idle: Board) -> None:
    assert x(idle, "03 FE 01") == h("04 FE 06 08")
    assert x(idle, "04 FE 06 08") == h("04 FE 06 08")


def test_nak_for_fe_form_is_not_an_ack_request(idle: Board) -> None:
    # 04 FE 15 17 is a valid frame but not an acknowledge request: NAK echoing FE
    assert x(idle, "04 FE 15 17") == h("04 FE 15 17")


def test_version(idle: Board) -> None:
    assert x(idle, "03 FD 00") == h(VERSION_REPLY)


def test_write_then_read_system_register(idle: Board) -> None:
    assert x(idle, "09 00 02 00 00 00 02 80 8D") == h("04 00 06 0A")
    assert x(idle, "0A 00 20 00 00 00 00 00 02 2C") == h("05 00 02 80 87")


def test_read_ics5_measured_value(idle: Board) -> None:
    assert x(idle, "0A 00 21 00 00 00 04 05 02 36") == h("04 00 15 19")  # not allocated
    alloc_servo(idle, 5, 0x0100)
    idle.ram[0x104:0x106] = (7510).to_bytes(2, "little")
    assert x(idle, "0A 00 21 00 00 00 04 05 02 36") == h("05 00 56 1D 78")


def test_rom_write_and_read(idle: Board) -> None:
    assert x(idle, "0A 00 32 80 0B 00 03 0D 10 E7") == h("04 00 06 0A")
    assert idle.rom[0x0B80:0x0B83] == h("03 0D 10")
    reply = x(idle, "0B 00 23 00 00 00 80 0B 00 04 BD")
    data = idle.rom[0x0B80:0x0B84]
    assert reply == bytes([7, 0]) + data + bytes([(7 + sum(data)) & 0xFF])


def test_call_then_return(idle: Board) -> None:
    idle.ram[2:5] = h("4B 04 00")
    assert x(idle, "07 0C 80 0B 00 00 9E") == h("04 0C 06 16")
    assert idle.pc == 0x0B80
    assert idle.call_stack == [0x044B]
    assert x(idle, "03 0D 10") == h("04 0D 06 17")
    assert idle.pc == 0x044B
    assert x(idle, "03 0D 10") == h("04 0D 15 26")  # empty stack


@pytest.mark.parametrize(("z", "pc"), [(True, 0x044B), (False, 0x0000)])
def test_jump_if_z(idle: Board, z: bool, pc: int) -> None:
    idle.ram[1] = 0x01 if z else 0x00
    assert x(idle, "07 0B 4B 04 00 05 66") == h("04 0B 06 15")
    assert idle.pc == pc


def test_add_user_variable(idle: Board) -> None:
    idle.ram[0x462:0x464] = (0xFFFE).to_bytes(2, "little")
    assert x(idle, "09 06 02 62 04 00 05 00 7C") == h("05 06 03 00 0E")
    assert idle.ram[0x462:0x464] == h("03 00")
    assert idle.ram[1] & 0x03 == 0x02  # C = 1, Z = 0


def test_sub_nw_button_compare(idle: Board) -> None:
    idle.ram[0x350:0x352] = h("00 01")
    assert x(idle, "09 07 82 50 03 00 00 01 E6") == h("05 07 00 00 0C")
    assert idle.ram[0x350:0x352] == h("00 01")  # NW: not written back
    assert idle.ram[1] & 0x03 == 0x03  # Z = 1, C = 1 (no borrow)


def test_and_pio(idle: Board) -> None:
    idle.ram[0x3A] = 0xF5
    assert x(idle, "08 01 02 3A 00 00 0F 54") == h("04 01 05 0A")
    assert idle.ram[0x3A] == 0x05


def test_not_and_shifts(idle: Board) -> None:
    idle.ram[0x462:0x464] = h("0F 00")
    assert x(idle, "0A 04 00 62 04 00 00 00 02 76") == h("05 04 F0 FF F8")
    assert x(idle, "0A 05 00 62 04 00 00 01 02 78") == h("05 05 F8 7F 81")
    assert idle.ram[1] & 0x02 == 0  # C = bit shifted out = 0
    assert x(idle, "0A 05 00 62 04 00 00 FF 02 76") == h("05 05 F0 FF F9")


def test_single_servo_moves(idle: Board) -> None:
    alloc_servo(idle, 2, 0x00B8)
    idle.ram[0xB8 + 6 : 0xB8 + 8] = (7000).to_bytes(2, "little")
    assert x(idle, "07 0F 02 1E 4C 1D 9F") == h("04 0F 06 19")
    assert idle.ram[0xB8 + 8] == 30
    assert idle.ram[0xB8 + 9 : 0xB8 + 11] == (7500).to_bytes(2, "little")
    assert idle.ram[7] == 0x04
    assert x(idle, "07 0F 02 01 00 80 99") == h("04 0F 06 19")
    assert idle.ram[0xB8 + 6 : 0xB8 + 8] == h("00 80")


def test_const_frame_servo(idle: Board) -> None:
    alloc_servo(idle, 0, 0x0090)
    alloc_servo(idle, 9, 0x0090 + 20 * 9)
    assert x(idle, "0D 10 01 02 00 00 00 0A 4C 1D 40 1F F2") == h("04 10 06 1A")
    assert idle.ram[0x90 + 9 : 0x90 + 11] == (7500).to_bytes(2, "little")
    assert idle.ram[0x90 + 8] == 10


def test_series_servo_and_speed(idle: Board) -> None:
    assert x(idle, "0E 11 08 00 00 00 01 05 B0 1D 06 14 1E 32") == h("04 11 06 1B")
    assert x(idle, "0B 12 01 02 00 00 00 02 64 3C C2") == h("04 12 06 1C")
    assert idle.speed_parameter == {0: 100, 9: 60}
