"""The 3D view in a real browser (headless Chromium, WebGL in software through SwiftShader):
it draws the robot, follows a moving servo, and previews a project motion."""

from __future__ import annotations

import io
import time
from collections import Counter
from typing import Any

import pytest

from rcb4hv.emulator import Board
from tests.ui.browser import SHOTS
from tests.ui.test_browser import _click_slider, _open_project, _output, _wait

pytestmark = pytest.mark.slow


def _pixels(png: bytes) -> list[tuple[int, int, int]]:
    from PIL import Image

    raw = Image.open(io.BytesIO(png)).convert("RGB").tobytes()
    return [(raw[i], raw[i + 1], raw[i + 2]) for i in range(0, len(raw), 3)]


def _canvas(page: Any, name: str) -> Any:
    canvas = page.get_by_test_id(name).locator("canvas").first
    canvas.wait_for(state="visible")
    return canvas


def _shot(canvas: Any) -> bytes:
    """A screenshot of ``canvas`` at whole pixels (the page may shift it by a fraction)."""
    box = canvas.bounding_box()
    clip = {k: round(box[k]) for k in ("x", "y", "width", "height")}
    return bytes(canvas.page.screenshot(clip=clip))


def _still(canvas: Any, timeout: float = 10.0) -> bytes:
    """A screenshot of ``canvas`` once two in a row agree (the pose has settled)."""
    deadline = time.monotonic() + timeout
    last = _shot(canvas)
    while True:
        time.sleep(0.3)
        now = _shot(canvas)
        if now == last:
            return now
        assert time.monotonic() < deadline, "the 3D view never settled"
        last = now


def _changed(a: bytes, b: bytes) -> int:
    return sum(p != q for p, q in zip(_pixels(a), _pixels(b), strict=True))


def _save(canvas_png: bytes, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    (SHOTS / f"{name}.png").write_bytes(canvas_png)


def test_the_canvas_draws_the_robot_and_the_ground(page: Any) -> None:
    page.get_by_test_id("tab-servos").click()
    _wait(lambda: "KHR-3HV" in page.get_by_test_id("servos-3d-caption").inner_text())
    png = _still(_canvas(page, "servos-3d"))
    pixels = _pixels(png)
    counts = Counter(pixels)
    n = counts.most_common(1)[0][1]
    drawn = 1 - n / len(pixels)
    colours = set(counts)
    # a blank canvas is one colour; the shaded robot, grid and ground make hundreds
    assert len(colours) > 100, f"only {len(colours)} colours: the canvas looks blank"
    assert drawn > 0.2, f"only {drawn:.0%} of the canvas differs from its background"
    _save(png, "3d-view")


def test_the_view_follows_a_servo(page: Any, board: tuple[Board, str]) -> None:
    b, _ = board
    page.get_by_test_id("tab-servos").click()
    canvas = _canvas(page, "servos-3d")
    before = _still(canvas)
    assert _changed(before, _still(canvas)) == 0  # nothing moves: the picture is the same
    # ICS 2: the left shoulder pitch of a KHR-3HV
    _click_slider(page, "slider-2", 0.85, lambda: _output(b, 2) > 9000)
    canvas.scroll_into_view_if_needed()  # the sliders are below it
    after = _still(canvas)
    moved = _changed(before, after)
    assert moved > 500, f"only {moved} pixels changed after the arm moved"
    page.screenshot(path=str(SHOTS / "servos-3d.png"))


def test_the_remote_page_shows_motion_1_raise_the_arms(page: Any) -> None:
    page.get_by_test_id("tab-remote").click()
    canvas = _canvas(page, "remote-3d")
    home = _still(canvas)
    assert len(set(_pixels(home))) > 100
    page.get_by_test_id("pad-triangle").hover()
    page.mouse.down()
    page.mouse.up()
    most = 0
    deadline = time.monotonic() + 10
    while most < 2000 and time.monotonic() < deadline:  # while the arms are up
        most = max(most, _changed(home, _shot(canvas)))
    assert most >= 2000, f"at most {most} pixels changed while motion 1 played"


def test_a_project_motion_previews_and_scrubs(page: Any, kxr_project_path: Any) -> None:
    _open_project(page, str(kxr_project_path))
    table = page.get_by_test_id("project-motions")
    table.locator("tbody tr", has_text="XL2G_201").locator(".q-checkbox").click()
    page.get_by_test_id("project-tab-preview").click()
    physics = page.get_by_test_id("preview-physics")
    if physics.get_attribute("aria-checked") == "true":
        physics.click()  # the plain simulator: the same picture on every machine
    page.get_by_test_id("preview-run").click()
    _wait(lambda: "completed" in page.get_by_test_id("preview-info").inner_text(), 30)
    canvas = _canvas(page, "preview-3d")
    page.get_by_test_id("preview-play").click()  # pause
    _wait(lambda: "play" in page.get_by_test_id("preview-play").inner_text().lower())
    scrubber = page.get_by_test_id("preview-scrubber")
    box = scrubber.bounding_box()
    status = page.get_by_test_id("preview-status")
    poses = "() => window.rcb4hvPoses || 0"
    frames = []
    for fraction in (0.02, 0.5):
        shown, drawn = status.inner_text(), page.evaluate(poses)
        page.mouse.click(box["x"] + box["width"] * fraction, box["y"] + box["height"] / 2)
        # the server has moved the player (its time changed); near the start the pose may be
        # the one shown already (nothing is sent then), in mid-motion the browser draws a new one
        _wait(lambda s=shown: status.inner_text() != s)
        if frames:
            _wait(lambda d=drawn: page.evaluate(poses) > d)
        frames.append(_still(canvas))
    assert _changed(frames[0], frames[1]) > 500  # the greeting moves the arms
    # for the docs: the controls and the view
    page.set_viewport_size({"width": 1400, "height": 1200})
    page.evaluate("window.scrollTo(0, 0)")
    _still(canvas)
    top = page.get_by_test_id("preview-run").bounding_box()["y"] - 12
    view = canvas.bounding_box()
    bottom = view["y"] + view["height"] + 12
    clip = {"x": 0, "y": top, "width": 1400, "height": bottom - top}
    page.screenshot(path=str(SHOTS / "3d-preview.png"), clip=clip)
