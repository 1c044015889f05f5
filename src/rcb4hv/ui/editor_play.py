"""The Editor page's "Play motion": put the edited project on the board and play a motion.

The ROM program plays motions from ROM, so the edited motion must be written there: after a
confirmation, the edited project's image is built and only the ROM pages that differ from
the board's are written and read back (:func:`rcb4hv.project.upload.upload_image` with
``only_changed``), then the motion is started. Unlike "Save" this changes the board's
program: the dialog says so.
"""

from __future__ import annotations

from nicegui import ui

from rcb4hv.client import Robot
from rcb4hv.hth4 import Project
from rcb4hv.project.upload import UploadResult, upload_image
from rcb4hv.ui.context import UiContext, guarded
from rcb4hv.ui.project_actions import READY_TIMEOUT_S, built_image, confirm

__all__ = ["play_on_board"]


async def play_on_board(ctx: UiContext, project: Project, slot: int) -> UploadResult | None:
    """Ask, write the changed ROM pages of ``project``, play motion ``slot``."""
    image = built_image(project)
    if image is None or not await confirm(
        f"Write the edited project to the board at {ctx.session.url} and play {slot}?",
        "The ROM pages that differ are replaced and read back to verify.",
        "Write and play",
        "editor-play-confirm",
    ):
        return None

    def job(robot: Robot) -> UploadResult:
        result = upload_image(robot, image, only_changed=True, verify=True)
        robot.wait_ready(timeout=READY_TIMEOUT_S)
        robot.discover_servos()
        robot.play_motion(slot)
        return result

    result = await guarded(ctx.session.submit(job, label="play motion"), "Play motion")
    if result is not None:
        ui.notify(
            f"motion {slot} playing ({result.pages_written} of {result.pages_total} ROM pages "
            "written)"
        )
    return result
