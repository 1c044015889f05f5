"""Helpers for the browser tests: find Chromium, run `rcb4hv ui` as a subprocess."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

SKIP_ENV = "RCB4HV_SKIP_BROWSER"
"""Set to 1 to skip the dashboard's browser tests (the only way to skip them: a missing
browser is a failure, and the test summary says when they were skipped)."""
CHROMIUM_ENV = "RCB4HV_CHROMIUM"
DEBIAN_CHROMIUM = "/usr/bin/chromium"
SHOTS = Path(
    os.environ.get(
        "RCB4HV_SCREENSHOTS", Path(__file__).resolve().parents[2] / "build" / "screenshots"
    )
)
LAUNCH_ARGS = [
    "--no-sandbox",
    "--disable-background-networking",
    "--disable-gpu",
    # WebGL (the 3D view) rendered in software by SwiftShader through ANGLE, with no GPU
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--ignore-gpu-blocklist",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def skip_requested() -> bool:
    """True when the browser tests are opted out with ``RCB4HV_SKIP_BROWSER=1``."""
    return os.environ.get(SKIP_ENV) == "1"


def _playwright_chromium() -> str | None:
    """The Chromium that ``playwright install chromium`` downloaded, if there is one."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        return None
    with sync_playwright() as pw:
        path = str(pw.chromium.executable_path)
    return path if Path(path).is_file() else None


def find_chromium() -> str | None:
    """The browser the tests drive: ``$RCB4HV_CHROMIUM`` if set (and nothing else then),
    else Debian's ``/usr/bin/chromium``, a ``chromium`` on PATH, or Playwright's download."""
    explicit = os.environ.get(CHROMIUM_ENV)
    if explicit:
        return explicit if (Path(explicit).is_file() or shutil.which(explicit)) else None
    for name in (DEBIAN_CHROMIUM, "chromium", "chromium-browser"):
        found = shutil.which(name)
        if found:
            return found
    return _playwright_chromium()


def require_browser() -> str:
    """Chromium's path for the browser tests. A missing browser or Playwright fails the test
    (``make test`` installs both); only ``RCB4HV_SKIP_BROWSER=1`` skips."""
    if skip_requested():
        pytest.skip(f"{SKIP_ENV}=1: the dashboard's browser tests were opted out")
    try:
        import playwright  # noqa: F401
    except ImportError:
        pytest.fail("playwright is not installed (pip install -e '.[dev]'; make test does it)")
    path = find_chromium()
    if path is None:
        pytest.fail(
            "no Chromium for the browser tests: run tools/ensure-browser (make test does), "
            f"or set {SKIP_ENV}=1 to skip them"
        )
    return path


# How long a page may take to load: the dashboard's first load ships NiceGUI's Vue/Quasar and
# three.js bundles, which takes seconds on a loaded two-core runner (the suite's own load).
PAGE_LOAD_MS = 90_000


def wait_until_serving(url: str, deadline: float) -> None:
    """Poll ``url`` until the server answers HTTP: uvicorn prints its address before the
    socket accepts, and a browser that comes too early gets ERR_CONNECTION_REFUSED."""
    last: Exception | None = None
    while time.monotonic() < deadline:
        try:
            with urllib.request.urlopen(url, timeout=5) as reply:
                reply.read(1)
            return
        except OSError as e:  # refused, reset, or an HTTP error before the app is mounted
            last = e
            time.sleep(0.1)
    raise AssertionError(f"rcb4hv ui printed {url} but never answered: {last}")


@contextmanager
def ui_server(board_url: str, *extra: str) -> Iterator[str]:
    """Run ``rcb4hv ui --port board_url --bind 127.0.0.1:0``; yield its http URL."""
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "rcb4hv.cli.main",
            "ui",
            "--port",
            board_url,
            "--bind",
            "127.0.0.1:0",
            *extra,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
    )
    try:
        assert proc.stdout is not None
        deadline = time.monotonic() + 60
        url = None
        lines = []
        while time.monotonic() < deadline:
            line = proc.stdout.readline()
            if not line:
                break
            lines.append(line)
            m = re.search(r"(http://\S+)", line)
            if m:
                url = m.group(1)
                break
        assert url is not None, "rcb4hv ui did not start:\n" + "".join(lines)
        wait_until_serving(url, deadline)
        yield url
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        if proc.stdout is not None:
            proc.stdout.close()


if __name__ == "__main__":  # tools/ensure-browser asks here what the tests would find
    found = find_chromium()
    print(found or "")
    sys.exit(0 if found else 1)
