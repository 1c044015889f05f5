"""The struct views of the memory map: golden bytes against spec 9 / 10 / 11.3 and round trips
over RAM and ROM buffers at an offset."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.protocol import Condition
from rcb4hv.protocol import memory as m

# spec section 9 field order: type, ID, base, measured, output, speed, end, remaining, width,
# mix1 source, mix1 method, mix2 source, mix2 method
GOLDEN_BLOCK = bytes.fromhex("00 05 fb ff 4c 1d 60 22 0a 98 3a 04 38 18 22 80 85 ff ff 00")


def test_servo_block_golden_fields() -> None:
    b = m.ServoBlock.from_bytes(GOLDEN_BLOCK)
    assert b == m.ServoBlock(
        type=0,
        ics_id=5,
        base=-5,
        measured=7500,
        output=8800,
        speed=10,
        end=15000,
        remaining=4,
        width=6200,
        mix1_source=0x8022,
        mix1_method=0x85,
        mix2_source=0xFFFF,
        mix2_method=0,
    )
    assert b.to_bytes() == GOLDEN_BLOCK


def test_servo_fields_read_and_write_a_block_at_its_ram_address() -> None:
    ram = bytearray(m.ADDR.RAM_SIZE)
    blk = m.ADDR.servo_block(3)
    assert blk == 0x0090 + 60
    ram[blk : blk + 20] = GOLDEN_BLOCK
    assert m.SERVO.F_OUTPUT.get(ram, blk) == 8800
    assert m.SERVO.F_BASE.get(ram, blk) == -5
    assert m.SERVO.F_WIDTH.get(ram, blk) == 6200
    assert m.SERVO.F_REMAINING.get(ram, blk) == 4
    m.SERVO.F_OUTPUT.put(ram, blk, 7500)
    m.SERVO.F_BASE.put(ram, blk, -1)
    assert ram[blk + 6 : blk + 8] == b"\x4c\x1d"
    assert ram[blk + 2 : blk + 4] == b"\xff\xff"
    assert m.SERVO.F_MEASURED.span(blk) == (blk + 4, 2)
    assert [f.offset for f in (m.SERVO.F_MIX1_SOURCE, m.SERVO.F_MIX2_METHOD)] == [14, 19]


@given(st.binary(min_size=20, max_size=20), st.integers(0, 100))
def test_servo_block_pack_unpack_at_any_offset(raw: bytes, at: int) -> None:
    buf = bytearray(at + 40)
    block = m.ServoBlock.from_bytes(raw)
    block.pack(buf, at)
    assert bytes(buf[at : at + 20]) == raw
    assert m.ServoBlock.unpack(buf, at) == block
    assert m.ServoBlock.unpack(bytes(buf), at) == block


def test_configured_block_is_free_until_boot() -> None:
    raw = m.ServoBlock.configured(7, -3, mix2=(0x0352, 0x02)).to_bytes()
    assert raw == bytes.fromhex("00 07 fd ff 00 00 00 80 00 00 80 00 00 00 ff ff 00 52 03 02")


def test_short_servo_block_is_rejected() -> None:
    with pytest.raises(ValueError, match="20 bytes"):
        m.ServoBlock.from_bytes(bytes(19))


@pytest.mark.parametrize(
    ("word", "decoded"),
    [
        (0x8022, (True, False, 0x0022)),
        (0xC105, (True, True, 0x0105)),
        (0x4352, (False, True, 0x352)),
    ],
)
def test_mix_source(word: int, decoded: tuple[bool, bool, int]) -> None:
    assert m.mix_source(word) == decoded


@given(st.integers(-127, 127))
def test_mix_method_round_trip(rate: int) -> None:
    assert m.mix_rate(m.mix_method(rate)) == rate
    assert m.mix_method(rate) >> 7 == (rate < 0)


def test_allocation_table() -> None:
    ram = bytearray(m.ADDR.RAM_SIZE)
    table: list[int | None] = [None] * 36
    table[0], table[35] = 0x0090, 0x034C
    ram[m.ADDR.ICS_ALLOC : m.ADDR.ICS_ALLOC + 72] = m.pack_alloc(table)
    assert ram[0x44:0x46] == b"\x90\x00" and ram[0x8A:0x8C] == b"\x4c\x03"
    assert m.unpack_alloc(ram) == table
    assert m.read_alloc(ram, 0) == 0x0090 and m.read_alloc(ram, 1) == m.NO_BLOCK
    assert m.pack_alloc([0x90]) == b"\x90\x00" + b"\xff" * 70
    with pytest.raises(ValueError):
        m.pack_alloc([None] * 37)


def test_vector_package_golden() -> None:
    # circle pressed -> CALL motion 1 (0B80h); compare word RAM 0350h with literal 4000h
    pkg = m.VectorPackage.button(m.Button.CIRCLE, 0x000B80)
    raw = pkg.to_bytes(last=True)
    assert raw == bytes.fromhex("b5 50 03 00 40 80 0b 00")
    assert m.VectorPackage.from_bytes(raw) == (pkg, True)
    assert pkg.condition == Condition.if_zero()
    assert raw[0] & m.VEC.CONDITION == Condition.if_zero().to_byte()
    c, dst, src, lo, hi = m.VECTOR_PACKAGE.unpack_from(raw)
    assert (c, dst, src, lo | hi << 16) == (0xB5, 0x0350, 0x4000, 0x0B80)


@given(st.binary(min_size=8, max_size=8), st.integers(0, 64))
def test_vector_package_round_trip_at_offset(raw: bytes, at: int) -> None:
    pkg, last = m.VectorPackage.from_bytes(raw)
    buf = bytearray(at + 8)
    pkg.pack(buf, at, last)
    assert bytes(buf[at:]) == raw
    assert m.VectorPackage.unpack(buf, at) == (pkg, last)


def test_operand_ics() -> None:
    assert m.operand_ics(0x0350) is None
    assert m.operand_ics(0x8304) == (3, 4)
    assert m.button_operand(m.Button.S1 | m.Button.UP) == 0x0102


def test_kri3_block_golden() -> None:
    blk = m.Kri3Block(buttons=int(m.Button.CIRCLE | m.Button.S1), pa1=0x80, checksum=0x5A)
    raw = blk.to_bytes()
    assert raw == bytes.fromhex("01 1f 00 00 02 40 80 00 00 00 5a")
    ram = bytearray(m.ADDR.RAM_SIZE)
    ram[m.ADDR.KRI3_BLOCK : m.ADDR.KRI3_BLOCK + 11] = raw
    assert m.Kri3Block.unpack(ram) == blk
    assert m.read_buttons(ram) == m.Button.CIRCLE | m.Button.S1
    with pytest.raises(ValueError, match="KRI-3"):
        m.Kri3Block(pa1=256).to_bytes()


def test_program_state_and_reset() -> None:
    ram = bytearray(m.ADDR.RAM_SIZE)
    m.write_system(ram, m.SYS.ROM_RUN | m.SYS.ICS_OUTPUT)
    ram[m.ADDR.PC : m.ADDR.PC + 10] = m.program_reset(0x00044B)
    ram[m.ADDR.CALL_DEPTH] = 2
    ram[m.ADDR.UPDATE_FLAGS + 1] = 0x04
    st_ = m.ProgramState.unpack(ram)
    assert st_ == m.ProgramState(0x0003, 0x00044B, 2, b"\x00\x04\x00\x00\x00")
    assert st_.running and st_.waiting
    assert m.read_pc(ram) == 0x44B and m.read_system(ram) == 3
    # spec 11.4 step 2 payload
    assert m.program_reset(0x00044B) == bytes.fromhex("4b 04 00 00 00 00 00 00 00 00")


def test_update_flags_read_as_one_integer_bit_n_is_ics_n() -> None:
    ram = bytearray(m.ADDR.RAM_SIZE)
    ram[m.ADDR.UPDATE_FLAGS : m.ADDR.UPDATE_FLAGS + 5] = bytes.fromhex("01 00 00 00 80")
    assert m.read_update_flags(ram) == 1 | 1 << 39
    span = bytes(3) + bytes.fromhex("00 04 00 00 00")  # read from the board at 0004h
    assert m.read_update_flags(span, m.ADDR.UPDATE_FLAGS - 4) == 1 << 10


@given(st.integers(0, 0x7FFF), st.booleans())
def test_timer_round_trip(count: int, running: bool) -> None:
    t = m.TimerState(count, running)
    assert m.TimerState.unpack(t.to_bytes(), 0) == t
    assert bool(t.to_word() & m.TIMER_STOPPED) != running


def test_regions_structs_cover_the_spec_sizes() -> None:
    assert m.COUNTERS.size == 11
    assert m.USER_VARIABLES.size == 40
    assert m.ADDR.USER_VARIABLES + m.USER_VARIABLES.size == m.ADDR.TEMPORARIES[0]
    assert m.AD_CHANNELS.size == 22 and m.PA_VALUES.size == 4 and m.TIMERS.size == 8
    assert m.ad_volts(0x0FFF) == pytest.approx(1023 * 25 / 1024)


@given(st.integers(-(1 << 20), 1 << 25), st.integers(0, 8))
def test_word_and_address_accessors(value: int, at: int) -> None:
    buf = bytearray(16)
    m.write_u16(buf, at, value)
    assert m.read_u16(buf, at) == value & 0xFFFF
    assert m.read_s16(buf, at) == m.s16(value & 0xFFFF)
    m.write_u24(buf, at, value)
    assert m.read_u24(buf, at) == value & 0xFFFFFF
    assert m.u24_bytes(value) == bytes(buf[at : at + 3])


def test_field_decode_and_run_state_of_a_span_read_from_a_board() -> None:
    # what a host reads: the field's own bytes, and the 10 bytes from the PC on
    assert m.SERVO.F_OUTPUT.decode(b"\x4c\x1d") == 7500
    assert m.SERVO.F_WIDTH.decode(b"\xff\xff") == -1
    raw = m.program_reset(0x000B80)[:3] + bytes((2, 0)) + b"\x01\x00\x00\x00\x80"
    assert m.read_run_state(raw, 0) == (0x000B80, 2, b"\x01\x00\x00\x00\x80")
    assert m.RUN_STATE_SIZE == m.ProgramState.SIZE - m.ADDR.PC == 10
    # HeartToHeart4's block of ICS 35 is where the KRI-3 block lives
    assert m.ADDR.servo_block(35) == m.ADDR.KRI3_BLOCK


def test_one_meaning_per_baud_name() -> None:
    from rcb4hv import protocol, transport

    # the system register's 2-bit codes (spec 10.2) vs the rates a host port can use
    assert m.SYSTEM_BAUD_RATES == (115200, 625000, 1250000, 115200)
    assert m.SystemRegister(baud_code=2).baud_rate == 1250000
    assert sorted(transport.BAUD_RATES) == [115200, 625000, 1250000]
    assert not hasattr(protocol, "BAUD_RATES") and not hasattr(m, "BAUD_RATES")
