"""BoardSession: bad arguments are refused at the call; one bad job or move never ends the
worker; a closed session says so."""

from __future__ import annotations

import math
import time
from collections.abc import Iterator
from typing import Any

import pytest

from rcb4hv.client import Robot
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, emulator_url
from rcb4hv.errors import ArgumentError, ArgumentTypeError, Rcb4TimeoutError, TransportError
from rcb4hv.rom.default import DEFAULT_ICS, default_image
from rcb4hv.session import BoardSession


@pytest.fixture
def session() -> Iterator[BoardSession]:
    board = Board(
        EmulatorConfig(virtual_servos=DEFAULT_ICS), clock=RealClock(), rom_image=default_image()
    )
    with BoardSession(emulator_url(board), poll_hz=20) as s:
        s.wait_connected()
        yield s
    board.close()


def _until(cond: Any, timeout: float = 3.0) -> None:
    deadline = time.monotonic() + timeout
    while not cond():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.01)


@pytest.mark.parametrize(
    ("options", "what"),
    [
        ({"timeout": 0}, "a timeout is a number of seconds > 0"),
        ({"timeout": -1}, "a timeout is a number of seconds > 0"),
        ({"poll_hz": math.nan}, "poll_hz must be a finite number"),
        ({"poll_hz": math.inf}, "poll_hz must be a finite number"),
        ({"poll_hz": -1}, "poll_hz must be >= 0"),
        ({"retry": -1}, "retry must be a number of seconds > 0"),
        ({"retry": 0}, "retry must be a number of seconds > 0"),
        ({"history_seconds": -5}, "history_seconds must be a number of seconds > 0"),
        ({"url": 5}, "url must be a str"),
        ({"baudrate": "115200"}, "baudrate must be an int"),
    ],
)
def test_bad_arguments_are_refused_at_construction(options: dict[str, Any], what: str) -> None:
    with pytest.raises(ArgumentError, match=what):
        BoardSession(**options)


def test_a_bad_target_is_refused_at_the_call_and_the_worker_runs_on(
    session: BoardSession,
) -> None:
    """set_target(99, ...) was accepted, then killed the worker thread in the next move frame:
    every later job hung while the state said connected."""
    with pytest.raises(ArgumentError, match=r"ICS number 99 outside 0\.\.35"):
        session.set_target(99, 7500)
    with pytest.raises(ArgumentTypeError, match="ICS 2: position must be an int, not nan"):
        session.set_target(2, math.nan)  # type: ignore[arg-type]
    with pytest.raises(ArgumentError, match="ICS 2: angle must be a finite number, not inf"):
        session.set_angle(2, math.inf)
    with pytest.raises(ArgumentTypeError, match="fn must be a callable"):
        session.submit(5)  # type: ignore[arg-type]
    assert session.submit(lambda r: r.ping()).result(timeout=5) > 0


def test_an_unexpected_error_in_a_move_is_logged_and_shown_not_fatal(
    session: BoardSession, caplog: pytest.LogCaptureFixture
) -> None:
    robot: Robot = session.submit(lambda r: r).result(timeout=5)
    real = robot.client.run_const_frame_servo
    calls = 0

    def fails_once(*args: Any, **kwargs: Any) -> None:
        nonlocal calls
        calls += 1
        if calls == 1:
            raise RuntimeError("a bug in one move")
        real(*args, **kwargs)

    robot.client.run_const_frame_servo = fails_once  # type: ignore[method-assign]
    session.set_target(2, 8000)
    _until(lambda: session.state.fault is not None)
    assert session.state.fault == "RuntimeError: a bug in one move"
    assert "a bug in one move" in caplog.text
    assert session.state.connected
    assert session.submit(lambda r: r.ping()).result(timeout=5) > 0
    session.set_target(2, 8000)
    _until(lambda: calls >= 2)


def test_a_bad_url_times_out_as_rcb4_timeout_error_with_its_cause() -> None:
    with (
        BoardSession("rcb4emu://?bad=1", retry=10) as s,
        pytest.raises(Rcb4TimeoutError, match="unknown option 'bad'") as info,
    ):
        s.wait_connected(timeout=1.0)
    assert isinstance(info.value, TimeoutError)
    assert isinstance(info.value.__cause__, TransportError)


def test_a_closed_session_refuses_moves_and_jobs(session: BoardSession) -> None:
    session.close()
    with pytest.raises(TransportError, match=r"session .* is closed"):
        session.set_target(2, 7500)
    with pytest.raises(TransportError, match=r"session .* is closed"):
        session.submit(lambda r: r.ping()).result(timeout=1)
