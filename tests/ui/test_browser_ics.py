"""The Servo tools page in headless Chromium against `rcb4hv ui` (an emulated ICS bus in the
dashboard's process: ``icsemu://``)."""

from __future__ import annotations

import time
from typing import Any

import pytest

from tests.ui.conftest import shot

pytestmark = pytest.mark.slow


def _field(page: Any, name: str) -> Any:
    """The native <input> of a NiceGUI input (Quasar puts data-testid on the input itself)."""
    return page.locator(f"input[data-testid={name}], [data-testid={name}] input").first


def _wait(cond: Any, timeout: float = 15.0) -> None:
    deadline = time.monotonic() + timeout
    while not cond():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.05)


def test_servo_tools_scan_read_write_and_id_warning(page: Any) -> None:
    page.get_by_test_id("tab-servo-tools").click()
    warning = page.get_by_test_id("ics-id-warning")
    warning.wait_for(state="visible")
    assert "Only ONE servo" in warning.inner_text()
    _field(page, "ics-url").fill("icsemu://?ids=0,2")
    page.get_by_test_id("ics-scan").click()
    _wait(lambda: "IDs answering: 0 2" in page.get_by_test_id("ics-found").inner_text())
    page.get_by_test_id("ics-read").click()
    table = page.get_by_test_id("ics-params")
    _wait(lambda: "stretch" in table.inner_text() and "11500" in table.inner_text())
    _field(page, "ics-value").fill("33")
    page.get_by_test_id("ics-write").click()
    _wait(lambda: "stretch 90 -> 33" in page.get_by_test_id("ics-changes").inner_text())
    page.get_by_test_id("ics-set-id").click()
    page.get_by_test_id("ics-confirm-id").wait_for(state="visible")
    shot(page, "servo-tools-id-confirm")
    page.keyboard.press("Escape")
