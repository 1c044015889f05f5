"""What a :class:`~rcb4hv.session.BoardSession` runs for its callers, and how it reads a job's
error: a failure of the link (every queued job fails, the link is reopened) or of that job
alone (only its future gets the error).

:func:`judge` decides from :mod:`rcb4hv.errors`:

* ``"link"``: a :class:`~rcb4hv.errors.TransportError` (the port failed, closed or
  disconnected), except a :class:`~rcb4hv.errors.RomFileError` (the emulator runs on with the
  image in memory).
* ``"check"``: an error that means the board stopped answering *or* something else, which an
  ACK check then tells apart. :class:`~rcb4hv.errors.Rcb4TimeoutError` is both a reply that
  never came and a wait that ended before the board got there (``wait_motion``: the motion is
  still playing; ``wait_servos``, ``wait_ready``); a damaged reply
  (:class:`~rcb4hv.errors.ProtocolError` other than a :class:`~rcb4hv.errors.VerifyError`)
  is noise on a working line or a line that no longer works; an ``OSError`` that is no
  :class:`~rcb4hv.errors.Rcb4Error` is a port's own error or the job's (a file it opened).
* ``"job"``: everything else. The board answered, and the error is about the request or the
  board's state: :class:`~rcb4hv.errors.NakError`, :class:`~rcb4hv.errors.ProgramStoppedError`,
  :class:`~rcb4hv.errors.CommandNotAllowedError` (refused before any byte is sent),
  :class:`~rcb4hv.errors.VerifyError`, :class:`~rcb4hv.errors.ArgumentError`,
  :class:`~rcb4hv.errors.IcsError`, a file error, or any exception of the job's own code.
"""

from __future__ import annotations

import contextlib
import logging
from collections.abc import Callable, Generator, Iterable
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any, Literal, TypeVar

from rcb4hv.client import Robot
from rcb4hv.client.args import integer
from rcb4hv.errors import (
    ArgumentError,
    NakError,
    ProtocolError,
    Rcb4Error,
    Rcb4TimeoutError,
    RomFileError,
    TransportError,
    VerifyError,
)

__all__ = [
    "Job",
    "Progress",
    "StepJob",
    "Steps",
    "Verdict",
    "answers",
    "closed_while_running",
    "fail_all",
    "judge",
    "rom_dump_steps",
]

log = logging.getLogger(__name__)

T = TypeVar("T")

StepJob = Generator[tuple[int, int], None, T]
"""A long job: yields ``(done, total)`` after each short step and returns its result."""

Verdict = Literal["link", "check", "job"]


@dataclass(frozen=True, slots=True)
class Progress:
    """How far the current long job is (``total`` 0: none running)."""

    label: str = ""
    done: int = 0
    total: int = 0

    @property
    def fraction(self) -> float:
        return self.done / self.total if self.total else 0.0


@dataclass
class Job:
    """One queued ``fn(robot)``."""

    fn: Callable[[Robot], Any]
    future: Future[Any]
    label: str = ""


@dataclass
class Steps:
    """A long job being run one step at a time."""

    gen: Generator[tuple[int, int], None, Any]
    future: Future[Any]
    label: str


def judge(exc: BaseException) -> Verdict:
    """Whether the error ``exc`` of a job means the link failed (see the module's text)."""
    if isinstance(exc, Rcb4Error):
        if isinstance(exc, RomFileError | VerifyError):
            return "job"
        if isinstance(exc, TransportError):
            return "link"
        if isinstance(exc, Rcb4TimeoutError | ProtocolError):
            return "check"
        return "job"
    return "check" if isinstance(exc, OSError) else "job"


def answers(robot: Robot) -> bool:
    """Whether the board answers an ACK check (a NAK is an answer too): the test after a job's
    error judged ``"check"``."""
    try:
        robot.client.acknowledge_check()
    except NakError:
        pass
    except (Rcb4Error, OSError) as exc:
        log.debug("no answer to an ACK check after a job's error: %s", exc)
        return False
    return True


def closed_while_running(url: str, exc: BaseException) -> TransportError:
    """What a job's future gets when the session was closed under it (``exc``: how the job
    ended, usually "the client is closed"; also the ``__cause__``)."""
    err = TransportError(
        f"the board session for {url} was closed while this job ran ({type(exc).__name__}: {exc})"
    )
    err.__cause__ = exc
    return err


def fail_all(jobs: Iterable[Job], steps: Iterable[Steps], exc: BaseException) -> None:
    """Fail the futures of ``jobs`` and ``steps`` not done yet with ``exc``, ending the long
    jobs (one that is running in the worker ends there)."""
    for j in jobs:
        if not j.future.done():
            j.future.set_exception(exc)
    for s in steps:
        with contextlib.suppress(ValueError):  # "generator already executing"
            s.gen.close()
        if not s.future.done():
            s.future.set_exception(exc)


def rom_dump_steps(chunk: int) -> Callable[[Robot], StepJob[bytes]]:
    """The long job that reads the whole 256 KB ROM, ``chunk`` bytes a step (ArgumentError
    unless 1..256 KB)."""
    from rcb4hv.rom.layout import ROM_SIZE

    if not 0 < integer("chunk", chunk) <= ROM_SIZE:
        raise ArgumentError(f"chunk must be 1..{ROM_SIZE} bytes, not {chunk}")

    def job(robot: Robot) -> StepJob[bytes]:
        out = bytearray()
        while len(out) < ROM_SIZE:
            out += robot.read_rom(len(out), min(chunk, ROM_SIZE - len(out)))
            yield len(out), ROM_SIZE
        return bytes(out)

    return job
