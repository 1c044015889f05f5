"""Clocks injected into the board model: virtual time for tests, scaled real time for serving."""

from __future__ import annotations

import time
from typing import Protocol, runtime_checkable

__all__ = ["Clock", "RealClock", "VirtualClock"]


@runtime_checkable
class Clock(Protocol):
    """A monotonic source of board time in seconds."""

    def now(self) -> float: ...


class VirtualClock:
    """Time that moves only when told (``advance`` / ``set``)."""

    speed = 1.0

    def __init__(self, start: float = 0.0) -> None:
        if start < 0:
            raise ValueError("start must be >= 0")
        self._t = float(start)

    def now(self) -> float:
        return self._t

    def advance(self, seconds: float) -> None:
        if seconds < 0:
            raise ValueError("virtual time cannot go backwards")
        self._t += seconds

    def set(self, t: float) -> None:
        if t < self._t:
            raise ValueError("virtual time cannot go backwards")
        self._t = float(t)


class RealClock:
    """``time.monotonic()`` since construction, scaled by ``speed`` (> 0)."""

    def __init__(self, speed: float = 1.0) -> None:
        if not speed > 0:
            raise ValueError("speed must be > 0")
        self.speed = float(speed)
        self._t0 = time.monotonic()

    def now(self) -> float:
        return (time.monotonic() - self._t0) * self.speed
