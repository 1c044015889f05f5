"""The client suite: every command and the robot-level API against the emulator, run once per
transport (in process via rcb4emu://, a real pty, TCP loopback)."""

from __future__ import annotations

import math
import time

import pytest

from rcb4hv.client import (
    Rcb4Client,
    plan_cheapest,
    plan_reads,
)
from rcb4hv.errors import (
    CommandNotAllowedError,
    NakError,
    ProgramStoppedError,
    Rcb4TimeoutError,
    VerifyError,
)
from rcb4hv.protocol import (
    ADDR,
    POSITION_FREE,
    POSITION_HOLD,
    Button,
    Com,
    Command,
    Condition,
    Data,
    DataReply,
    Ics,
    Ram,
    Reply,
    Rom,
    SystemRegister,
)
from tests.client.aio_bridge import BlockingBridge
from tests.client.conftest import STEP, Rig

VAR = ADDR.user_variable(0)


def test_ack_and_version(rig: Rig) -> None:
    rig.client.acknowledge_check()
    rig.client.acknowledge_check(long_form=True)
    v = rig.client.get_version_info()
    assert v.text == "CB-4 V1.0      090715"
    assert v.version == rig.board.config.version_string


def test_ram_round_trip_any_size(rig: Rig) -> None:
    data = bytes((i * 7) & 0xFF for i in range(300))
    rig.client.write_ram(0x0357, data[:200])
    assert rig.client.read_ram(0x0357, 200) == data[:200]
    assert bytes(rig.board.ram[0x0357 : 0x0357 + 200]) == data[:200]
    rig.robot.stop_motion(reset=False)  # the running program would change RAM between frames
    assert rig.robot.ram_dump() == bytes(rig.board.ram)


def test_move_variants(rig: Rig) -> None:
    c = rig.client
    c.move(Ram(VAR), Data(b"\x34\x12"))
    assert c.move(Com(), Ram(VAR), 2) == b"\x34\x12"
    c.move(Ram(VAR + 2), Ram(VAR), 2)
    assert c.read_ram(VAR + 2, 2) == b"\x34\x12"
    # ICS operand: the measured value of a servo block through alloc[]
    alloc = rig.robot.allocation_table()
    k = next(i for i, a in enumerate(alloc) if a is not None)
    assert c.move(Com(), Ics(4, k), 2) == c.read_ram(alloc[k] + 4, 2)  # type: ignore[operator]


def test_logic_and_arithmetic(rig: Rig) -> None:
    c = rig.client
    rig.robot.stop_motion(reset=False)  # the ROM main loop would change the flags under us
    c.write_ram(VAR, (0x00F0).to_bytes(2, "little"))
    assert c.and_(Ram(VAR), Data(b"\x3c\x00")) == b"\x30\x00"
    assert c.or_(Ram(VAR), Data(b"\x0f\x00")) == b"\x3f\x00"
    assert c.xor(Ram(VAR), Data(b"\xff\x00")) == b"\xc0\x00"
    assert c.not_(Ram(VAR), 2) == b"\x3f\xff"
    c.write_ram(VAR, (6).to_bytes(2, "little"))
    assert c.shift(Ram(VAR), 2, 1) == (3).to_bytes(2, "little")
    assert c.shift(Ram(VAR), 2, 0xFF) == (6).to_bytes(2, "little")
    assert c.add(Ram(VAR), Data(b"\x05\x00")) == 11
    assert c.sub(Ram(VAR), Data(b"\x01\x00")) == 10
    assert c.multiply(Ram(VAR), Data(b"\x03\x00")) == 30
    assert c.division(Ram(VAR), Data(b"\x04\x00")) == 7
    assert c.modulo(Ram(VAR), Data(b"\x04\x00")) == 3
    assert c.sub(Ram(VAR), Data(b"\x03\x00"), no_write=True) == 0
    assert rig.robot.variable(0) == 3  # no write-back
    assert rig.robot.system_register().zero


def test_nak_is_an_error_and_the_next_call_works(rig: Rig) -> None:
    with pytest.raises(NakError) as info:
        rig.client.division(Ram(VAR), Data(b"\x00\x00"))
    assert info.value.command == 0x09
    free_slot = rig.robot.allocation_table().index(None)
    with pytest.raises(NakError):
        rig.client.move(Com(), Ics(4, free_slot), 2)
    rig.client.acknowledge_check()


def test_communicate_device_is_opt_in(rig: Rig) -> None:
    with pytest.raises(CommandNotAllowedError):
        rig.client.communicate_device(0, 1, 0x0462, 0x0464)
    assert isinstance(CommandNotAllowedError("x"), PermissionError)
    if isinstance(rig.client, BlockingBridge):
        rig.client.inner.allow_communicate_device = True
        opted = rig.client
    else:
        opted = Rcb4Client(rig.client.transport, allow_communicate_device=True)
    with pytest.raises(NakError):  # the emulator refuses 0Eh, as the reference advises
        opted.communicate_device(0, 1, 0x0462, 0x0464)


def test_control_flow(rig: Rig) -> None:
    r = rig.robot
    r.stop_motion(reset=False)
    r.client.jump(0x0B80, Condition.if_zero())
    r.client.call(0x0B80)
    status = r.motion_status()
    assert status.call_depth == 1
    r.client.return_()
    assert r.motion_status().call_depth == 0
    with pytest.raises(NakError):
        r.client.return_()


def test_rom_read_write_verify_progress(rig: Rig) -> None:
    seen: list[tuple[int, int]] = []
    image = bytes(range(256)) * 2
    addr = 0x3F000 + 40  # unaligned start: first chunk is 24 bytes
    rig.robot.write_rom(addr, image, progress=lambda d, t: seen.append((d, t)))
    assert rig.robot.read_rom(addr, len(image)) == image
    assert seen[0] == (24, 512) and seen[-1] == (512, 512)
    assert all(b - a <= 64 for (a, _), (b, _) in zip([(0, 0), *seen], seen, strict=False))


def _lie(reply: Reply) -> Reply:
    """A data reply with its first byte flipped (what a failing ROM page would read back)."""
    if isinstance(reply, DataReply):
        return DataReply(reply.cmd, bytes((reply.data[0] ^ 1,)) + reply.data[1:])
    return reply


def test_rom_verify_detects_a_mismatch(rig: Rig, monkeypatch: pytest.MonkeyPatch) -> None:
    if isinstance(rig.client, BlockingBridge):
        inner = rig.client.inner
        real_async = inner.transact

        async def lying_async(command: Command, timeout: float | None = None) -> Reply:
            return _lie(await real_async(command, timeout))

        monkeypatch.setattr(inner, "transact", lying_async)
    else:
        real = rig.client.transact

        def lying(command: Command, timeout: float | None = None) -> Reply:
            return _lie(real(command, timeout))

        monkeypatch.setattr(rig.client, "transact", lying)
    with pytest.raises(VerifyError) as info:
        rig.client.write_rom(0x3F100, b"\x01\x02\x03")
    assert info.value.address == 0x3F100


def test_discover_servos_matches_the_board(rig: Rig) -> None:
    servos = rig.robot.discover_servos()
    alloc = rig.robot.allocation_table()
    assert servos, "the default image allocates servos"
    for s in servos:
        assert alloc[s.ics] == s.block_address
        raw = bytes(rig.board.ram[s.block_address : s.block_address + 20])
        assert raw[0] == 0 and s.block.output == int.from_bytes(raw[6:8], "little")
    assert 35 not in [s.ics for s in servos]


def test_bulk_positions_use_the_cheapest_plan(rig: Rig) -> None:
    r = rig.robot
    ids = r.servo_ids()
    frames_before = _frames(rig)
    pos = r.positions()
    used = _frames(rig) - frames_before
    blocks = [r._known()[k].block_address for k in ids]
    spans = [(a + 4, 2) for a in blocks]
    plan = r.read_plan()
    assert used == len(plan)
    assert plan == plan_cheapest(spans, r.link_cost)
    # never costlier than the fewest frames, nor than one frame per servo
    cost = r.link_cost.read_seconds
    assert cost(plan) <= cost(plan_reads(spans)) + 1e-12
    assert cost(plan) <= cost(spans) + 1e-12
    assert used < len(ids) / 3
    for k, p in pos.items():
        a = r._known()[k].block_address
        assert p == int.from_bytes(rig.board.ram[a + 4 : a + 6], "little")


def _frames(rig: Rig) -> int:
    return int(rig.board.frames_handled)


def _board_time(rig: Rig) -> float:
    return float(rig.board.virtual.now())


def test_timed_move_and_wait(rig: Rig) -> None:
    r = rig.robot
    k = r.servo_ids()[1]
    r.hold()
    r.interpolating([k])  # the poll below is a read like this one: count what one costs
    frames = _frames(rig)
    r.interpolating([k])
    poll = (_frames(rig) - frames) * STEP
    r.move_angles({k: 20.0}, duration=1.5)  # 100 periods of 15 ms
    t0 = _board_time(rig) - STEP  # the board handled the move frame, the last one, then
    assert k in r.interpolating()
    r.wait_interpolation([k], timeout=60.0)
    took = _board_time(rig) - t0
    # done once 1.5 s of board time have passed (the next output period), and seen by the
    # first poll after that
    assert 1.5 <= took <= 1.5 + r.output_period() + poll + STEP, took
    assert r.angles([k])[k] == pytest.approx(20.0, abs=0.05)
    assert r.angles([k], kind="output")[k] == pytest.approx(20.0, abs=0.05)


def test_wait_interpolation_times_out(rig: Rig) -> None:
    r = rig.robot
    k = r.servo_ids()[0]
    r.move({k: 9000}, duration=3.5)  # 233 periods of 15 ms: 70 polls at least
    t0 = time.monotonic()
    with pytest.raises(Rcb4TimeoutError):
        r.wait_interpolation([k], timeout=0.05)  # a few polls in 50 ms of real time
    # the timeout is real time (the thing under test here): its margin is a second of
    # scheduling delay, what a loaded runner (load 4 on two cores) can add
    assert time.monotonic() - t0 < 0.05 + 1.0
    assert k in r.interpolating()


def test_free_hold_neutral(rig: Rig) -> None:
    r = rig.robot
    r.free()
    assert {s.state for s in r.servo_states()} == {"free"}
    assert set(r.positions(kind="output").values()) == {POSITION_FREE}
    assert all(math.isnan(a) for a in r.angles(kind="output").values())
    r.hold(r.servo_ids()[:2])
    assert r.positions(r.servo_ids()[:2], kind="output") == dict.fromkeys(
        r.servo_ids()[:2], POSITION_HOLD
    )
    r.neutral(duration=0.1, wait=True)
    assert set(r.positions(kind="output").values()) == {7500}


def test_calibration_trim_and_direction(rig: Rig) -> None:
    from rcb4hv.client import Calibration

    k = rig.robot.servo_ids()[0]
    robot = rig.new_robot(calibration={k: Calibration(trim=100, direction=-1)})
    robot.move_angles({k: 10.0}, duration=0.0, wait=True)
    expected = round(7500 + 100 - 10.0 * 8000 / 270)
    assert robot.positions([k], kind="output")[k] == expected
    assert robot.angles([k], kind="output")[k] == pytest.approx(10.0, abs=0.05)


def test_stretch_and_speed(rig: Rig) -> None:
    ids = rig.robot.servo_ids()[:3]
    rig.robot.set_stretch(60, ids)
    rig.robot.set_speed({ids[0]: 100})
    assert all(rig.board.stretch[k] == 60 for k in ids)
    assert rig.board.speed_parameter[ids[0]] == 100
    with pytest.raises(ValueError):
        rig.robot.set_stretch(0, ids)


def test_play_motion_and_wait(rig: Rig) -> None:
    r = rig.robot
    r.play_motion(1)
    assert r.current_motion() == 1
    r.wait_motion(timeout=5.0)
    assert r.current_motion() is None
    status = r.motion_status()
    assert status.call_depth == 0
    assert r.system_register().rom_run


def test_stop_and_resume_motion(rig: Rig) -> None:
    r = rig.robot
    r.play_motion(1)
    r.stop_motion(reset=False)
    assert not r.system_register().rom_run
    assert r.current_motion() == 1
    r.resume_motion()
    r.wait_motion(timeout=5.0)
    r.play_motion(1)
    r.stop_motion()
    assert r.current_motion() is None
    assert r.motion_status().pc == r.board_layout().main_loop or r.system_register().rom_run


def test_a_motion_that_stops_the_program_is_reported_at_once(rig: Rig) -> None:
    """Playing a slot that holds no motion stops the board's program with a ROM error: the
    wait says so at once (it waited out its timeout for a motion "still playing")."""
    r = rig.robot
    empty = 50
    assert r.read_rom(r.board_layout().address(empty), 1) == b"\xff"
    t0 = time.monotonic()
    with pytest.raises(ProgramStoppedError, match=r"motion 50: .*ROM error") as info:
        r.play_motion(empty, wait=True, timeout=30.0)
    assert time.monotonic() - t0 < 10.0  # real time: far below the timeout
    assert info.value.motion == empty
    status = r.motion_status()
    assert status.rom_error and not status.running
    assert status.state == "stopped by a ROM error" and r.current_motion() is None
    r.stop_motion()  # the program runs on; ROMERR (until the main loop rewrites it) is no error
    r.play_motion(1, wait=True, timeout=30.0)
    assert r.motion_status().state == "idle"
    # HeartToHeart4's main loop begins by writing the system register: that clears ROMERR
    # (docs/spec-notes.md, "What clears ROMERR")
    assert not r.motion_status().rom_error


def test_a_move_to_a_servo_the_board_lacks_sends_nothing(rig: Rig) -> None:
    """A servo the board has not allocated is refused before the frame goes out: the servo
    that is there does not move either."""
    r = rig.robot
    k = r.servo_ids()[0]
    missing = r.allocation_table().index(None)
    with pytest.raises(ValueError, match=rf"no servo at ICS \[{missing}\]"):
        r.move({k: 9000, missing: 7500})
    with pytest.raises(ValueError, match=rf"no servo at ICS \[{missing}\]"):
        r.set_stretch({missing: 60})
    assert r.positions([k], kind="output")[k] != 9000
    assert k not in r.interpolating()


def test_wait_motion_times_out(rig: Rig) -> None:
    r = rig.robot
    r.play_motion(1)
    r.stop_motion(reset=False)
    with pytest.raises(Rcb4TimeoutError, match="motion 1"):
        r.wait_motion(timeout=0.05)


def test_buttons_and_pa(rig: Rig) -> None:
    r = rig.robot
    r.set_buttons(Button.UP | Button.S1)
    assert bytes(rig.board.ram[0x350:0x352]) == b"\x02\x01"  # high byte first
    assert r.buttons() == Button.UP | Button.S1
    r.press_button(Button.CIRCLE, duration=0.01)
    assert r.buttons() == Button.NONE
    r.set_pa(2, 200)
    assert r.pa_values()[1] == 200


def test_sensors_pio_timers_counters_variables(rig: Rig) -> None:
    r = rig.robot
    ad = r.ad_values()
    assert len(ad) == 11
    assert r.battery_voltage() == pytest.approx(ad[0] * 25 / 1024)
    r.set_pio_direction(0x00F)
    r.write_pio(0x005)
    assert r.pio() == (0x00F, 0x005)
    r.set_timer(1, 50)
    assert r.timer(1).running
    r.stop_timer(1)
    assert not r.timer(1).running
    r.set_counter(3, 77)
    assert r.counter(3) == 77
    r.set_variable(5, -1234)
    assert r.variable(5) == -1234
    assert r.variables()[5] == -1234


def test_system_register_typed(rig: Rig) -> None:
    r = rig.robot
    reg = r.system_register()
    assert isinstance(reg, SystemRegister)
    assert r.output_period() == reg.frame_period_ms / 1000
    info = r.info()
    assert info.version.startswith("CB-4")
    assert info.system.to_word() & ~0x0300 == reg.to_word() & ~0x0300
    assert info.describe()["servos"]


def test_concurrent_callers_are_serialised(rig: Rig) -> None:
    import threading

    errors: list[BaseException] = []

    def worker(n: int) -> None:
        try:
            for i in range(20):
                rig.robot.set_variable(n, i)
                assert rig.robot.variable(n) == i
        except BaseException as exc:  # pragma: no cover - reported below
            errors.append(exc)

    threads = [threading.Thread(target=worker, args=(n,)) for n in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []


def test_rom_constant_read(rig: Rig) -> None:
    assert rig.client.move(Com(), Rom(0), 9) == bytes(rig.board.rom[:9])
