"""Clocks injected into the board model: virtual time for tests, scaled real time for serving.

The clock owns time and its conversions (trio's ``Clock``/``MockClock`` is the model): the
board counts in *board seconds* (:meth:`Clock.now`) and asks the clock how many *real*
seconds a stretch of board time takes (:meth:`Clock.real_seconds`, for a server's wait) and
how much board time a real duration covers (:meth:`Clock.board_seconds`, for the frame
timeout, which is a property of the serial line and so of real time).
"""

from __future__ import annotations

import math
import time
from typing import Protocol, runtime_checkable

from rcb4hv.errors import ArgumentError

__all__ = ["Clock", "RealClock", "ScaledClock", "VirtualClock"]


@runtime_checkable
class Clock(Protocol):
    """A monotonic source of board time in seconds, running ``speed`` times real time."""

    @property
    def speed(self) -> float:
        """Board seconds per real second (> 0)."""
        ...

    def now(self) -> float:
        """The current board time in seconds."""
        ...

    def real_seconds(self, board_seconds: float) -> float:
        """Real seconds that ``board_seconds`` of board time take."""
        ...

    def board_seconds(self, real_seconds: float) -> float:
        """Board seconds that pass in ``real_seconds`` of real time."""
        ...


class ScaledClock:
    """The conversions of a clock running ``speed`` times real time."""

    speed: float = 1.0

    def real_seconds(self, board_seconds: float) -> float:
        return board_seconds / self.speed

    def board_seconds(self, real_seconds: float) -> float:
        return real_seconds * self.speed


class VirtualClock(ScaledClock):
    """Time that moves only when told (``advance`` / ``set``); nominally at real speed."""

    def __init__(self, start: float = 0.0) -> None:
        if not 0 <= start < math.inf:
            raise ArgumentError(f"start must be a finite number of seconds >= 0, not {start!r}")
        self._t = float(start)

    def now(self) -> float:
        return self._t

    def advance(self, seconds: float) -> None:
        if not 0 <= seconds < math.inf:
            raise ArgumentError(
                f"virtual time advances by a finite number of seconds >= 0, not {seconds!r}"
            )
        self._t += seconds

    def set(self, t: float) -> None:
        if not self._t <= t < math.inf:
            raise ArgumentError(f"virtual time cannot go backwards or past every end, to {t!r}")
        self._t = float(t)


class RealClock(ScaledClock):
    """``time.monotonic()`` since construction, scaled by ``speed`` (> 0)."""

    def __init__(self, speed: float = 1.0) -> None:
        if not 0 < speed < math.inf:
            raise ArgumentError(f"speed must be a finite number > 0, not {speed!r}")
        self.speed = float(speed)
        self._t0 = time.monotonic()

    def now(self) -> float:
        return (time.monotonic() - self._t0) * self.speed
