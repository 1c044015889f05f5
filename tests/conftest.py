"""Shared test configuration: fixture location (``../shared`` must be there), the --port
option for hardware tests, and the browser opt-out in the report header and summary."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

from tests.ui.browser import SKIP_ENV, find_chromium, skip_requested

REPO = Path(__file__).resolve().parent.parent
FIXTURES = REPO.parent / "shared" / "fixtures" / "hth4"
KXR_PROJECT_DIR = FIXTURES / "kxr-l2-hac"

settings.register_profile(
    "default", deadline=None, suppress_health_check=[HealthCheck.too_slow], max_examples=150
)
settings.register_profile(
    "fuzz", deadline=None, max_examples=int(os.environ.get("RCB4HV_FUZZ_EXAMPLES", "5000"))
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--port",
        action="store",
        default=None,
        help="serial URL of a real RCB-4HV board; enables tests marked 'hardware'",
    )


def pytest_sessionstart(session: pytest.Session) -> None:
    """The shared material beside the clone is part of the test set-up, not optional: without
    it a third of the suite (every test of the real HeartToHeart4 project) could not run."""
    if not KXR_PROJECT_DIR.is_dir():
        raise pytest.UsageError(
            f"the HeartToHeart4 fixtures are missing: {KXR_PROJECT_DIR} does not exist. "
            f"The tests need the shared material checked out beside this clone, as "
            f"{REPO.parent / 'shared'} (with fixtures/hth4/kxr-l2-hac inside)."
        )


def _browser_line() -> str:
    if skip_requested():
        return f"browser tests: SKIPPED ({SKIP_ENV}=1 opted out; the dashboard was not tested)"
    return f"browser tests: run with {find_chromium() or 'NO CHROMIUM FOUND (they will fail)'}"


def pytest_report_header(config: pytest.Config) -> str:
    return _browser_line()


def pytest_unconfigure(config: pytest.Config) -> None:
    """Right under the ``N passed, M skipped`` line: an opt-out is never silent."""
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    if skip_requested() and reporter is not None:
        reporter.write_line(_browser_line(), yellow=True, bold=True)


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    if config.getoption("--port"):
        return
    skip = pytest.mark.skip(reason="hardware test: run with --port URL of a real board")
    for item in items:
        if "hardware" in item.keywords:
            item.add_marker(skip)


@pytest.fixture
def hardware_port(request: pytest.FixtureRequest) -> str:
    port = request.config.getoption("--port")
    assert isinstance(port, str)
    return port


@pytest.fixture(scope="session")
def kxr_dir() -> Path:
    """The HeartToHeart4 fixture folder (checked at session start)."""
    return KXR_PROJECT_DIR


@pytest.fixture(scope="session")
def kxr_project_path(kxr_dir: Path) -> Path:
    return kxr_dir / "HAC_KXR_HTH4_project.h4p"
