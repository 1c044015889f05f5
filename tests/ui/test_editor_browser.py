"""The Editor page in headless Chromium: open the fixture project, change one pose, mirror
another motion into a free slot, save; then `project diff` shows exactly those changes and the
saved file builds and simulates."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from rcb4hv import hth4
from rcb4hv.project.image import build_project_image
from rcb4hv.project.run import run_motions
from tests.ui.browser import LAUNCH_ARGS, PAGE_LOAD_MS
from tests.ui.conftest import shot

pytestmark = pytest.mark.slow

WALK, TURN_LEFT, FREE = 66, 69, 73
WEBGL = [a for a in LAUNCH_ARGS if a != "--disable-gpu"] + [
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
]
"""Software WebGL, so the 3D view draws in the headless browser."""


@pytest.fixture(scope="module")
def gl_browser(chromium_path: str) -> Iterator[Any]:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=chromium_path, headless=True, args=WEBGL)
        yield b
        b.close()


@pytest.fixture
def gl_page(gl_browser: Any, app_url: str) -> Iterator[Any]:
    context = gl_browser.new_context(viewport={"width": 1500, "height": 1000})
    pg = context.new_page()
    pg.set_default_timeout(40_000)
    pg.goto(app_url, timeout=PAGE_LOAD_MS)
    pg.get_by_test_id("stop").wait_for(timeout=PAGE_LOAD_MS)
    yield pg
    context.close()


def _input(page: Any, name: str) -> Any:
    return page.locator(f"input[data-testid={name}], [data-testid={name}] input").first


def _choose(page: Any, name: str, text: str) -> None:
    """Pick an option of a select with input: type its start (the list is virtual), click it."""
    field = _input(page, name)
    option = page.get_by_role("option", name=text).first
    deadline = time.monotonic() + 40
    while True:  # the options may reach the browser after the first filtering: type again
        field.click()
        field.fill(text[:4])
        try:
            option.wait_for(state="visible", timeout=5_000)
            break
        except Exception:  # playwright's TimeoutError
            assert time.monotonic() < deadline, f"{name}: no option {text!r}"
            page.keyboard.press("Escape")
    option.click()


def _chart_of(page: Any, address: int) -> None:
    """Wait until the flowchart drawn is the motion at ROM ``address``."""
    chart = page.get_by_test_id("editor-flowchart")
    chart.get_by_text(f"{address:05X} ").first.wait_for()


def _wait_text(page: Any, name: str, text: str, timeout: float = 40.0) -> None:
    deadline = time.monotonic() + timeout
    while text not in page.get_by_test_id(name).inner_text():
        assert time.monotonic() < deadline, f"{name}: no {text!r} in time"
        time.sleep(0.1)


def test_editor_in_the_browser(gl_page: Any, kxr_project_path: Path, tmp_path: Path) -> None:
    page = gl_page
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())
    out = tmp_path / "edited.h4p"
    page.get_by_test_id("tab-editor").click()
    _input(page, "editor-path").fill(str(src))
    page.get_by_test_id("editor-open").click()
    _wait_text(page, "editor-status", "no edits")
    # change one pose: WALK, pose 2 (clicked in the flowchart), ICS 10 -> 7700
    _choose(page, "editor-motion", f"M{WALK:03d} HAC_KXR_WALK_FORWARD")
    _chart_of(page, 0x21380)  # slot 66 starts at 0B80h + 65 * 800h
    page.locator("[data-testid=editor-flowchart] g[data-pose='1']").click()
    raw = _input(page, "editor-raw-10")
    deadline = time.monotonic() + 40
    while raw.input_value() != "7900":
        assert time.monotonic() < deadline, "pose 2 not selected"
        time.sleep(0.1)
    raw.fill("7700")
    raw.press("Tab")
    _wait_text(page, "editor-status", "1 edit ")
    assert (
        page.locator("[data-testid=editor-flowchart] g[data-pose='1'] rect").get_attribute("fill")
        == "#bbdefb"
    )
    # mirror TURN_LEFT into the free slot
    _choose(page, "editor-motion", f"M{TURN_LEFT:03d} HAC_KXR_TURN_LEFT")
    _choose(page, "editor-mirror-to", f"M{FREE:03d} (free)")
    _input(page, "editor-mirror-name").fill("TURN_RIGHT_MIRROR")
    page.get_by_test_id("editor-mirror-motion").click()
    _wait_text(page, "editor-status", "2 edits")
    _choose(page, "editor-motion", f"M{FREE:03d} TURN_RIGHT_MIRROR")
    _chart_of(page, 0x24B80)  # slot 73
    page.locator("[data-testid=editor-flowchart] g[data-pose='0']").click()
    page.get_by_test_id("editor-3d").wait_for()
    time.sleep(1.0)  # let three.js draw the pose
    shot(page, "editor")
    # the browser is asked to confirm leaving while there are unsaved changes
    assert page.evaluate("typeof window.onbeforeunload") == "function"
    _input(page, "editor-path").fill(str(out))
    page.get_by_test_id("editor-save").click()
    _wait_text(page, "editor-status", f"{out} - 2 edits - saved")
    page.wait_for_function("window.onbeforeunload === null")

    diff = subprocess.run(
        [sys.executable, "-m", "rcb4hv", "project", "diff", str(src), str(out), "--json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert diff.returncode == 1, diff.stderr
    changes = json.loads(diff.stdout)["changes"]
    assert [(c["kind"], c["slot"], c.get("pose"), c.get("ics")) for c in changes] == [
        ("pose-servo", WALK, 2, 10),
        ("motion-added", FREE, None, None),
    ]
    assert src.read_bytes() == kxr_project_path.read_bytes()
    image = tmp_path / "edited.bin"
    build = subprocess.run(
        [sys.executable, "-m", "rcb4hv", "project", "build", str(out), "-o", str(image)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert build.returncode == 0, build.stderr
    project = hth4.load_project(out)
    assert image.read_bytes() == build_project_image(project)
    run = run_motions(image.read_bytes(), (WALK, FREE))
    assert run.boot.status == "completed"
    results = run.results
    assert [r.status for r in results] == ["completed", "completed"]
