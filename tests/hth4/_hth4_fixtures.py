"""Locating the shared HeartToHeart4 fixtures and comparing XML canonically."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[2]
FIXTURES = REPO_ROOT.parent / "shared" / "fixtures" / "hth4" / "kxr-l2-hac"


def fixture(name: str) -> Path:
    path = FIXTURES / name
    if not path.is_file():
        pytest.skip(f"HeartToHeart4 fixture {path} is absent (needs ../shared/fixtures/hth4)")
    return path


def canonical(data: bytes) -> tuple[object, ...]:
    """Tag, attributes, stripped text and children, recursively (formatting ignored)."""

    def walk(el: ET.Element) -> tuple[object, ...]:
        text = (el.text or "") if len(el) == 0 else (el.text or "").strip()
        return (el.tag, sorted(el.attrib.items()), text, tuple(walk(c) for c in el))

    return walk(ET.fromstring(data))
