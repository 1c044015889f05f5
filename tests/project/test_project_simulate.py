"""Simulating motions in virtual time: completion, waiting loops, held buttons, errors."""

from __future__ import annotations

import time

import pytest

from rcb4hv import hth4
from rcb4hv.emulator import EmulatorConfig
from rcb4hv.project.run import run_motions
from rcb4hv.project.simulate import PROGRESS_WINDOW, MotionResult, Simulator
from rcb4hv.protocol import (
    ALWAYS,
    Add,
    Button,
    Call,
    Data,
    Div,
    Ics,
    Jump,
    Move,
    Ram,
    Return,
)
from rcb4hv.protocol.memory import ADDR
from rcb4hv.rom import ImageDescription, ImageMotion, ImageServo, build_image, layout


@pytest.fixture(scope="module")
def kxr_results(kxr_project: hth4.Project, kxr_image: bytes) -> list[MotionResult]:
    names = {m.slot: m.name or "" for m in kxr_project.used_motions}
    run = run_motions(kxr_image, list(names), names=names)
    assert run.boot.status == "completed", run.boot
    return run.results


def test_every_fixture_motion_completes_or_waits(
    kxr_project: hth4.Project, kxr_results: list[MotionResult]
) -> None:
    assert len(kxr_results) == len(kxr_project.used_motions) == 65
    bad = [r for r in kxr_results if r.status not in ("completed", "waiting")]
    assert bad == []
    for r in kxr_results:
        assert r.error is None and r.duration > 0 and r.instructions > 0
    waiting = [r for r in kxr_results if r.status == "waiting"]
    # XL2G_292 (low battery) loops re-posing until a button is pressed: its own waiting loop
    assert [r.slot for r in waiting] == [40]
    (w,) = waiting
    assert w.inputs == ("buttons",)
    assert w.loop is not None
    lo, hi = w.loop
    assert layout.motion_address(40) <= lo < hi < layout.motion_address(41)


def test_a_waiting_loop_reports_time_and_instructions_of_one_moment(
    kxr_image: bytes, kxr_results: list[MotionResult]
) -> None:
    """XL2G_292 waits from 1.8 s, but its loop is recognised ~30 virtual seconds later: the
    instruction count was that of the recognition (166) beside the time of the entry (1.8 s).
    Both are the entry's now: no more than a run cut at a little after it has executed."""
    (w,) = [r for r in kxr_results if r.slot == 40]
    sim = Simulator(kxr_image)
    sim.boot()
    cut = sim.play(layout.motion_address(40), slot=40, limit=w.duration + 0.1)
    assert cut.status == "timeout"
    assert w.instructions <= cut.instructions


def test_fixture_durations_follow_the_poses(
    kxr_project: hth4.Project, kxr_results: list[MotionResult]
) -> None:
    # the home-position motion: one pose of speed 10 at 15 ms periods (+ one period)
    home = next(r for r in kxr_results if r.slot == 39)
    assert home.status == "completed"
    assert 0.150 <= home.duration <= 0.180
    # a motion with a 1 s timer wait takes longer than its poses alone
    pushups = next(r for r in kxr_results if r.slot == 23)
    assert pushups.status == "completed" and pushups.duration > 5.0


def _walk(project: hth4.Project) -> hth4.Motion:
    return next(
        m for m in project.used_motions if "歩行" in (m.name or "") and m.button_data == 0x0001
    )


def test_walk_loops_while_up_is_held(kxr_project: hth4.Project, kxr_image: bytes) -> None:
    walk = _walk(kxr_project)
    sim = Simulator(kxr_image)
    sim.boot()
    once = sim.play(walk.address, slot=walk.slot)
    assert once.status == "completed"
    held = {}
    for seconds in (2.0, 5.0):
        r = sim.play(walk.address, slot=walk.slot, hold=int(Button.UP), hold_for=seconds)
        assert r.status == "completed", r
        assert r.held is not None
        held[seconds] = r
        # it keeps walking while held and stops within about one gait cycle after release
        assert seconds <= r.duration <= seconds + 1.5
        assert r.instructions > once.instructions
    assert held[5.0].instructions > held[2.0].instructions
    # the button is released afterwards: the board's button word is 0 again
    assert sim.board.ram[0x0350:0x0352] == b"\x00\x00"


def _image(*motion_frames: list[object], servos: tuple[int, ...] = (2, 3)) -> bytes:
    desc = ImageDescription(
        system_register=0x821B,
        servos=tuple(ImageServo(i) for i in servos),
        motions=tuple(ImageMotion(n + 1, f) for n, f in enumerate(motion_frames)),  # type: ignore[arg-type]
    )
    return build_image(desc)


def _play(image: bytes, slot: int = 1, limit: float = 5.0) -> MotionResult:
    sim = Simulator(image)
    assert sim.boot().status == "completed"
    return sim.play(layout.motion_address(slot), limit=limit)


def test_call_stack_underflow_is_reported() -> None:
    # clear the call depth, then RETURN: the stack is empty
    img = _image([Move(Ram(0x0005), Data(b"\x00")), Return()])
    r = _play(img)
    assert r.status == "error"
    assert r.error is not None and "underflow" in r.error
    assert r.pc == layout.motion_address(1) + 8
    assert r.instruction == "RETURN"


def test_call_stack_overflow_is_reported() -> None:
    a = layout.motion_address(1)
    r = _play(_image([Call(a, ALWAYS)]))
    assert r.status == "error" and r.error is not None and "overflow" in r.error
    assert r.pc == a
    assert r.instruction is not None and r.instruction.startswith("CALL")


def test_command_error_names_the_unallocated_ics() -> None:
    r = _play(_image([Move(Ics(6, 30), Data(b"\x4c\x1d"))]))
    assert r.status == "error" and r.error is not None and "ICS 30" in r.error
    assert r.pc == layout.motion_address(1)
    assert r.instruction is not None and "ICS[30]" in r.instruction


def test_romerr_is_reported() -> None:
    img = bytearray(_image([Move(Ram(0x0462), Data(b"\x01\x00")), Return()]))
    a = layout.motion_address(1)
    img[a + img[a] - 1] ^= 0xFF  # break the first instruction's checksum
    r = _play(bytes(img))
    assert r.status == "error" and r.error is not None and "ROMERR" in r.error
    assert r.pc == a


def test_endless_loop_without_inputs_is_stalled_and_a_counter_times_out() -> None:
    a = layout.motion_address(1)
    r = _play(_image([Jump(a, ALWAYS)]))
    assert r.status == "stalled" and r.loop == (a, a + 6) and r.inputs == ()
    counter = [Add(Ram(0x0462), Data(b"\x01\x00")), Jump(a, ALWAYS)]
    r = _play(_image(counter), limit=2.0)
    assert r.status == "timeout" and abs(r.duration - 2.0) < 0.01
    assert a <= (r.pc or 0) < a + 16


def test_a_loop_without_progress_times_out_after_one_window() -> None:
    """No explicit limit: a loop that never recurs but changes nothing a motion's progress
    shows (servos, loop counters, variables; here only a temporary word) is a timeout after
    one progress window, not after the hour a progressing motion may take."""
    a = layout.motion_address(1)
    busy = [Add(Ram(ADDR.TEMPORARIES[0]), Data(b"\x01\x00")), Jump(a, ALWAYS)]
    sim = Simulator(_image(busy))
    assert sim.boot().status == "completed"
    t0 = time.perf_counter()
    r = sim.play(a)
    assert r.status == "timeout" and r.error == "no progress", r
    assert r.duration == pytest.approx(PROGRESS_WINDOW, abs=0.01)
    assert "without progress" in r.detail
    assert time.perf_counter() - t0 < 20  # one window of virtual time: well under a second


def test_button_poll_is_waiting() -> None:
    a = layout.motion_address(1)
    from rcb4hv.protocol import Condition, Sub

    poll = [Sub(Ram(0x0350), Data(b"\x00\x00"), None, True), Jump(a, Condition.if_zero()), Return()]
    r = _play(_image(poll))
    assert r.status == "waiting" and r.inputs == ("buttons",)
    assert r.loop == (a, a + 9 + 7 - 1)


def test_error_kind_is_the_boards_own_stop_record() -> None:
    # the reason comes from Board.last_stop: a division by zero (a stop the old heuristics
    # could only call "command error (program stopped)") is named
    img = _image([Div(Ram(0x0462), Data(b"\x00\x00")), Return()])
    sim = Simulator(img, config=EmulatorConfig(division_by_zero="error"))
    sim.boot()
    r = sim.play(layout.motion_address(1), limit=1.0)
    assert r.status == "error" and r.error == "command error: division by zero"
    assert r.pc == layout.motion_address(1) and r.instruction is not None
    stop = sim.board.last_stop
    assert stop is not None and stop.what == "command-error" and stop.where == r.pc


def test_a_program_that_clears_rom_f_itself_is_a_plain_stop() -> None:
    # MOVE RAM[0000h] <- 0000: the program stops itself; the board records no stop for it
    r = _play(_image([Move(Ram(0x0000), Data(b"\x00\x00")), Return()]))
    assert r.status == "error" and r.error == "program stopped (ROM_F cleared)"
