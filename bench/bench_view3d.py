"""The 3D view under live polling, measured in the browser (headless Chromium, WebGL in
software through SwiftShader).

`rcb4hv ui` runs against an emulated board on TCP; servo 2 (the left shoulder) is set to hold
and swung back and forth by hand (:meth:`rcb4hv.emulator.Board.set_servo_position`, under
the server's lock), so every poll finds a new pose; Chromium shows the Servos page. In the
browser the robot object counts the poses it applies and the time it spends applying them
(``window.rcb4hvPoses``, ``window.rcb4hvPoseMs``, set in robot3d.js). Over a fixed number of
updates: updates per second against the poll rate (1.0 = one redraw per poll), and the
browser's time per update against the poll period.
"""

from __future__ import annotations

import importlib.util
import math
import threading
import time
from typing import Any

from tests.ui.browser import LAUNCH_ARGS, find_chromium, skip_requested, ui_server

from rcb4hv.emulator import Board, EmulatorConfig, RealClock, TcpServer
from rcb4hv.protocol import POSITION_HOLD
from rcb4hv.protocol.memory import CENTER, COUNTS_PER_DEGREE, SERVO
from rcb4hv.rom.default import DEFAULT_ICS, default_image

RATES_HZ = (10.0, 50.0)
"""The dashboard's default poll rate (target: a redraw for at least 90 % of the polls), and
a fast one to find the ceiling (no target: the session's own poll rate limits it)."""
UPDATES = 100
SWEEP_S = 2.0
"""One shoulder swing back and forth (±60°) every 2 s, a new target every 20 ms."""


def _sweep(srv: TcpServer, stop: threading.Event) -> None:
    board = srv.board
    with srv.lock:
        SERVO.F_OUTPUT.put(board.ram, board.alloc(2), POSITION_HOLD)  # hold: moved by hand
    t0 = time.monotonic()
    while not stop.is_set():
        phase = 2 * math.pi * (time.monotonic() - t0) / SWEEP_S
        degrees = 60.0 * math.sin(phase)
        with srv.lock:
            board.set_servo_position(2, round(CENTER + degrees * COUNTS_PER_DEGREE))
        time.sleep(0.02)


def _measure(page: Any, updates: int, timeout: float) -> tuple[float, float]:
    """(updates per second, ms per update in the browser) over the next ``updates``."""
    read = "() => [window.rcb4hvPoses || 0, window.rcb4hvPoseMs || 0]"
    n0, ms0 = page.evaluate(read)
    t0 = time.monotonic()
    deadline = t0 + timeout
    while True:
        n, ms = page.evaluate(read)
        if n - n0 >= updates or time.monotonic() > deadline:
            break
        time.sleep(0.05)
    dt = time.monotonic() - t0
    return (n - n0) / dt, (ms - ms0) / max(n - n0, 1)


def _rate(srv: TcpServer, chromium: str, poll_hz: float, updates: int) -> tuple[float, float]:
    from playwright.sync_api import sync_playwright

    host, port = srv.address
    with (
        ui_server(f"socket://{host}:{port}", "--poll-hz", str(poll_hz)) as app,
        sync_playwright() as pw,
    ):
        browser = pw.chromium.launch(executable_path=chromium, headless=True, args=LAUNCH_ARGS)
        page = browser.new_page(viewport={"width": 1400, "height": 900})
        page.goto(app)
        page.get_by_test_id("tab-servos").click()
        page.get_by_test_id("servos-3d").locator("canvas").wait_for()
        stop = threading.Event()
        mover = threading.Thread(target=_sweep, args=(srv, stop), daemon=True)
        mover.start()
        try:
            _measure(page, 5, 10.0)  # warm up: the first poses arrive
            return _measure(page, updates, 3 * updates / poll_hz)
        finally:
            stop.set()
            mover.join(timeout=5)
            browser.close()


def run(quick: bool = False) -> list[dict[str, Any]]:
    chromium = None if skip_requested() else find_chromium()
    if chromium is None or importlib.util.find_spec("playwright") is None:
        print(
            "(skipping the 3D view benchmark: needs Chromium (tools/ensure-browser) and "
            "playwright, and RCB4HV_SKIP_BROWSER unset)"
        )
        return []
    rates, updates = (RATES_HZ[:1], 5) if quick else (RATES_HZ, UPDATES)
    board = Board(
        EmulatorConfig(virtual_servos=DEFAULT_ICS), clock=RealClock(), rom_image=default_image()
    )
    rows: list[dict[str, Any]] = []
    with TcpServer(board, "127.0.0.1", 0) as srv:
        for hz in rates:
            per_s, ms = _rate(srv, chromium, hz, updates)
            period_us = 1e6 / hz
            rows.append(
                {
                    "name": f"3D view: updates/s in Chromium, polling at {hz:g} Hz",
                    "ours_us": 1e6 / per_s if per_s else math.inf,
                    "wire_us": period_us,
                    "ratio": per_s / hz,
                    "lower_is_better": False,
                    **({"target": 0.9} if hz == RATES_HZ[0] else {}),
                    "note": f"{per_s:.1f} updates/s over {updates} updates (ratio: per poll)",
                }
            )
            rows.append(
                {
                    "name": f"3D view: browser time per update at {hz:g} Hz",
                    "ours_us": ms * 1e3,
                    "wire_us": period_us,
                    "ratio": ms * 1e3 / period_us,
                    "note": "set_pose in robot3d.js (rendering runs on its own clock)",
                }
            )
    board.close()
    return rows


if __name__ == "__main__":
    for r in run():
        print(r)
