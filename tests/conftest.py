"""Shared test configuration: fixture location, the --port option for hardware tests."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

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
    """The HeartToHeart4 fixture folder, or skip when ../shared is absent."""
    if not KXR_PROJECT_DIR.is_dir():
        pytest.skip(f"HeartToHeart4 fixtures not found at {KXR_PROJECT_DIR} (../shared absent)")
    return KXR_PROJECT_DIR


@pytest.fixture(scope="session")
def kxr_project_path(kxr_dir: Path) -> Path:
    return kxr_dir / "HAC_KXR_HTH4_project.h4p"
