"""Helpers for the browser tests: find Chromium, run `rcb4hv ui` as a subprocess."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

CHROMIUM = os.environ.get("RCB4HV_CHROMIUM", "/usr/bin/chromium")
REQUIRE = os.environ.get("RCB4HV_REQUIRE_BROWSER") == "1"
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


def browser_or_skip() -> str:
    """Chromium's path; skip (or fail under RCB4HV_REQUIRE_BROWSER=1) when it is missing."""
    why = None
    if not (Path(CHROMIUM).is_file() or shutil.which(CHROMIUM)):
        why = f"no Chromium at {CHROMIUM} (apt-get install chromium)"
    else:
        try:
            import playwright  # noqa: F401
        except ImportError:
            why = "playwright is not installed (pip install -e '.[dev]')"
    if why is not None:
        if REQUIRE:
            pytest.fail(f"browser tests required (RCB4HV_REQUIRE_BROWSER=1): {why}")
        pytest.skip(why)
    return CHROMIUM


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
