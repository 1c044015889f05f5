"""Named settings of the emulated ICS servos: every choice a public source does not settle.

==========================  ============  =====================================================
setting                     default       evidence
==========================  ============  =====================================================
``version``                 ``"3.6"``     Read sc 5 (position) is ICS 3.6 only; Kondo's IcsClass
                                          says an ICS 3.5 servo does not answer it. iory/rcb4
                                          ``ics.py`` reads positions with it, and the KXR's
                                          KRS-3304R2 servos are ICS 3.6. ``"3.5"``: silent.
``eeprom_write_delay_s``    ``0.35``      FACTS: an EEPROM write's reply comes about 0.35 s
                                          after its echo (ICS 3.5 manual, 2015); the servo
                                          answers nothing else meanwhile.
``id_write_busy_s``         ``0.0``       Kondo's IcsClass waits 520 ms after *both* ID read and
                                          ID write; rcb4 reads the ID before every command with
                                          a 0.1 s timeout on real servos, so an ID read leaves
                                          no busy time. rcb4 notes one missed read right after
                                          an ID write: set this (e.g. 0.5) to model that.
``live_writes_persist``     ``False``     2011 vs 2015 manuals disagree. Off: sc 1-4 writes
                                          change the working value only (what the RCB-4's 12h,
                                          sent on every motion, needs: an EEPROM would wear
                                          out); the EEPROM keeps its value for power-on.
``current_scale_a``         ``0.1``       amperes per count of read sc 3 (0-63 forward, 64-127
                                          reverse: IcsClass ``getCur``); iory/rcb4
                                          ``get_current`` divides by 10. The 2011 manual's
                                          scale differs (FACTS); its figure is not public.
``temperature_points``      rcb4 table    (raw, degC) knots of iory/rcb4 ``temperature.py``:
                                          0 = 118 degC (hot) ... 127 = 26.7 degC; lower raw is
                                          hotter (IcsClass ``getTmp``: 0 hot, 127 cold).
``response_delay_s``        ``0.0``       the time a servo takes to answer after the command's
                                          last byte; no source gives a figure, and rcb4 waits
                                          the command's wire time + 2 ms before reading.
``id_collision``            ``"and"``     several servos answering an ID read at once: the
                                          wire-AND of their bytes (a UART line idles high, any
                                          transmitter pulls it low). Kondo: "unintended data".
==========================  ============  =====================================================
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Final, Literal

__all__ = ["RCB4_TEMPERATURE_POINTS", "IcsSettings"]

RCB4_TEMPERATURE_POINTS: Final = (
    (0, 118.0),
    (1, 117.06),
    (47, 90.0),
    (60, 80.0),
    (75, 70.0),
    (127, 26.67),
)


@dataclass(frozen=True, slots=True)
class IcsSettings:
    """How the emulated ICS servos behave where the sources disagree or say nothing."""

    version: Literal["3.5", "3.6"] = "3.6"
    eeprom_write_delay_s: float = 0.35
    id_write_busy_s: float = 0.0
    live_writes_persist: bool = False
    current_scale_a: float = 0.1
    temperature_points: tuple[tuple[int, float], ...] = RCB4_TEMPERATURE_POINTS
    response_delay_s: float = 0.0
    id_collision: Literal["and", "silent"] = "and"

    def __post_init__(self) -> None:
        if self.version not in ("3.5", "3.6"):
            raise ValueError("version must be '3.5' or '3.6'")
        if self.id_collision not in ("and", "silent"):
            raise ValueError("id_collision must be 'and' or 'silent'")
        for name in ("eeprom_write_delay_s", "id_write_busy_s", "response_delay_s"):
            v = getattr(self, name)
            if not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise ValueError(f"{name} must be a finite number >= 0")
        if not self.current_scale_a > 0:
            raise ValueError("current_scale_a must be > 0")
        pts = tuple((int(r), float(t)) for r, t in self.temperature_points)
        if len(pts) < 2 or any(b[0] <= a[0] or b[1] >= a[1] for a, b in itertools.pairwise(pts)):
            raise ValueError("temperature_points rise in raw value and fall in temperature")
        object.__setattr__(self, "temperature_points", pts)

    def current_raw(self, amperes: float) -> int:
        """Read-sc-3 value of a current: 0..63 forward, 64 + |I| for reverse."""
        n = min(63, round(abs(amperes) / self.current_scale_a))
        return n + 64 if amperes < 0 and n else n

    def temperature_raw(self, celsius: float) -> int:
        """Read-sc-4 value of a temperature (piecewise linear over ``temperature_points``)."""
        pts = self.temperature_points
        if celsius >= pts[0][1]:
            return pts[0][0]
        for (r0, t0), (r1, t1) in itertools.pairwise(pts):
            if celsius >= t1:
                return round(r0 + (t0 - celsius) * (r1 - r0) / (t0 - t1))
        return pts[-1][0]

    def temperature_c(self, raw: int) -> float:
        """The temperature of a read-sc-4 value."""
        pts = self.temperature_points
        for (r0, t0), (r1, t1) in itertools.pairwise(pts):
            if raw <= r1:
                return t0 + (max(raw, r0) - r0) * (t1 - t0) / (r1 - r0)
        return pts[-1][1]
