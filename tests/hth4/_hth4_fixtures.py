"""Locating the shared HeartToHeart4 fixtures and comparing XML canonically."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from tests.conftest import KXR_PROJECT_DIR

FIXTURES = KXR_PROJECT_DIR


def fixture(name: str) -> Path:
    path = FIXTURES / name
    assert path.is_file(), f"HeartToHeart4 fixture {path} is missing from ../shared"
    return path


def canonical(data: bytes) -> tuple[object, ...]:
    """Tag, attributes, stripped text and children, recursively (formatting ignored)."""

    def walk(el: ET.Element) -> tuple[object, ...]:
        text = (el.text or "") if len(el) == 0 else (el.text or "").strip()
        return (el.tag, sorted(el.attrib.items()), text, tuple(walk(c) for c in el))

    return walk(ET.fromstring(data))
