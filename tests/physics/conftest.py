"""Shared helpers of the physics tests: the KXR fixture project with extra keyframe motions
built into a ROM image, and host reads through real frames."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

from rcb4hv.hth4 import load_project
from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
from rcb4hv.project.relocate import project_image
from rcb4hv.protocol import Command, DataReply, decode_reply, encode_command
from rcb4hv.robot import RobotModel
from rcb4hv.rom.layout import MotionLayout
from tests.conftest import KXR_PROJECT_DIR

PROJECT = KXR_PROJECT_DIR / "HAC_KXR_HTH4_project.h4p"
FREE_SLOTS = (18, 19, 20)  # empty in the fixture


def pose(model: RobotModel, degrees: Mapping[str, float]) -> dict[int, int]:
    """Motion values of every mapped servo for joint angles in degrees (others 0)."""
    angles = {s.joint: math.radians(degrees.get(s.joint, 0.0)) for s in model.servos}
    return model.motion_values(angles)


def image_with(
    motions: Sequence[Sequence[Keyframe]],
) -> tuple[bytes, MotionLayout, dict[int, str]]:
    """The fixture project's image with ``motions`` stored in slots 18, 19, 20."""
    project = load_project(PROJECT)
    names: dict[int, str] = {}
    for slot, keyframes in zip(FREE_SLOTS, motions, strict=False):
        name = f"test {slot}"
        project = add_motion(
            project, motion_from_keyframes(keyframes, slot=slot, name=name, date="2026/01/01")
        )
        names[slot] = name
    image, lay = project_image(project, None)
    return image, lay, names


def host_read(board_feed: object, cmd: Command) -> bytes:
    """Send ``cmd`` through the board's byte interface and return the reply's data."""
    assert callable(board_feed)
    reply = decode_reply(board_feed(encode_command(cmd)), cmd)
    assert isinstance(reply, DataReply)
    return reply.data
