"""Fixtures of the UI tests: an emulated board served over TCP (so the test can look at its
RAM and ROM), `rcb4hv ui` against it, and headless Chromium driven by Playwright."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from rcb4hv.emulator import Board, EmulatorConfig, RealClock, TcpServer
from rcb4hv.rom.default import DEFAULT_ICS, default_image
from tests.ui.browser import LAUNCH_ARGS, PAGE_LOAD_MS, SHOTS, require_browser, ui_server


@pytest.fixture(scope="module")
def board() -> Iterator[tuple[Board, str]]:
    b = Board(
        EmulatorConfig(virtual_servos=DEFAULT_ICS), clock=RealClock(), rom_image=default_image()
    )
    with TcpServer(b, "127.0.0.1", 0) as srv:
        host, port = srv.address
        yield b, f"socket://{host}:{port}"
    b.close()


@pytest.fixture(scope="module")
def chromium_path() -> str:
    return require_browser()


@pytest.fixture(scope="module")
def app_url(chromium_path: str, board: tuple[Board, str]) -> Iterator[str]:
    with ui_server(board[1]) as url:
        yield url


@pytest.fixture(scope="module")
def browser(chromium_path: str) -> Iterator[Any]:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=chromium_path, headless=True, args=LAUNCH_ARGS)
        yield b
        b.close()


def open_page(browser: Any, app_url: str, viewport: dict[str, int]) -> Iterator[Any]:
    """A page of the dashboard in a new browser context of ``viewport``, loaded (its STOP
    button shown); the context is closed after."""
    context = browser.new_context(viewport=viewport, accept_downloads=True)
    pg = context.new_page()
    pg.set_default_timeout(15_000)
    pg.goto(app_url, timeout=PAGE_LOAD_MS)
    pg.get_by_test_id("stop").wait_for(timeout=PAGE_LOAD_MS)
    yield pg
    context.close()


@pytest.fixture
def page(browser: Any, app_url: str) -> Iterator[Any]:
    yield from open_page(browser, app_url, {"width": 1400, "height": 900})


def shot(page: Any, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.evaluate("window.scrollTo(0, 0)")
    page.screenshot(path=str(SHOTS / f"{name}.png"), full_page=False)
