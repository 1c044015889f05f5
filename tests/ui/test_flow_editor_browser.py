"""The program panel in headless Chromium: open the fixture project, add a button branch and a
counter loop to a motion, save, reopen; `project diff` shows exactly those blocks added."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from rcb4hv import hth4
from rcb4hv.hth4.blocks import motion_program
from tests.ui.browser import SHOTS
from tests.ui.test_editor_browser import _choose, _input, _wait_text

pytestmark = pytest.mark.slow

TURN_LEFT = 69


def _click_block(page: Any, index: int) -> None:
    page.locator(f"[data-testid=flow-chart] g[data-block='{index}']").click()
    page.get_by_test_id("flow-apply").wait_for()
    deadline = time.monotonic() + 40
    while f"block {index}:" not in page.get_by_test_id("flow-panel").inner_text():
        assert time.monotonic() < deadline, f"block {index} not selected"
        time.sleep(0.1)


def test_program_panel_in_the_browser(page: Any, kxr_project_path: Path, tmp_path: Path) -> None:
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())
    out = tmp_path / "edited.h4p"
    page.set_default_timeout(40_000)
    page.get_by_test_id("tab-editor").click()
    _input(page, "editor-path").fill(str(src))
    page.get_by_test_id("editor-open").click()
    _wait_text(page, "editor-status", "no edits")
    _choose(page, "editor-motion", f"M{TURN_LEFT:03d} HAC_KXR_TURN_LEFT")
    page.locator("[data-testid=flow-chart] g[data-block='7']").wait_for()
    # a button branch after block 1: while S1 is held, back to the first pose
    _click_block(page, 1)
    _choose(page, "flow-kind", "button_branch")
    page.get_by_test_id("flow-add").click()
    _wait_text(page, "editor-status", "1 edit ")
    field = _input(page, "flow-field-buttons")
    field.fill('["S1"]')
    page.get_by_test_id("flow-apply").click()
    _wait_text(page, "editor-status", "2 edits")
    # a counter loop after it, connected back to block 1
    _click_block(page, 2)
    _choose(page, "flow-kind", "counter_loop")
    page.get_by_test_id("flow-add").click()
    _wait_text(page, "editor-status", "3 edits")
    _choose(page, "flow-target", "1 pose")
    page.get_by_test_id("flow-connect").click()
    _wait_text(page, "editor-status", "4 edits")
    page.locator("[data-testid=flow-chart] path[data-from='3'][data-to='1']").wait_for()
    # step it in the emulator
    page.get_by_test_id("flow-step").click()
    _wait_text(page, "flow-step-status", "at block 0")
    page.get_by_test_id("flow-step").click()
    _wait_text(page, "flow-step-status", "at block 1")
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.get_by_test_id("flow-panel").screenshot(path=str(SHOTS / "program-panel.png"))
    _input(page, "editor-path").fill(str(out))
    page.get_by_test_id("editor-save").click()
    _wait_text(page, "editor-status", f"{out} - 4 edits - saved")
    # reopen the saved file
    page.get_by_test_id("editor-open").click()
    _wait_text(page, "editor-status", f"{out} - no edits")
    _choose(page, "editor-motion", f"M{TURN_LEFT:03d} HAC_KXR_TURN_LEFT")
    page.locator("[data-testid=flow-chart] path[data-from='3'][data-to='1']").wait_for()

    diff = subprocess.run(
        [sys.executable, "-m", "rcb4hv", "project", "diff", str(src), str(out), "--json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert diff.returncode == 1, diff.stderr
    changes = json.loads(diff.stdout)["changes"]
    assert [(c["kind"], c["slot"]) for c in changes] == [("block-added", TURN_LEFT)] * 4
    assert src.read_bytes() == kxr_project_path.read_bytes()
    blocks = motion_program(hth4.load_project(out), TURN_LEFT).blocks
    assert [b.kind for b in blocks[:4]] == ["pose", "pose", "button_branch", "counter_loop"]
    assert blocks[2].fields == {"buttons": ["S1"], "if": "equal", "to": blocks[0].label}
    assert blocks[3].fields["to"] == blocks[1].label
