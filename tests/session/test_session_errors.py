"""BoardSession: a job's error that is not a failure of the link stays that job's (the link,
the board and the queue go on); close() interrupts a running job and ends the worker at once.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from rcb4hv.client import Robot
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, emulator_url
from rcb4hv.errors import (
    ChecksumError,
    CommandNotAllowedError,
    NakError,
    ProgramStoppedError,
    Rcb4TimeoutError,
    TransportError,
    VerifyError,
)
from rcb4hv.rom.default import DEFAULT_ICS, default_image
from rcb4hv.session import BoardSession
from rcb4hv.session.jobs import judge

LOGGER = "rcb4hv.session.core"


@pytest.fixture
def board() -> Iterator[Board]:
    b = Board(
        EmulatorConfig(virtual_servos=DEFAULT_ICS), clock=RealClock(), rom_image=default_image()
    )
    yield b
    b.close()


@pytest.fixture
def session(board: Board) -> Iterator[BoardSession]:
    with BoardSession(emulator_url(board), poll_hz=20, retry=30) as s:
        s.wait_connected()
        yield s


def _warnings(caplog: pytest.LogCaptureFixture) -> list[str]:
    return [r.getMessage() for r in caplog.records if r.name == LOGGER and r.levelno >= 30]


def _raise(exc: BaseException) -> Callable[[Robot], None]:
    def job(_robot: Robot) -> None:
        raise exc

    return job


def _motion_still_playing(r: Robot) -> None:
    r.play_motion(1)
    r.wait_motion(timeout=0.05)  # motion 1 plays for seconds: the wait ends first


def _ics_communication(r: Robot) -> None:
    r.client.communicate_device(2, 1, 0x462, 0x464)  # refused before any byte is sent


def _empty_motion_slot(r: Robot) -> None:
    r.play_motion(60, wait=True)  # slot 60 holds no motion: the program stops (ROMERR)


JOB_ERRORS: list[tuple[str, Callable[[Robot], Any], type[BaseException]]] = [
    ("wait_motion ends with the motion playing", _motion_still_playing, Rcb4TimeoutError),
    ("an empty motion slot", _empty_motion_slot, ProgramStoppedError),
    ("ICS communication not enabled", _ics_communication, CommandNotAllowedError),
    ("a failed verify", _raise(VerifyError("read back differs", 0x100)), VerifyError),
    ("a NAK", _raise(NakError("board answered NAK to Move", 0)), NakError),
    ("a wait that timed out", _raise(Rcb4TimeoutError("servos still moving")), Rcb4TimeoutError),
    ("a damaged reply, once", _raise(ChecksumError("bad sum")), ChecksumError),
    ("the job's own file", _raise(FileNotFoundError(2, "no such file")), FileNotFoundError),
]


@pytest.mark.parametrize(
    ("job", "error"), [c[1:] for c in JOB_ERRORS], ids=[c[0] for c in JOB_ERRORS]
)
def test_an_error_about_the_request_stays_that_jobs(
    session: BoardSession,
    caplog: pytest.LogCaptureFixture,
    job: Callable[[Robot], Any],
    error: type[BaseException],
) -> None:
    """Such an error dropped the link: the queued jobs failed ("the link ... failed ...: not
    sent"), a warning, a reopen (on rcb4emu:// a fresh board: RAM and variables lost)."""
    caplog.set_level(logging.INFO, logger=LOGGER)
    robot = session.robot
    session.submit(lambda r: r.set_variable(0, 1234)).result(timeout=5)
    failing = session.submit(job)
    queued = session.submit(lambda r: r.variables()[0])
    with pytest.raises(error):
        failing.result(timeout=5)
    assert queued.result(timeout=5) == 1234
    assert session.state.connected and session.state.error is None
    assert session.robot is robot  # the same link: never closed and reopened
    assert session.submit(lambda r: r.ping()).result(timeout=5) > 0
    assert _warnings(caplog) == []


def test_an_error_of_a_long_job_stays_that_jobs(session: BoardSession) -> None:
    robot = session.robot

    def steps(r: Robot) -> Iterator[tuple[int, int]]:
        yield 1, 2
        r.play_motion(60, wait=True)
        yield 2, 2

    failing = session.submit_steps(steps, "empty slot")  # type: ignore[arg-type]
    with pytest.raises(ProgramStoppedError):
        failing.result(timeout=5)
    assert session.submit(lambda r: r.ping()).result(timeout=5) > 0
    assert session.robot is robot and session.state.connected


def test_a_timeout_with_a_board_that_no_longer_answers_fails_the_link(
    session: BoardSession,
) -> None:
    """A timeout is checked with an ACK check: no answer, and it is a failure of the link."""
    started, release = threading.Event(), threading.Event()

    def link_breaks(r: Robot) -> None:
        started.set()
        release.wait(5)
        r.client.transport.close()  # the adapter is gone: nothing answers any more
        raise Rcb4TimeoutError("no reply to ReadRam within 0.5 s")

    broken = session.submit(link_breaks)
    assert started.wait(5)
    queued = session.submit(lambda r: r.ping())
    release.set()
    with pytest.raises(Rcb4TimeoutError, match="no reply"):
        broken.result(timeout=5)
    with pytest.raises(TransportError, match=r"failed .*no reply.*not sent"):
        queued.result(timeout=5)
    assert not session.state.connected


@pytest.mark.parametrize(
    ("exc", "verdict"),
    [
        (TransportError("port disconnected"), "link"),
        (Rcb4TimeoutError("no reply"), "check"),
        (ChecksumError("bad sum"), "check"),
        (OSError(5, "I/O error"), "check"),
        (VerifyError("differs", 0), "job"),
        (ProgramStoppedError("stopped", 0x100, 60), "job"),
        (CommandNotAllowedError("0Eh"), "job"),
        (NakError("NAK", 0), "job"),
        (ValueError("bad argument"), "job"),
        (RuntimeError("a bug in the job"), "job"),
    ],
)
def test_judge_reads_the_exception_tree(exc: BaseException, verdict: str) -> None:
    assert judge(exc) == verdict


def test_close_interrupts_a_running_job_and_ends_the_worker(
    board: Board, caplog: pytest.LogCaptureFixture
) -> None:
    """close() blocked 10 s, then closed the link under the job from the caller's thread: the
    worker lived on, the job failed with "the client is closed" and the session logged a
    link failure and retried after close."""
    caplog.set_level(logging.INFO, logger=LOGGER)
    s = BoardSession(emulator_url(board), poll_hz=20).start()
    s.wait_connected()
    thread = s._thread
    assert thread is not None
    waiting = threading.Event()

    def paused_motion(r: Robot) -> None:
        r.play_motion(1)
        r.stop_motion(reset=False)  # paused: wait_motion waits for it to its timeout
        r.wait_motion(timeout=30, on_poll=lambda _status: waiting.set())

    job = s.submit(paused_motion)
    queued = s.submit(lambda r: r.ping())
    assert waiting.wait(5)
    t0 = time.monotonic()
    s.close()
    took = time.monotonic() - t0
    assert not thread.is_alive()  # the worker is gone when close returns
    assert took < 2.0
    with pytest.raises(TransportError, match=r"session .* was closed while this job ran"):
        job.result(timeout=0)
    with pytest.raises(TransportError, match=r"session .* is closed"):
        queued.result(timeout=0)
    assert _warnings(caplog) == []
    assert s.robot is None
    s.close()  # idempotent


def test_close_waits_for_a_job_off_the_link_at_most_its_timeout(
    board: Board, caplog: pytest.LogCaptureFixture
) -> None:
    s = BoardSession(emulator_url(board), poll_hz=20).start()
    s.wait_connected()
    thread = s._thread
    assert thread is not None
    running, release = threading.Event(), threading.Event()

    def computes(_robot: Robot) -> str:
        running.set()
        release.wait(10)  # no exchange with the board that closing the link could end
        return "done"

    job = s.submit(computes)
    assert running.wait(5)
    s.close(timeout=0.05)
    assert thread.is_alive()
    assert any("still running" in w for w in _warnings(caplog))
    release.set()
    thread.join(5)
    assert not thread.is_alive()
    assert job.result(timeout=0) == "done"


def test_close_timeout_is_checked(session: BoardSession) -> None:
    with pytest.raises(ValueError, match="timeout"):
        session.close(timeout=0)
