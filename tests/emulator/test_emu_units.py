"""The emulator's units: the ALU table and condition evaluator, the public stop reason
(``Board.last_stop``) and the clock's time conversions."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.emulator import Board, Clock, EmulatorConfig, RealClock, Stop, VirtualClock
from rcb4hv.emulator.alu import ALU, AluOp, alu, condition_table, set_flags
from rcb4hv.protocol import (
    ALWAYS,
    Call,
    Condition,
    Data,
    Ics,
    Jump,
    Move,
    Ram,
    Return,
    encode_command,
)
from rcb4hv.protocol.memory import ADDR, SYS
from tests.emulator.test_emu_program import blank, load, setv, start

# ------------------------------------------------------------------------------ ALU


@pytest.mark.parametrize(
    ("op", "a", "b", "size", "expected"),
    [
        (AluOp.ADD, 0xFF, 0x01, 1, (0x00, True, True)),
        (AluOp.ADD, 0x1234, 0x0001, 2, (0x1235, False, False)),
        (AluOp.SUB, 5, 5, 1, (0, True, True)),  # C = no borrow
        (AluOp.SUB, 4, 5, 1, (0xFF, False, False)),
        (AluOp.MUL, 0x100, 0x100, 2, (0, True, True)),
        (AluOp.DIV, 7, 2, 1, (3, False, False)),
        (AluOp.MOD, 7, 2, 1, (1, False, False)),
        (AluOp.DIV, 7, 0, 1, (0, True, False)),  # the "zero" setting's value
        (AluOp.AND, 0xF0, 0x0F, 1, (0, True, None)),  # logic leaves C
        (AluOp.OR, 0xF0, 0x0F, 1, (0xFF, False, None)),
        (AluOp.XOR, 0xFF, 0x0F, 1, (0xF0, False, None)),
        (AluOp.NOT, 0x00FF, 0, 2, (0xFF00, False, None)),
        (AluOp.SHIFT, 0b101, 1, 1, (0b10, False, True)),  # right: C = last bit out
        (AluOp.SHIFT, 0x81, -1, 1, (0x02, False, True)),  # left
        (AluOp.SHIFT, 0x81, -9, 1, (0x00, True, False)),  # past the width
        (AluOp.SHIFT, 0x81, 0, 1, (0x81, False, None)),
    ],
)
def test_alu_golden(op: AluOp, a: int, b: int, size: int, expected: tuple[int, bool, bool]) -> None:
    assert alu(op, a, b, size) == expected


@given(st.sampled_from(list(AluOp)), st.integers(0, 0xFFFF), st.integers(0, 0xFFFF))
def test_alu_results_fit_and_z_means_zero(op: AluOp, a: int, b: int) -> None:
    if op is AluOp.SHIFT:
        b = (b % 33) - 16
    r, z, _ = alu(op, a, b, 2)
    assert 0 <= r <= 0xFFFF and z == (r == 0)
    assert set(ALU) == set(AluOp)


def test_set_flags_keeps_other_bits() -> None:
    hi = 0xF0 | (SYS.ROM_ERROR >> 8)
    assert set_flags(hi, True, True, False) == hi | 0x03
    assert set_flags(hi | 0x02, False, None, False) == hi | 0x02  # C unchanged
    assert set_flags(hi | 0x02, False, None, True) == hi  # logic_carry="clear"


def test_condition_table_is_and_or_or() -> None:
    zc = Condition(compare_z=True, z=True, compare_c=True, c=True).to_byte()
    # index: bit 0 Z, bit 1 C
    assert condition_table(zc) == (False, False, False, True)
    assert condition_table(zc, any_mode=True) == (False, True, True, True)
    assert condition_table(ALWAYS.to_byte()) == (True,) * 4
    assert condition_table(Condition.if_not_zero().to_byte()) == (True, False, True, False)


# ------------------------------------------------------------------------------ last_stop


def test_no_stop_after_power_on() -> None:
    assert Board().last_stop is None


def test_romerr_stop() -> None:
    b = blank()
    start(b, 0x5000)
    b.run_for(0.01)
    s = b.last_stop
    assert s is not None and (s.what, s.where, s.instruction) == ("romerr", 0x5000, None)
    assert isinstance(s, Stop) and "no valid frame" in s.why and s.halted
    assert b.ram[1] & (SYS.ROM_ERROR >> 8)


def test_command_error_stop_names_the_instruction() -> None:
    b = blank()
    load(b, 0x100, [Move(Ics(4, 3), Data(b"\x01\x00"))])  # ICS 3 is not allocated
    start(b, 0x100)
    b.run_for(0.01)
    s = b.last_stop
    assert s is not None and s.what == "command-error" and s.where == 0x100
    assert "ICS 3 is not allocated" in s.why and s.instruction and s.instruction in s.why


def test_stack_overflow_and_underflow_stops() -> None:
    b = blank()
    load(b, 0x1000, [Call(0x1000, ALWAYS)])
    start(b, 0x1000)
    b.run_for(0.1)
    assert b.last_stop is not None
    assert (b.last_stop.what, b.last_stop.where) == ("stack-overflow", 0x1000)
    b = blank()
    (_, ret) = load(b, 0x100, [setv(0, 1), Return()])
    start(b, 0x100)
    b.run_for(0.1)
    assert b.last_stop is not None
    assert (b.last_stop.what, b.last_stop.where) == ("stack-underflow", ret)


def test_return_to_host_and_suspended() -> None:
    """The spec 11.4 play sequence: the routine a host CALL started returns to the host's
    PC (the program keeps running), then the host suspends the program."""
    b = blank()
    (loop,) = load(b, 0x100, [Jump(0x100, ALWAYS)])  # the main loop
    (_, ret) = load(b, 0x2000, [setv(0, 7), Return()])
    start(b, loop)
    b.run_for(0.01)
    assert b.feed(encode_command(Call(0x2000, ALWAYS))) == bytes.fromhex("04 0C 06 16")
    b.run_for(0.01)
    s = b.last_stop
    assert s is not None and (s.what, s.where) == ("return-to-host", ret) and not s.halted
    assert b.ram[0] & SYS.ROM_RUN and b.ram[ADDR.CALL_DEPTH] == 0
    b.feed(encode_command(Move(Ram(0), Data(b"\x00"))))
    s = b.last_stop
    assert s is not None and s.what == "suspended" and s.halted and "Move" in s.why


def test_a_routine_call_from_rom_is_not_a_return_to_host() -> None:
    b = blank()
    load(b, 0x100, [Call(0x2000, ALWAYS), Jump(0x100 + 7, ALWAYS)])
    load(b, 0x2000, [Return()])
    start(b, 0x100)
    b.run_for(0.1)
    assert b.last_stop is None


# ------------------------------------------------------------------------------ clock


def test_clocks_convert_board_and_real_time() -> None:
    fast = RealClock(speed=4.0)
    assert isinstance(fast, Clock) and isinstance(VirtualClock(), Clock)
    assert fast.real_seconds(2.0) == 0.5 and fast.board_seconds(0.5) == 2.0
    v = VirtualClock()
    assert v.speed == 1.0 and v.real_seconds(0.3) == 0.3


def test_poll_timeout_is_real_seconds_of_a_fast_clock() -> None:
    """A board on a clock running 10x real time needs a tick 10x sooner in real time."""
    fast = RealClock(speed=10.0)
    b = Board(EmulatorConfig(), clock=fast)
    t = b.poll_timeout()
    assert t is not None and t <= 0.010 / 10 + 1e-9
    b.feed(bytes.fromhex("07 0F"))  # a partial frame: its timeout is real time
    t = b.poll_timeout()
    assert t is not None and t <= EmulatorConfig().frame_timeout_s + 1e-9
