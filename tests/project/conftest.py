"""Shared fixtures of the project tests: the fixture project and its image (built once)."""

from __future__ import annotations

from pathlib import Path

import pytest

from rcb4hv import hth4
from rcb4hv.project.image import build_project_image


@pytest.fixture(scope="session")
def kxr_project(kxr_project_path: Path) -> hth4.Project:
    return hth4.load_project(kxr_project_path)


@pytest.fixture(scope="session")
def kxr_image(kxr_project: hth4.Project) -> bytes:
    return build_project_image(kxr_project)
