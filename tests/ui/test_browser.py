"""The dashboard in a real browser (headless Chromium) against `rcb4hv ui` and the emulator."""

from __future__ import annotations

import re
import time
from typing import Any

import pytest

from rcb4hv.emulator import Board
from tests.ui.conftest import shot

pytestmark = pytest.mark.slow


def _ram_word(b: Board, address: int) -> int:
    return int(b.ram[address]) | int(b.ram[address + 1]) << 8


def _output(b: Board, ics: int) -> int:
    blk = _ram_word(b, 0x44 + 2 * ics)
    return _ram_word(b, blk + 6)


def _wait(cond: Any, timeout: float = 10.0) -> None:
    deadline = time.monotonic() + timeout
    while not cond():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.05)


def test_servo_table_fills(page: Any) -> None:
    page.get_by_test_id("tab-servos").click()
    table = page.get_by_test_id("servo-table")
    rows = table.locator("tbody tr")
    rows.nth(16).wait_for()
    assert rows.count() == 17
    assert "7500" in rows.nth(0).inner_text()
    shot(page, "servos")


def test_slider_moves_a_servo(page: Any, board: tuple[Board, str]) -> None:
    b, _ = board
    page.get_by_test_id("tab-servos").click()
    before = _output(b, 2)
    slider = page.get_by_test_id("slider-2")
    slider.click()  # the middle of the track: 0 degrees
    box = slider.bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] * 0.8, box["y"] + box["height"] / 2, steps=10)
    page.mouse.up()
    _wait(lambda: _output(b, 2) > 9000)
    assert _output(b, 2) != before
    row = page.get_by_test_id("servo-table").locator("tbody tr").nth(1)
    _wait(lambda: int(re.split(r"\s+", row.inner_text())[4]) > 9000)


def test_triangle_plays_motion_1_and_the_plot_moves(page: Any, board: tuple[Board, str]) -> None:
    b, _ = board
    page.get_by_test_id("tab-remote").click()
    pad = page.get_by_test_id("pad-triangle")
    pad.hover()
    page.mouse.down()
    _wait(lambda: page.get_by_test_id("remote-word").inner_text().endswith("0010h"))
    page.mouse.up()
    _wait(lambda: "motion: 1" in page.get_by_test_id("remote-motion").inner_text())
    _wait(lambda: page.get_by_test_id("remote-word").inner_text().endswith("0000h"))

    def ics3_range() -> float:
        m = re.search(r"ICS 3: ([0-9.]+)", page.get_by_test_id("remote-plot-spread").inner_text())
        return float(m.group(1)) if m else 0.0

    _wait(lambda: ics3_range() > 30)  # motion 1 lowers the right arm (ICS 3) by ~91 degrees
    shot(page, "remote")
    _wait(lambda: "motion: -" in page.get_by_test_id("remote-motion").inner_text(), 15)


def test_stop_stops_the_motion_and_holds(page: Any, board: tuple[Board, str]) -> None:
    b, _ = board
    page.get_by_test_id("tab-motions").click()
    page.get_by_test_id("motion-play").click()
    _wait(lambda: "current motion: 1" in page.get_by_test_id("motion-current").inner_text())
    page.get_by_test_id("stop").click()
    _wait(lambda: "current motion: -" in page.get_by_test_id("motion-current").inner_text())
    _wait(lambda: all(_output(b, k) == 0x7FFF for k in (0, 2, 3, 19)))
    shot(page, "motions")
