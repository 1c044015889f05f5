"""BoardSession: one owner of the link, polling, coalesced moves, STOP, long jobs."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator

import pytest

from rcb4hv.client import Robot
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, emulator_url
from rcb4hv.errors import TransportError
from rcb4hv.protocol.memory import ADDR, SERVO
from rcb4hv.rom.default import DEFAULT_ICS, default_image
from rcb4hv.session import BoardSession, MeteredTransport, wire_seconds


@pytest.fixture
def board() -> Iterator[Board]:
    b = Board(
        EmulatorConfig(virtual_servos=DEFAULT_ICS), clock=RealClock(), rom_image=default_image()
    )
    yield b
    b.close()


@pytest.fixture
def session(board: Board) -> Iterator[BoardSession]:
    with BoardSession(emulator_url(board), poll_hz=20) as s:
        s.wait_connected()
        yield s


ALLOC = ADDR.ICS_ALLOC


def output_of(board: Board, ics: int) -> int:
    """The output value in servo ``ics``'s block (through the allocation table)."""
    block = int.from_bytes(board.ram[ALLOC + 2 * ics : ALLOC + 2 * ics + 2], "little")
    return SERVO.F_OUTPUT.get(board.ram, block)


def _until(cond: object, timeout: float = 3.0) -> None:
    deadline = time.monotonic() + timeout
    while not cond():  # type: ignore[operator]
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.01)


def test_polls_fill_the_servo_table(session: BoardSession) -> None:
    state = session.state
    assert [s.ics for s in state.servos] == list(DEFAULT_ICS)
    assert state.version and state.rom_running
    first = state.polls
    _until(lambda: session.state.polls >= first + 3)
    assert session.history.samples


def test_targets_are_coalesced_into_one_frame_per_period(
    session: BoardSession, board: Board
) -> None:
    """Slider events that arrive while the worker is busy go out as one frame with the last
    value of each servo; its latency counts from the first of them."""
    busy, release = threading.Event(), threading.Event()

    def hold_the_worker(_robot: object) -> None:
        busy.set()
        release.wait(10)

    job = session.submit(hold_the_worker)
    assert busy.wait(10)
    sent, measured = session.moves_sent, len(session.latencies)
    session.set_target(2, 7600)
    after_first = time.perf_counter()
    for p in range(7610, 8600, 10):  # 99 more slider events in a burst
        session.set_target(2, p)
    session.set_target(3, 7000)
    released = time.perf_counter()
    release.set()
    job.result(timeout=10)
    _until(lambda: session.moves_sent > sent)
    _until(lambda: session.state.servo(2) is not None and session.state.servo(2).output == 8590)
    assert session.moves_sent - sent == 1
    assert output_of(board, 2) == 8590 and output_of(board, 3) == 7000
    assert len(session.latencies) == measured + 1
    assert session.latencies[-1] >= released - after_first


def test_range_checked_before_queueing(session: BoardSession) -> None:
    with pytest.raises(ValueError, match="outside 3500"):
        session.set_target(2, 20000)


def test_stop_stops_motion_then_holds(session: BoardSession) -> None:
    session.submit(lambda r: r.play_motion(1)).result(timeout=5)
    _until(lambda: session.state.motion == 1)
    session.stop().result(timeout=5)
    _until(lambda: session.state.motion is None)
    assert all(s.state == "hold" for s in session.state.servos)


def test_rom_dump_runs_in_steps_while_polling(session: BoardSession, board: Board) -> None:
    polls = session.state.polls
    fut = session.rom_dump(chunk=4096)
    seen = []
    while not fut.done():
        seen.append(session.progress.fraction)
        time.sleep(0.02)
    assert fut.result() == bytes(board.rom)
    assert session.state.polls > polls + 1  # the view kept updating during the dump
    assert any(0 < f < 1 for f in seen)


def test_errors_reach_the_caller_and_the_worker_survives(
    session: BoardSession, board: Board
) -> None:
    def boom(_robot: object) -> None:
        raise ValueError("bad argument")

    with pytest.raises(ValueError, match="bad argument"):
        session.submit(boom).result(timeout=5)
    table = session.submit(lambda r: r.read_ram(ALLOC, 2 * 36)).result(timeout=5)
    assert table == bytes(board.ram[ALLOC : ALLOC + 2 * 36])


def test_unreachable_board_reports_and_retries() -> None:
    with BoardSession("socket://127.0.0.1:9", poll_hz=10, retry=0.05) as s:
        _until(lambda: s.state.error is not None)
        assert not s.state.connected
        with pytest.raises(TimeoutError, match="no board"):
            s.wait_connected(timeout=0.2)
    assert threading.active_count() >= 1


def test_nothing_clicked_while_the_link_is_down_runs_when_it_comes_back(board: Board) -> None:
    """A link failure fails the queued jobs and drops pending moves; while the link is down new
    jobs and moves are refused at once (a "free all" queued then ran on reconnect and dropped
    the robot)."""
    with BoardSession(emulator_url(board), poll_hz=20, retry=30) as s:
        s.wait_connected()
        k = DEFAULT_ICS[0]
        started, release = threading.Event(), threading.Event()

        def link_breaks(robot: Robot) -> None:
            started.set()
            release.wait(5)
            robot.client.transport.close()  # the board no longer answers an ACK check
            raise OSError("the cable came out")

        broken = s.submit(link_breaks)
        assert started.wait(5)
        queued = s.submit(lambda r: r.free())
        s.set_target(k, 9000)
        release.set()
        with pytest.raises(OSError, match="cable"):
            broken.result(timeout=5)
        with pytest.raises(TransportError, match=r"failed .*not sent"):
            queued.result(timeout=5)
        assert not s.state.connected and s.state.error is not None
        with pytest.raises(TransportError, match="no board connected"):
            s.submit(lambda r: r.free()).result(timeout=1)
        with pytest.raises(TransportError, match="no board connected"):
            s.set_target(k, 9000)
        with pytest.raises(TransportError):
            s.stop().result(timeout=1)
        s.reconnect()
        s.wait_connected(timeout=10)
        time.sleep(0.2)  # a move left over would be sent now
        assert output_of(board, k) != 9000
        assert {st.state for st in s.submit(lambda r: r.servo_states()).result(5)} != {"free"}


def test_close_fails_pending_jobs() -> None:
    s = BoardSession("socket://127.0.0.1:9", retry=10)
    fut = s.submit(lambda r: r.ping())
    s.close()
    with pytest.raises(TransportError, match="closed"):
        fut.result(timeout=1)


def test_meter_counts_wire_time(session: BoardSession) -> None:
    assert isinstance(session.meter, MeteredTransport)
    w, r = session.meter.snapshot()
    assert w > 0 and r > 0
    assert wire_seconds(125_000, 1_375_000) == pytest.approx(1.0)
