"""Every frame of every motion in the HeartToHeart4 fixture files decodes and re-encodes exactly."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

from rcb4hv import protocol as p


def motion_entries(path: Path) -> list[bytes]:
    """The hex entries of every <MotionData> list in a HeartToHeart4 XML file."""
    root = ET.parse(path).getroot()
    return [
        bytes.fromhex(item.text or "") for md in root.iter("MotionData") for item in md if item.text
    ]


def split_entry(entry: bytes) -> tuple[bytes, bytes]:
    """A motion entry is one frame, optionally followed by the FF end-of-motion marker."""
    return entry[: entry[0]], entry[entry[0] :]


def test_every_fixture_frame_round_trips(kxr_project_path: Path) -> None:
    kinds: Counter[str] = Counter()
    entries = motion_entries(kxr_project_path)
    assert len(entries) > 900
    for entry in entries:
        frame, rest = split_entry(entry)
        assert rest in (b"", b"\xff"), f"unexpected tail {rest.hex()}"
        cmd = p.decode_command(frame)
        assert p.encode_command(cmd) == frame
        kinds[type(cmd).__name__] += 1
    # the project really exercises the servo, branch and compare commands
    assert kinds["RunConstFrameServo"] > 100
    assert kinds["Jump"] > 10 and kinds["Sub"] > 10 and kinds["Return"] > 10


def test_project_motions_end_with_return_and_ff_marker(kxr_project_path: Path) -> None:
    root = ET.parse(kxr_project_path).getroot()
    motions = [md for md in root.iter("MotionData") if len(md)]
    assert len(motions) == 65  # 120 slots, 65 of them hold a motion
    for md in motions:
        last = bytes.fromhex(md[-1].text or "")
        assert last == b"\x03\x0d\x10\xff"
