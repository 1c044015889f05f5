"""ROM programs: the execution loop of spec 11.1, call stack, flags, timers, vector jumps."""

from __future__ import annotations

from collections.abc import Sequence

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.protocol import (
    ALWAYS,
    AcknowledgeCheck,
    Add,
    Button,
    Call,
    Command,
    Condition,
    Data,
    GetVersionInfo,
    Ics,
    Jump,
    Move,
    Ram,
    Return,
    RunSingleServo,
    Sub,
    encode_command,
)
from tests.emulator.conftest import x

VAR = 0x0462
T0 = 0x003C
ROM_F = 0x02
VEC_F = 0x08


def blank(clock: VirtualClock | None = None, **cfg: object) -> Board:
    """Erased ROM, program stopped, 10 ms periods."""
    config = EmulatorConfig(power_on_system_register=0, **cfg)  # type: ignore[arg-type]
    return Board(config, clock=clock or VirtualClock(), rom_image=b"\xff" * 0x40000)


def load(board: Board, addr: int, cmds: Sequence[Command]) -> list[int]:
    """Write the commands from ``addr``; return the address of each."""
    out = []
    for c in cmds:
        f = encode_command(c)
        out.append(addr)
        board.load_rom(addr, f)
        addr += len(f)
    return out


def start(board: Board, pc: int, sysreg: int = ROM_F) -> None:
    board.ram[2:5] = pc.to_bytes(3, "little")
    board.ram[0] = sysreg


def var(board: Board, n: int = 0) -> int:
    return int.from_bytes(board.ram[VAR + 2 * n : VAR + 2 * n + 2], "little")


def setv(n: int, value: int) -> Move:
    return Move(Ram(VAR + 2 * n), Data(value.to_bytes(2, "little")))


def halt_at(addr: int) -> Jump:
    return Jump(addr, ALWAYS)


def test_nested_calls_return_in_order() -> None:
    b = blank()
    # main: CALL A; var1 = 9; halt.   A: var0 += 1; CALL B; RETURN.   B: CALL C; RETURN. C: RETURN
    main = [Call(0x1000, ALWAYS), setv(1, 9), halt_at(0x0000 + 7 + 9)]
    load(b, 0x0000, main)
    load(b, 0x1000, [Add(Ram(VAR), Data(b"\x01\x00")), Call(0x2000, ALWAYS), Return()])
    load(b, 0x2000, [Call(0x3000, ALWAYS), Return()])
    seen_depths = []
    load(b, 0x3000, [Return()])
    start(b, 0)
    for _ in range(20):
        b.run_for(0.0002)  # one instruction at 5 per ms
        seen_depths.append(b.ram[5])
    assert max(seen_depths) == 3
    assert b.ram[5] == 0
    assert var(b) == 1 and var(b, 1) == 9
    assert b.pc == 16 and b.ram[0] & ROM_F


def test_seventeenth_call_stops_the_program() -> None:
    b = blank()
    load(b, 0x1000, [Add(Ram(VAR), Data(b"\x01\x00")), Call(0x1000, ALWAYS)])
    start(b, 0x1000)
    b.run_for(0.1)
    assert not b.ram[0] & ROM_F
    assert b.ram[5] == 16 and var(b) == 17
    assert b.call_stack == [0x1010] * 16  # the address after the CALL
    assert b.pc == 0x1009  # stopped at the CALL that failed
    assert not b.ram[1] & 0x04  # not a ROM error


def test_return_on_empty_stack_stops_the_program() -> None:
    b = blank()
    load(b, 0x100, [setv(0, 1), Return(), setv(0, 2)])
    start(b, 0x100)
    b.run_for(0.1)
    assert var(b) == 1 and not b.ram[0] & ROM_F and b.pc == 0x109


def test_checksum_error_sets_romerr() -> None:
    b = blank()
    (a,) = load(b, 0x100, [setv(0, 1)])
    b.load_rom(0x109, bytes.fromhex("09 00 02 62 04 00 05 00 00"))  # bad SUM
    start(b, a)
    b.run_for(0.1)
    assert var(b) == 1
    assert not b.ram[0] & ROM_F and b.ram[1] & 0x04 and b.pc == 0x109


def test_erased_rom_is_a_rom_error() -> None:
    b = blank()
    start(b, 0x5000)
    b.run_for(0.01)
    assert not b.ram[0] & ROM_F and b.ram[1] & 0x04


def test_command_error_from_rom_stops_without_romerr() -> None:
    b = blank()
    load(b, 0x100, [Move(Ram(0x90), Ram(0x90), 2)])
    load(b, 0x10A, [Move(Ics(4, 3), Data(b"\x01\x00"))])  # ICS 3 is not allocated
    start(b, 0x100)
    b.run_for(0.1)
    assert not b.ram[0] & ROM_F and not b.ram[1] & 0x04 and b.pc == 0x10A


def test_conditional_loop_counts_to_five() -> None:
    b = blank()
    # loop: var0 += 1; SUB NW var0 - 5; JUMP loop if Z = 0; var1 = 1; halt
    addrs = load(
        b,
        0x200,
        [
            Add(Ram(VAR), Data(b"\x01\x00")),
            Sub(Ram(VAR), Data(b"\x05\x00"), None, True),
            Jump(0x200, Condition.if_not_zero()),
            setv(1, 1),
        ],
    )
    end = addrs[-1] + 9
    load(b, end, [halt_at(end)])
    start(b, 0x200)
    b.run_for(0.1)
    assert var(b) == 5 and var(b, 1) == 1 and b.pc == end


def test_carry_conditions() -> None:
    b = blank()
    # var0 = 3; SUB NW var0 - 4 -> C = 0 (borrow): CALL if C=0 sets var1
    load(
        b,
        0x0,
        [
            setv(0, 3),
            Sub(Ram(VAR), Data(b"\x04\x00"), None, True),
            Call(0x800, Condition.if_not_carry()),
            Call(0x900, Condition.if_carry()),
            halt_at(9 + 9 + 7 + 7),
        ],
    )
    load(b, 0x800, [setv(1, 0x11), Return()])
    load(b, 0x900, [setv(2, 0x22), Return()])
    start(b, 0)
    b.run_for(0.1)
    assert var(b, 1) == 0x11 and var(b, 2) == 0


def test_timer_wait_in_virtual_time() -> None:
    clock = VirtualClock()
    b = blank(clock)
    # timer0 = 5 (500 ms); wait while timer0 != 8000; var0 = 1; halt
    load(
        b,
        0x0,
        [
            Move(Ram(T0), Data(b"\x05\x00")),
            Sub(Ram(T0), Data(b"\x00\x80"), None, True),
            Jump(0x9, Condition.if_not_zero()),
            setv(0, 1),
            halt_at(0x9 + 9 + 7 + 9),
        ],
    )
    start(b, 0)
    b.run_for(0.39)
    assert var(b) == 0
    assert 0 < int.from_bytes(b.ram[T0 : T0 + 2], "little") <= 2
    b.run_for(0.12)
    assert var(b) == 1  # timer expired at 0.5 s (100 ms ticks from power-on)
    assert b.ram[T0 : T0 + 2] == b"\x00\x80"


def test_timers_count_down_and_stop() -> None:
    b = blank()
    b.ram[0x3E:0x40] = (3).to_bytes(2, "little")
    b.ram[0x40:0x42] = (0x8005).to_bytes(2, "little")  # stopped
    b.run_for(0.25)
    assert int.from_bytes(b.ram[0x3E:0x40], "little") == 1
    b.run_for(0.1)
    assert b.ram[0x3E:0x40] == b"\x00\x80"
    assert int.from_bytes(b.ram[0x40:0x42], "little") == 0x8005


def test_update_flags_gate_the_next_instruction() -> None:
    b = blank()
    b.ram[0x44 + 2 * 2 : 0x46 + 2 * 2] = (0x00B8).to_bytes(2, "little")
    b.ram[0xB8 + 6 : 0xB8 + 8] = (7000).to_bytes(2, "little")
    b.ram[0xB8 + 14 : 0xB8 + 16] = b"\xff\xff"
    b.ram[0xB8 + 17 : 0xB8 + 19] = b"\xff\xff"
    load(b, 0, [RunSingleServo(2, 10, 8000), setv(0, 1), halt_at(7 + 9)])
    start(b, 0)  # 10 ms periods
    b.run_for(0.0002)
    assert b.ram[7] == 0x04
    b.run_for(0.1)  # periods 1..10: the ramp; flag still set until period 11
    assert var(b) == 0 and b.ram[7] == 0x04
    assert int.from_bytes(b.ram[0xB8 + 6 : 0xB8 + 8], "little") == 8000
    b.run_for(0.0105)
    assert b.ram[7] == 0 and var(b) == 1


def test_version_and_ack_do_nothing_from_rom() -> None:
    b = blank()
    load(b, 0, [GetVersionInfo(), AcknowledgeCheck(), setv(0, 7), halt_at(3 + 3 + 9)])
    start(b, 0)
    b.run_for(0.01)
    assert var(b) == 7 and b.take_output() == b""


def test_com_commands_served_while_program_runs() -> None:
    b = blank()
    load(b, 0, [Add(Ram(VAR), Data(b"\x01\x00")), halt_at(0)])
    start(b, 0)
    b.run_for(0.01)
    reply = x(b, "0A 00 20 00 00 00 62 04 02 92")
    assert reply[0] == 5 and int.from_bytes(reply[2:4], "little") >= 1
    assert b.ram[0] & ROM_F


def vector_table(b: Board, packages: list[bytes]) -> None:
    b.ram[0x357 : 0x357 + 8 * len(packages)] = b"".join(packages)
    b.ram[0x8C:0x8E] = (0x357).to_bytes(2, "little")


def package(cond: int, dst: int, src: int, target: int) -> bytes:
    return (
        bytes((cond,))
        + dst.to_bytes(2, "little")
        + src.to_bytes(2, "little")
        + target.to_bytes(3, "little")
    )


def test_vector_jump_driven_by_buttons() -> None:
    b = blank()
    raw = int.from_bytes(Button.CIRCLE.to_ram(), "little")
    raw2 = int.from_bytes(Button.CROSS.to_ram(), "little")
    # package 0: CALL 0x800 when buttons == CIRCLE; package 1 (EOF): JUMP 0x900 on CROSS
    vector_table(
        b, [package(0x35, 0x350, raw, 0x800), package(0x80 | 0x40 | 0x35, 0x350, raw2, 0x900)]
    )
    load(b, 0, [halt_at(0)])
    load(b, 0x800, [setv(0, 1), Return()])
    load(b, 0x900, [setv(1, 2), halt_at(0x909)])
    start(b, 0, ROM_F | VEC_F)
    b.run_for(0.05)
    assert b.pc == 0 and var(b) == 0
    b.set_buttons(Button.CIRCLE)
    b.run_for(0.01)
    assert var(b) == 1 and b.pc == 0 and b.ram[5] == 0
    assert not b.ram[0] & VEC_F  # cleared when the jump fired
    b.ram[0] |= VEC_F
    b.set_buttons(Button.CROSS)
    b.run_for(0.01)
    assert var(b, 1) == 2 and b.pc == 0x909 and b.ram[5] == 0


def test_vector_jump_needs_vec_f() -> None:
    b = blank()
    raw = int.from_bytes(Button.UP.to_ram(), "little")
    vector_table(b, [package(0x80 | 0x35, 0x350, raw, 0x800)])
    load(b, 0, [halt_at(0)])
    start(b, 0, ROM_F)
    b.set_buttons(Button.UP)
    b.run_for(0.05)
    assert b.pc == 0


def test_program_with_nested_calls_timer_and_button_vector() -> None:
    """The issue's acceptance program: main loop re-arming VEC_F, a button-driven CALL
    into a routine that nests two calls, waits on a timer and moves a servo."""
    clock = VirtualClock()
    b = blank(clock)
    b.ram[0x44 + 0 : 0x46] = (0x0090).to_bytes(2, "little")
    b.ram[0x90 + 6 : 0x90 + 8] = (7500).to_bytes(2, "little")
    b.ram[0x90 + 14 : 0x90 + 16] = b"\xff\xff"
    b.ram[0x90 + 17 : 0x90 + 19] = b"\xff\xff"
    raw = int.from_bytes(Button.TRIANGLE.to_ram(), "little")
    vector_table(b, [package(0x80 | 0x35, 0x350, raw, 0x1000)])
    sysreg = ROM_F | VEC_F | 0x01
    load(b, 0x44B, [Move(Ram(0), Data(bytes((sysreg, 0)))), halt_at(0x44B)])
    load(b, 0x1000, [Call(0x1100, ALWAYS), setv(2, 3), Return()])
    load(b, 0x1100, [Add(Ram(VAR), Data(b"\x01\x00")), Call(0x1200, ALWAYS), Return()])
    load(
        b,
        0x1200,
        [
            Move(Ram(T0), Data(b"\x03\x00")),
            Sub(Ram(T0), Data(b"\x00\x80"), None, True),
            Jump(0x1209, Condition.if_not_zero()),
            RunSingleServo(0, 20, 9000),
            setv(1, 0x55),
            Return(),
        ],
    )
    start(b, 0x44B, sysreg)
    b.run_for(0.2)
    assert var(b) == 0 and b.pc in (0x44B, 0x454)
    b.set_buttons(Button.TRIANGLE)
    b.run_for(0.05)
    b.set_buttons(0)
    assert b.ram[5] == 3 and 0x1209 <= b.pc < 0x1219  # waiting on the timer, 3 deep
    assert var(b) == 1
    b.run_for(0.4)  # timer expired; the servo moves for 20 periods of 10 ms
    assert b.ram[7] == 0x01 and var(b, 1) == 0
    b.run_for(0.25)
    assert var(b, 1) == 0x55 and var(b, 2) == 3
    assert b.ram[5] == 0 and b.pc in (0x44B, 0x454)
    assert b.servo_outputs()[0] == 9000
    assert b.ram[0] & VEC_F  # re-armed by the main loop
    assert var(b) == 1  # ran once: the button was released
