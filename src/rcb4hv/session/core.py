"""The one owner of a board link: :class:`BoardSession`.

A session holds the :class:`~rcb4hv.client.Robot`, runs one worker thread that polls the
board at a set rate and executes every command (UI clicks, teach, uploads, ROM dumps) from one
queue, so nothing ever talks to the link concurrently and no caller's event loop blocks:

* :meth:`BoardSession.submit` queues ``fn(robot)`` and returns a
  :class:`concurrent.futures.Future`; :meth:`BoardSession.run` awaits the same from asyncio.
* :meth:`BoardSession.submit_steps` queues a long job written as a generator: the worker runs
  one step at a time and polls, moves and other commands run between the steps (a 256 KB ROM
  dump keeps the live view moving).
* :meth:`BoardSession.set_target` records a servo target; targets are coalesced and sent in one
  frame at most once per servo output period, so a dragged slider cannot flood the link.
* :meth:`BoardSession.stop` jumps the queue: stop the motion, then hold every servo.

A job's error goes to its future, and only there unless the link failed
(:func:`rcb4hv.session.jobs.judge`): a NAK, a ``wait_motion`` that ends with the motion still
playing, a program stopped by a ROM error or a refused command leave the link and the queue
alone. A link failure marks the state disconnected with the error text and fails every queued
job and pending move (:class:`~rcb4hv.errors.TransportError`): nothing clicked while the board
was away runs when it comes back (a "free all" would drop the robot then). While the link is
down, new jobs and moves are refused at once; the worker reopens the link every ``retry``
seconds until it answers again. Before the first attempt to connect, jobs wait for it.

Bad arguments raise :class:`~rcb4hv.errors.ArgumentError` at the call (the constructor's too:
a timeout, ``poll_hz``, ``retry``); after :meth:`BoardSession.close`, jobs and moves raise
:class:`~rcb4hv.errors.TransportError`. An unexpected error in one move or poll is logged and
kept in ``state.fault``: the worker runs on.
"""

from __future__ import annotations

import asyncio
import collections
import logging
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import replace
from typing import Any, TypeVar

from rcb4hv.client import HTH4_22, MotionLayout, Rcb4Client, Robot
from rcb4hv.client.args import check_link_args, finite, plain, seconds, servo_targets
from rcb4hv.client.exchange import check_timeout
from rcb4hv.errors import (
    ArgumentError,
    ArgumentTypeError,
    Rcb4Error,
    Rcb4TimeoutError,
    TransportError,
)
from rcb4hv.session.jobs import (
    Job,
    Progress,
    StepJob,
    Steps,
    answers,
    closed_while_running,
    fail_all,
    judge,
    rom_dump_steps,
)
from rcb4hv.session.meter import MeteredTransport
from rcb4hv.session.state import AngleHistory, BoardState, poll_state
from rcb4hv.transport import DEFAULT_BAUD, EMULATOR_URL, open_transport

__all__ = ["BoardSession", "Progress", "StepJob"]

log = logging.getLogger(__name__)

T = TypeVar("T")


class BoardSession:
    """``with BoardSession("rcb4emu://") as s: s.submit(lambda r: r.ping()).result()``.

    ``baudrate`` None detects the board's rate (serial ports only). ``poll_hz`` 0 disables
    polling. ``robot`` passes a ready Robot instead of opening ``url`` (the session then owns
    and closes it).
    """

    def __init__(
        self,
        url: str = EMULATOR_URL,
        *,
        baudrate: int | None = DEFAULT_BAUD,
        poll_hz: float = 10.0,
        layout: MotionLayout = HTH4_22,
        history_seconds: float = 10.0,
        retry: float = 1.0,
        timeout: float = 0.5,
    ) -> None:
        if not isinstance(url, str):
            raise ArgumentTypeError(f"url must be a str (a port or URL), not {plain(url)}")
        baudrate = check_link_args(url, baudrate)
        if finite("poll_hz", poll_hz) < 0:
            raise ArgumentError(f"poll_hz must be >= 0 (0: no polling), not {plain(poll_hz)}")
        history_seconds = seconds("history_seconds", history_seconds, allow_zero=False)
        retry = seconds("retry", retry, allow_zero=False)
        check_timeout(timeout)
        self.url = url
        self.baudrate = baudrate
        self.poll_hz = poll_hz
        self.layout = layout
        self.retry = retry
        self.timeout = timeout
        self.history = AngleHistory(history_seconds)
        self.state = BoardState(url=url)
        self.progress = Progress()
        self.meter: MeteredTransport | None = None
        self.robot: Robot | None = None
        self.latencies: collections.deque[float] = collections.deque(maxlen=10_000)
        self.moves_sent = 0
        self._jobs: collections.deque[Job] = collections.deque()
        self._steps: collections.deque[Steps] = collections.deque()
        self._targets: dict[int, int] = {}
        self._target_t: float | None = None
        self._last_move = 0.0
        self._period = 0.015
        self._cond = threading.Condition()
        self._closed = False
        self._thread: threading.Thread | None = None
        self._state_lock = threading.Lock()
        self._link_lock = threading.Lock()
        """Guards :attr:`robot` and the client being opened (close() closes either)."""
        self._opening: Rcb4Client | None = None
        self._reopen = False
        self._failures = 0
        """Failed attempts since the link was last up (only the first is logged as a
        warning, then a change of error, then the reconnect)."""
        self._down_since = 0.0
        self._last_error: BaseException | None = None

    # ------------------------------------------------------------------ lifecycle

    def start(self) -> BoardSession:
        """Start the worker (it opens the link); idempotent."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._worker, name="rcb4hv-session", daemon=True)
            self._thread.start()
        return self

    def close(self, timeout: float = 10.0) -> None:
        """Stop the worker, fail queued jobs, close the link; idempotent.

        The link is closed at once, under a job that is running: its next exchange with the
        board fails, and its future gets :class:`~rcb4hv.errors.TransportError` ("... was
        closed while this job ran"), so a ``wait_motion(timeout=30)`` ends within one
        exchange. Then close waits up to ``timeout`` seconds for the worker thread to end: only
        a job that keeps computing without the link can make it wait that long (close then
        logs a warning and returns; the worker ends when that job returns)."""
        check_timeout(timeout)
        with self._cond:
            self._closed = True
            self._cond.notify_all()
        with self._link_lock:
            opening = self._opening
        if opening is not None:
            opening.close()  # a link being opened: _connect fails at its next exchange
        self._disconnect()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout)
            if thread.is_alive():
                log.warning("closing %s: a job still running after %g s", self.url, timeout)
            else:
                self._thread = None
        self._fail_pending(TransportError(f"the board session for {self.url} is closed"))
        self._disconnect()

    def __enter__(self) -> BoardSession:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    def reconnect(self, url: str | None = None) -> None:
        """Close the link and open it again (to ``url`` when given) from the worker."""
        with self._cond:
            if url:
                self.url = url
            self._reopen = True
            self._cond.notify_all()

    def wait_connected(self, timeout: float = 5.0) -> BoardState:
        """Block until the first successful poll, or raise :class:`Rcb4TimeoutError` (a
        TimeoutError) with the link error (its ``__cause__`` the exception itself)."""
        check_timeout(timeout)
        deadline = time.monotonic() + timeout
        while not (self.state.connected and self.state.polls):
            if time.monotonic() > deadline:
                raise Rcb4TimeoutError(
                    f"no board at {self.url}: {self.state.error or 'no answer'}"
                ) from self._last_error
            time.sleep(0.01)
        return self.state

    # ------------------------------------------------------------------ commands

    def submit(
        self, fn: Callable[[Robot], T], *, urgent: bool = False, label: str = ""
    ) -> Future[T]:
        """Queue ``fn(robot)``; ``urgent`` puts it first. The future carries its result."""
        if not callable(fn):
            raise ArgumentTypeError(f"fn must be a callable taking the Robot, not {plain(fn)}")
        fut: Future[T] = Future()
        with self._cond:
            if self._closed:
                fut.set_exception(self._closed_error())
                return fut
            down = self._link_down()
            if down is not None:
                fut.set_exception(down)
                return fut
            job = Job(fn, fut, label)
            if urgent:
                self._jobs.appendleft(job)
            else:
                self._jobs.append(job)
            self._cond.notify_all()
        return fut

    async def run(self, fn: Callable[[Robot], T], *, urgent: bool = False) -> T:
        """``await`` :meth:`submit` without blocking the event loop."""
        return await asyncio.wrap_future(self.submit(fn, urgent=urgent))

    def submit_steps(self, make: Callable[[Robot], StepJob[T]], label: str) -> Future[T]:
        """Queue a long job: ``make(robot)`` returns a generator of ``(done, total)`` steps."""
        holder: Future[T] = Future()

        def start(robot: Robot) -> None:
            with self._cond:
                self._steps.append(Steps(make(robot), holder, label))

        started = self.submit(start, label=label)

        def forward(f: Future[None]) -> None:
            exc = f.exception()
            if exc is not None and not holder.done():
                holder.set_exception(exc)

        started.add_done_callback(forward)
        return holder

    def set_target(self, ics: int, position: int) -> None:
        """Move servo ``ics`` to raw ``position`` at the next output period (coalesced).
        ArgumentError for an ICS number outside 0..35 or a position outside 3500..11500 (or
        hold/free); TransportError once the session is closed or while the link is down."""
        ((ics, position),) = servo_targets({ics: position}, check_range=True).items()
        with self._cond:
            if self._closed:
                raise self._closed_error()
            down = self._link_down()
            if down is not None:
                raise down
            self._targets[ics] = position
            if self._target_t is None:
                self._target_t = time.perf_counter()
            self._cond.notify_all()

    def set_angle(self, ics: int, degrees: float) -> None:
        """Like :meth:`set_target` in degrees (the robot's host calibration applied)."""
        robot = self.robot
        if robot is None:
            raise self._link_down() or TransportError(f"no board connected at {self.url} yet")
        self.set_target(ics, robot.to_position(ics, degrees))

    def stop(self) -> Future[None]:
        """STOP: drop pending moves, stop the ROM motion, then hold every servo (urgent)."""
        with self._cond:
            self._targets.clear()
            self._target_t = None

        def do(robot: Robot) -> None:
            robot.stop_motion(reset=True)
            robot.set_buttons(0)
            if robot.servo_ids():
                robot.hold()

        return self.submit(do, urgent=True, label="stop")

    def rom_dump(self, chunk: int = 1024) -> Future[bytes]:
        """Read the whole 256 KB ROM as a long job (1 KB per step)."""
        return self.submit_steps(rom_dump_steps(chunk), "ROM dump")

    # ------------------------------------------------------------------ worker

    def _closed_error(self) -> TransportError:
        return TransportError(f"the board session for {self.url} is closed: not sent")

    def _link_down(self) -> TransportError | None:
        """The error to refuse a command with while the link is known to be down, else None
        (connected, or not tried yet)."""
        state = self.state
        if state.connected or state.error is None:
            return None
        return TransportError(f"no board connected at {self.url} ({state.error}): not sent")

    def _fail_pending(self, exc: BaseException) -> None:
        with self._cond:
            jobs, steps = list(self._jobs), list(self._steps)
            self._jobs.clear()
            self._steps.clear()
            self._targets.clear()
            self._target_t = None
        fail_all(jobs, steps, exc)
        self.progress = Progress()

    def _connect(self) -> None:
        transport = MeteredTransport(open_transport(self.url, self.baudrate or DEFAULT_BAUD))
        client = Rcb4Client(transport, timeout=self.timeout)
        with self._link_lock:
            self._opening = client
        try:
            if self._closed:
                raise self._closed_error()
            if self.baudrate is None:
                client.detect_baudrate()
            robot = Robot(client, layout=self.layout)
            version = client.get_version_info().text
            try:
                robot.wait_ready(timeout=3.0)
            except Rcb4Error as exc:  # a program that never reaches its main loop
                log.warning("%s: %s", self.url, exc)
            robot.discover_servos()
            self._period = robot.output_period(refresh=True)
            with self._link_lock:
                self._opening = None
                if self._closed:  # close() saw neither this client nor the robot
                    raise self._closed_error()
                self.meter, self.robot = transport, robot
        except BaseException:
            with self._link_lock:
                self._opening = None
            client.close()
            raise
        inner: Any = getattr(transport.inner, "baudrate", 0)
        self.state = replace(
            self.state, connected=True, error=None, version=version, baudrate=int(inner or 0)
        )
        if self._failures:
            down = time.monotonic() - self._down_since
            log.warning("link to %s is back after %d failed attempts over %.1f s (%s)",
                        self.url, self._failures, down, version)  # fmt: skip
        else:
            log.info("connected to %s (%s)", self.url, version)
        self._failures = 0

    def _disconnect(self, error: str | None = None) -> None:
        with self._link_lock:
            robot, self.robot = self.robot, None
        if robot is not None:
            try:
                robot.close()
            except Exception as exc:  # closing a broken link must not stop the worker
                log.warning("closing %s: %s", self.url, exc)
        if error is not None:
            self.state = replace(self.state, connected=False, error=error)

    def _link_failed(self, exc: BaseException) -> None:
        self._last_error = exc
        msg = f"{type(exc).__name__}: {exc}"
        if not self._failures:
            self._down_since = time.monotonic()
        self._failures += 1
        if self._failures == 1 or msg != self.state.error:  # news: warn once, not per retry
            log.warning("link to %s failed: %s (retrying every %g s; logged again when this "
                        "changes)", self.url, msg, self.retry)  # fmt: skip
        else:
            log.debug("link to %s still down (attempt %d): %s", self.url, self._failures, msg)
        self._disconnect(msg)
        self._fail_pending(TransportError(f"the link to {self.url} failed ({msg}): not sent"))

    def _worker(self) -> None:
        next_poll = 0.0
        while True:
            with self._cond:
                if self._closed:
                    return
                reopen, self._reopen = self._reopen, False
            if reopen:
                self._disconnect()
                self.state = BoardState(url=self.url)
                self._failures = 0
            if self.robot is None:
                try:
                    self._connect()
                    next_poll = 0.0
                except Exception as exc:  # a bad URL, a board that does not answer, a bug
                    if self._closed:
                        return
                    self._link_failed(exc)
                    with self._cond:
                        self._cond.wait(self.retry)
                    continue
            robot = self.robot
            if robot is None:  # close() took it
                continue
            try:
                self._work_once(robot)
                now = time.monotonic()
                if self.poll_hz and now >= next_poll and not self._closed:
                    self._poll(robot)
                    next_poll = max(next_poll + 1 / self.poll_hz, now)
            except (Rcb4Error, OSError) as exc:
                if not self._closed:  # close() closed the link under the worker: no failure
                    self._link_failed(exc)
                continue
            except Exception as exc:  # one bad move or poll must not end the worker
                if not self._closed:
                    self._fault(exc)
            self._idle(next_poll)

    def _fault(self, exc: Exception) -> None:
        """Log an unexpected error of the worker and show it in :attr:`state` (``fault``)."""
        log.error("session worker for %s: %s", self.url, exc, exc_info=exc)
        with self._state_lock:
            self.state = replace(self.state, fault=f"{type(exc).__name__}: {exc}")

    def _idle(self, next_poll: float) -> None:
        with self._cond:
            if self._jobs or self._steps or self._closed or self._reopen:
                return
            wake = next_poll if self.poll_hz else time.monotonic() + 1.0
            if self._targets:
                wake = min(wake, self._last_move + self._period)
            self._cond.wait(max(0.0, wake - time.monotonic()))

    def _work_once(self, robot: Robot) -> None:
        """One queued job, then the coalesced move, then one step of a long job."""
        with self._cond:
            job = self._jobs.popleft() if self._jobs else None
        if job is not None and job.future.set_running_or_notify_cancel():
            try:
                result = job.fn(robot)
            except Exception as exc:
                self._job_failed(robot, job.future, exc)
            else:
                job.future.set_result(result)
        if self._closed:
            return
        self._send_targets(robot)
        with self._cond:
            steps = self._steps[0] if self._steps else None
        if steps is not None:
            self._step(robot, steps)

    def _step(self, robot: Robot, s: Steps) -> None:
        try:
            done, total = next(s.gen)
            self.progress = Progress(s.label, done, total)
        except StopIteration as stop:
            self._end_steps(s)
            if not s.future.done():
                s.future.set_result(stop.value)
        except Exception as exc:
            self._end_steps(s)
            self._job_failed(robot, s.future, exc)

    def _job_failed(self, robot: Robot, future: Future[Any], exc: Exception) -> None:
        """Give a job's error to its future; re-raise it when the link failed (the worker
        then fails the queue and reopens). Anything else was that job's alone."""
        closed = self._closed  # close() closed the link under the job
        if not future.done():
            future.set_exception(closed_while_running(self.url, exc) if closed else exc)
        if closed:
            return
        verdict = judge(exc)
        if verdict == "link" or (verdict == "check" and not answers(robot)):
            raise exc

    def _end_steps(self, s: Steps) -> None:
        with self._cond:
            if self._steps and self._steps[0] is s:
                self._steps.popleft()
        self.progress = Progress()

    def _send_targets(self, robot: Robot) -> None:
        now = time.perf_counter()
        with self._cond:
            if not self._targets or now < self._last_move + self._period:
                return
            targets, t0 = dict(self._targets), self._target_t
            self._targets.clear()
            self._target_t = None
        robot.client.run_const_frame_servo(1, targets)
        self._last_move = time.perf_counter()
        self.moves_sent += 1
        if t0 is not None and self.meter is not None:
            self.latencies.append(self.meter.last_write - t0)

    def _poll(self, robot: Robot) -> None:
        if not robot.servo_ids() and self.state.polls % 10 == 0:
            robot.discover_servos()  # a freshly uploaded or booting program fills the table
        state = poll_state(robot, self.state, time.monotonic(), lambda: self._send_targets(robot))
        with self._state_lock:
            self.state = state
            self.history.add(state)
