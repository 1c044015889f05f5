"""Sample servo positions through the client in a background thread (for plots and logs)."""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from types import TracebackType
from typing import Literal

from rcb4hv.client.robot import Robot
from rcb4hv.errors import Rcb4Error

__all__ = ["PositionRecorder", "Sample"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True)
class Sample:
    t: float
    """Seconds since the recorder started."""
    angles: dict[int, float]
    """Degrees by ICS number."""
    label: str = ""


@dataclass
class PositionRecorder:
    """``with PositionRecorder(robot, period=0.02) as rec: ...`` then ``rec.samples``.

    Reads the selected servos' positions (one bulk read per sample, through the same client,
    which serialises it with the caller's commands) every ``period`` seconds. ``mark(label)``
    labels the following samples (e.g. the phase of a demo).
    """

    robot: Robot
    period: float = 0.02
    ics: Iterable[int] | None = None
    kind: Literal["measured", "output"] = "measured"
    samples: list[Sample] = field(default_factory=list)
    errors: int = 0

    def __post_init__(self) -> None:
        if not self.period > 0:
            raise ValueError("period must be > 0")
        self._sel = None if self.ics is None else sorted(set(self.ics))
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._label = ""
        self._t0 = 0.0
        self.marks: list[tuple[float, str]] = []

    def mark(self, label: str) -> None:
        self._label = label
        self.marks.append((time.monotonic() - self._t0, label))

    def start(self) -> None:
        if self._thread is not None:
            raise RuntimeError("recorder already started")
        self._t0 = time.monotonic()
        self._thread = threading.Thread(target=self._run, name="rcb4hv-recorder", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
            self._thread = None

    def _run(self) -> None:
        next_t = time.monotonic()
        while not self._stop.is_set():
            try:
                angles = self.robot.angles(self._sel, self.kind)
            except Rcb4Error as exc:
                self.errors += 1
                log.debug("recorder: %s", exc)
            else:
                self.samples.append(Sample(time.monotonic() - self._t0, angles, self._label))
            next_t += self.period
            delay = next_t - time.monotonic()
            if delay < 0:
                next_t = time.monotonic()
                delay = 0.0
            self._stop.wait(delay)

    def __enter__(self) -> PositionRecorder:
        self.start()
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.stop()
