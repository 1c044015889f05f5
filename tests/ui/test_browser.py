"""The dashboard in a real browser (headless Chromium) against `rcb4hv ui` and the emulator."""

from __future__ import annotations

import re
import time
from typing import Any

import pytest

from rcb4hv.emulator import Board
from rcb4hv.ui.servos_page import COLUMNS
from tests.ui.conftest import shot

pytestmark = pytest.mark.slow


def _ram_word(b: Board, address: int) -> int:
    return int(b.ram[address]) | int(b.ram[address + 1]) << 8


def _output(b: Board, ics: int) -> int:
    blk = _ram_word(b, 0x44 + 2 * ics)
    return _ram_word(b, blk + 6)


def _field(page: Any, name: str) -> Any:
    """The native <input> of a NiceGUI input (Quasar puts data-testid on the input itself)."""
    return page.locator(f"input[data-testid={name}], [data-testid={name}] input").first


def _click_slider(page: Any, name: str, fraction: float, done: Any, drag: bool = False) -> None:
    """Click (or drag from the middle of) a slider's track to ``fraction`` until ``done()``
    (a tab switch animates the page, so a click during the transition may land beside the
    moving track; under load the first try may also come before the page is wired)."""
    slider = page.get_by_test_id(name)
    deadline = time.monotonic() + 20
    while True:
        slider.wait_for(state="visible")
        slider.scroll_into_view_if_needed()  # below the table and the 3D view on a narrow page
        box = slider.bounding_box()
        y = box["y"] + box["height"] / 2
        if drag:
            page.mouse.move(box["x"] + box["width"] / 2, y)
            page.mouse.down()
            page.mouse.move(box["x"] + box["width"] * fraction, y, steps=10)
            page.mouse.up()
        else:
            page.mouse.click(box["x"] + box["width"] * fraction, y)
        end = time.monotonic() + 3
        while time.monotonic() < end:
            if done():
                return
            time.sleep(0.05)
        assert time.monotonic() < deadline, f"{name}: the slider did not move the servo"


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
    page.get_by_test_id("tab-board").click()
    board_rows = page.get_by_test_id("board-table").locator("tbody tr")
    _wait(lambda: "CB-4" in board_rows.nth(3).inner_text())
    assert "1,250,000" in page.get_by_test_id("board-table").inner_text()  # detected baud
    shot(page, "board")


def test_slider_moves_a_servo(page: Any, board: tuple[Board, str]) -> None:
    b, _ = board
    page.get_by_test_id("tab-servos").click()
    before = _output(b, 2)
    _click_slider(page, "slider-2", 0.8, lambda: _output(b, 2) > 9000, drag=True)
    assert _output(b, 2) != before
    row = page.get_by_test_id("servo-table").locator("tbody tr").nth(1)
    measured = COLUMNS.index("measured")  # cells hold no spaces (joint names use "_")
    _wait(lambda: int(re.split(r"\s+", row.inner_text())[measured]) > 9000)


def test_triangle_plays_motion_1_and_the_plot_moves(page: Any) -> None:
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


def _open_project(page: Any, path: str) -> None:
    page.get_by_test_id("tab-project").click()
    page.get_by_test_id("project-upload").locator("input[type=file]").set_input_files(path)
    _wait(lambda: "65 motions" in page.get_by_test_id("project-summary").inner_text())


def test_project_opens_shows_a_motion_and_simulates(page: Any, kxr_project_path: Any) -> None:
    _open_project(page, str(kxr_project_path))
    table = page.get_by_test_id("project-motions")
    table.locator("tbody tr", has_text="XL2G_201").locator(".q-checkbox").click()
    _wait(lambda: "M021" in page.get_by_test_id("project-motion-title").inner_text())
    assert "RETURN" in page.get_by_test_id("project-disasm").inner_text()
    svg = page.get_by_test_id("flowchart-svg")
    assert svg.locator("rect.node").count() == 7
    shot(page, "project")
    page.get_by_text("Simulate / upload").click()
    page.get_by_test_id("project-simulate").click()
    _wait(lambda: "completed" in page.get_by_test_id("simulate-status").inner_text(), 30)
    assert "motion 21" in page.get_by_test_id("simulate-status").inner_text()
    shot(page, "simulate")


def test_a_file_that_is_no_project_is_refused_aloud(page: Any, tmp_path: Any) -> None:
    """The project box takes .h4p only, and says so when given another file (a flowchart
    .xml has its own box); the open project stays."""
    notes = tmp_path / "notes.txt"
    notes.write_text("not a project", encoding="utf-8")
    page.get_by_test_id("tab-project").click()
    before = page.get_by_test_id("project-summary").inner_text()
    page.get_by_test_id("project-upload").locator("input[type=file]").set_input_files(str(notes))
    _wait(lambda: page.get_by_text("not opened: a project is a .h4p file").count() > 0)
    assert page.get_by_test_id("project-summary").inner_text() == before


def test_a_refused_project_is_not_listed_as_uploaded(
    page: Any, tmp_path: Any, kxr_project_path: Any
) -> None:
    """A .h4p that does not parse was refused aloud, yet its box listed it with a tick next
    to the open project, as if it had been opened."""
    broken = tmp_path / "broken.h4p"
    broken.write_bytes(kxr_project_path.read_bytes()[:5000])
    _open_project(page, str(kxr_project_path))
    box = page.get_by_test_id("project-upload")
    box.locator("input[type=file]").set_input_files(str(broken))
    _wait(lambda: page.get_by_text("cannot open broken.h4p").count() > 0)
    _wait(lambda: "broken.h4p" not in box.inner_text())
    assert "65 motions" in page.get_by_test_id("project-summary").inner_text()
    assert ".h4p" in page.get_by_test_id("project-summary").inner_text()


def test_upload_writes_the_emulator_rom_with_progress(
    page: Any, board: tuple[Board, str], kxr_project_path: Any
) -> None:
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.image import build_project_image

    b, _ = board
    expected = build_project_image(load_project(kxr_project_path))
    assert bytes(b.rom) != expected
    page.get_by_test_id("tab-project").click()
    page.get_by_text("Simulate / upload").click()
    page.get_by_test_id("project-upload-rom").click()
    page.get_by_test_id("upload-confirm").click()
    bar = page.get_by_test_id("upload-progress")
    seen: set[float] = set()
    deadline = time.monotonic() + 120
    status = page.get_by_test_id("upload-status")
    while "upload done" not in status.inner_text():
        assert time.monotonic() < deadline, "upload did not finish"
        now = bar.get_attribute("aria-valuenow")
        if now is not None:
            seen.add(float(now))
        time.sleep(0.05)
    assert any(0 < v < 1 for v in seen), f"no intermediate progress seen: {sorted(seen)}"
    assert "verified" in status.inner_text()
    assert bytes(b.rom) == expected
    shot(page, "upload")


def test_teach_captures_poses_and_saves_a_motion_that_reloads(
    page: Any, board: tuple[Board, str], tmp_path: Any
) -> None:
    from rcb4hv.hth4 import dump_project, load_project
    from rcb4hv.project.image import build_project_image
    from rcb4hv.project.simulate import Simulator

    page.get_by_test_id("tab-teach").click()
    page.get_by_test_id("teach-capture").click()
    _wait(lambda: page.get_by_test_id("teach-count").inner_text() == "1 keyframes")
    # captured keyframes are work a reload would lose: the browser asks before leaving
    page.wait_for_function("typeof window.onbeforeunload === 'function'")
    page.get_by_test_id("tab-servos").click()
    b, _ = board
    _click_slider(page, "slider-2", 0.75, lambda: _output(b, 2) > 8500)
    time.sleep(0.3)
    page.get_by_test_id("tab-teach").click()
    page.get_by_test_id("teach-capture").click()
    _wait(lambda: page.get_by_test_id("teach-count").inner_text() == "2 keyframes")
    time_box = _field(page, "teach-time-1")
    time_box.fill("0.8")
    time_box.press("Tab")
    _field(page, "teach-name").fill("wave by hand")
    page.get_by_test_id("teach-save").click()
    _wait(lambda: "saved as motion" in page.get_by_test_id("teach-status").inner_text(), 30)
    page.wait_for_function("window.onbeforeunload === null")  # saved into the project
    text = page.get_by_test_id("teach-status").inner_text()
    slot = int(re.search(r"motion (\d+)", text).group(1))
    shot(page, "teach")
    with page.expect_download() as info:
        page.get_by_test_id("teach-download").click()
    path = tmp_path / "saved.h4p"
    info.value.save_as(str(path))
    project = load_project(path)
    assert dump_project(project) == path.read_bytes()
    m = project.motion(slot)
    assert m.name == "wave by hand" and len(m.frames) == 4
    sim = Simulator(build_project_image(project))
    sim.boot()
    result = sim.play(m.address, slot=slot)
    assert result.status == "completed"
    assert result.duration == pytest.approx(1.3, abs=0.1)
