"""The dashboard's layout at a laptop's size (1280x800) in real Chromium: every control
usable, nothing cut off, plot legends clear of their axes."""

from __future__ import annotations

import time
from collections.abc import Iterator
from typing import Any

import pytest

from tests.ui.conftest import open_page, shot

pytestmark = pytest.mark.slow

LAPTOP = {"width": 1280, "height": 800}


@pytest.fixture
def laptop(browser: Any, app_url: str) -> Iterator[Any]:
    yield from open_page(browser, app_url, LAPTOP)


def _wait(cond: Any, timeout: float = 15.0) -> None:
    deadline = time.monotonic() + timeout
    while not cond():
        assert time.monotonic() < deadline, "condition not met in time"
        time.sleep(0.05)


def _fully_shown(page: Any, locator: Any) -> bool:
    """Whether ``locator`` is on screen whole once scrolled to: inside the viewport and not
    clipped by a parent (the element itself is what the page shows at its corners)."""
    locator.scroll_into_view_if_needed()
    return bool(
        locator.evaluate(
            """(el) => {
                const r = el.getBoundingClientRect();
                if (r.width < 1 || r.left < 0 || r.right > window.innerWidth) return false;
                const inside = (x, y) => { const hit = document.elementFromPoint(x, y);
                                           return hit !== null && el.contains(hit); };
                const y = r.top + r.height / 2;
                return inside(r.left + 2, y) && inside(r.right - 2, y)
                    && el.scrollWidth <= el.clientWidth + 1;
            }"""
        )
    )


# The rectangles (page pixels, relative to the chart) of the chart's texts: the legend's
# "ICS n" labels and the y axis's name, as ECharts drew them on its canvas.
_CHART_TEXTS = """(el) => {
    const chart = getElement(el).chart;
    const out = [];
    for (const d of chart.getZr().storage.getDisplayList(true)) {
        const text = d.style && d.style.text;
        if (typeof text !== "string" || d.invisible || d.ignore) continue;
        const r = d.getBoundingRect().clone();
        if (d.transform) r.applyTransform(d.transform);
        out.push({text, x: r.x, y: r.y, w: r.width, h: r.height});
    }
    return out;
}"""


def _overlap(a: dict[str, float], b: dict[str, float]) -> bool:
    return (
        a["x"] < b["x"] + b["w"]
        and b["x"] < a["x"] + a["w"]
        and a["y"] < b["y"] + b["h"]
        and b["y"] < a["y"] + a["h"]
    )


def _legend_clear(page: Any, name: str, grid_top: float = 40) -> None:
    """The legend of chart ``name`` is drawn, on one line above the plot, clear of "deg"."""
    chart = page.get_by_test_id(name)
    chart.scroll_into_view_if_needed()
    texts: list[dict[str, Any]] = []

    def drawn() -> bool:
        texts[:] = chart.evaluate(_CHART_TEXTS)
        return any(t["text"].startswith("ICS") for t in texts)

    _wait(drawn)
    legend = [t for t in texts if t["text"].startswith("ICS")]
    axis = [t for t in texts if t["text"] == "deg"]
    assert len(axis) == 1, texts
    for t in legend:
        assert not _overlap(t, axis[0]), (t, axis[0])
        assert t["y"] + t["h"] <= grid_top, f"legend {t} runs into the plot"


def _servo_controls_usable(page: Any, width: int) -> None:
    sliders = page.locator("[data-testid^=slider-]")
    assert sliders.count() == 17
    for i in range(sliders.count()):
        box = sliders.nth(i).bounding_box()
        assert box is not None and box["width"] >= 150, (width, i, box)
    frees = page.locator("[data-testid^=free-]")
    assert frees.count() == 17
    for i in range(frees.count()):
        assert _fully_shown(page, frees.nth(i)), f"{width} px: free button {i} is cut off"
        assert frees.nth(i).inner_text().strip().upper() == "FREE"
    wide = page.evaluate("document.documentElement.scrollWidth")
    assert wide <= width, f"the page is {wide} px wide in a {width} px window"


def test_the_servos_page_is_usable_on_a_laptop(laptop: Any) -> None:
    """At 1280x800 each servo's slider was 0.44 px wide (a press on it sent a shoulder to its
    end stop), its FREE button cut to "FI", the legend over the axis name: the controls now
    wrap below the table and the 3D view instead of being squeezed."""
    laptop.get_by_test_id("tab-servos").click()
    _wait(lambda: laptop.locator("[data-testid^=slider-]").count() == 17)
    _legend_clear(laptop, "servo-plot")
    shot(laptop, "servos-1280")
    _servo_controls_usable(laptop, LAPTOP["width"])
    # and on a narrower screen still
    laptop.set_viewport_size({"width": 1024, "height": 768})
    _servo_controls_usable(laptop, 1024)
    _legend_clear(laptop, "servo-plot")


def test_the_project_page_is_readable_on_a_laptop(laptop: Any, kxr_project_path: Any) -> None:
    """At 1280x800 the disassembly was squeezed to ~180 px with every line cut off, and the
    simulate plot's legend ran over its "deg"."""
    laptop.get_by_test_id("tab-project").click()
    laptop.get_by_test_id("project-upload").locator("input[type=file]").set_input_files(
        str(kxr_project_path)
    )
    _wait(lambda: "65 motions" in laptop.get_by_test_id("project-summary").inner_text())
    table = laptop.get_by_test_id("project-motions")
    table.locator("tbody tr", has_text="XL2G_201").locator(".q-checkbox").click()
    _wait(lambda: "M021" in laptop.get_by_test_id("project-motion-title").inner_text())
    disasm = laptop.get_by_test_id("project-disasm")
    box = disasm.bounding_box()
    assert box is not None and box["width"] >= 400, box
    cut = disasm.evaluate(
        "(el) => [...el.querySelectorAll('pre, code, div')]"
        ".filter((e) => e.scrollWidth > e.clientWidth + 1).length"
    )
    assert cut == 0, "disassembly lines are cut off"
    assert _fully_shown(laptop, disasm)
    shot(laptop, "project-1280")
    laptop.get_by_text("Simulate / upload").click()
    laptop.get_by_test_id("project-simulate").click()
    _wait(lambda: "completed" in laptop.get_by_test_id("simulate-status").inner_text(), 30)
    _legend_clear(laptop, "simulate-plot")
