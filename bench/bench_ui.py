"""The dashboard's load on the link and its slider latency (``rcb4hv ui``'s BoardSession).

* Polling load: a session polls the default board (17 servos) at 10 Hz against the in-process
  emulator; the bytes it moves per second are converted to wire time at 1,250,000 baud
  (8E1, 11 bits a byte) and compared with one second: the fraction of the link the live view takes.
* Slider latency: slider events arrive at 60 Hz (a drag) while the session polls; each
  coalesced servo frame's latency is from the first event it carries to the moment the frame
  is written to the link. Compared with the servo output period (15 ms on the default board),
  the most coalescing may add.
"""

from __future__ import annotations

import statistics
import time
from typing import Any

from rcb4hv.session import BoardSession, wire_seconds

BAUD = 1_250_000
POLL_HZ = 10.0


def _polling_load(seconds: float = 3.0) -> tuple[float, int, int]:
    with BoardSession("rcb4emu://", poll_hz=POLL_HZ) as s:
        s.wait_connected(timeout=10)
        assert s.meter is not None
        servos = len(s.state.servos)
        w0, r0 = s.meter.snapshot()
        p0, t0 = s.state.polls, time.monotonic()
        time.sleep(seconds)
        w1, r1 = s.meter.snapshot()
        polls, dt = s.state.polls - p0, time.monotonic() - t0
    per_second = (w1 - w0 + r1 - r0) / dt
    return wire_seconds(round(per_second), BAUD), servos, round(polls / dt)


def _slider_latency(seconds: float = 3.0) -> tuple[list[float], float, int, int]:
    with BoardSession("rcb4emu://", poll_hz=POLL_HZ) as s:
        s.wait_connected(timeout=10)
        period = s.robot.output_period() if s.robot is not None else 0.015
        s.latencies.clear()
        events = 0
        t_end = time.monotonic() + seconds
        position = 7500
        while time.monotonic() < t_end:
            position = 7000 + (position + 37) % 1000
            s.set_target(2, position)
            events += 1
            time.sleep(1 / 60)
        time.sleep(0.1)
        return list(s.latencies), period, events, s.moves_sent


def run(quick: bool = False) -> list[dict[str, Any]]:
    seconds = 0.3 if quick else 3.0
    fraction, servos, rate = _polling_load(seconds)
    lat, period, events, frames = _slider_latency(seconds)
    lat_us = sorted(x * 1e6 for x in lat)
    median = statistics.median(lat_us)
    p99 = lat_us[min(len(lat_us) - 1, round(0.99 * (len(lat_us) - 1)))]
    period_us = period * 1e6
    note = f"{events} slider events -> {frames} frames"
    return [
        {
            "name": f"ui polling: wire time/s, {servos} servos at {rate} Hz",
            "ours_us": fraction * 1e6,
            "wire_us": 1e6,
            "ratio": fraction,
            "target": 0.1,
            "note": "fraction of the 1,250,000-baud link the live view uses",
        },
        {
            "name": "ui slider -> frame on the wire, median",
            "ours_us": median,
            "wire_us": period_us,
            "ratio": median / period_us,
            "target": 1.0,
            "note": note,
        },
        {
            "name": "ui slider -> frame on the wire, p99",
            "ours_us": p99,
            "wire_us": period_us,
            "ratio": p99 / period_us,
            "target": 2.0,
            "note": note,
        },
    ]


if __name__ == "__main__":
    for r in run():
        print(r)
