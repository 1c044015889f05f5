"""The Editor's posing aids through NiceGUI's simulated `User`: a handle dropped out of reach
gives the nearest pose and says so (one undo step), "keep balance" lifts a foot over the
other, the balance line follows the pose, easing is applied as one edit."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from nicegui.events import GenericEventArguments
from nicegui.testing.user import User

from rcb4hv.emulator import Board
from rcb4hv.ui.context import UiContext
from tests.ui.test_user import one, open_in_editor, run, until

HOME, BOW = 39, 21


def drop(scene: Any, link: str, dx: float, dy: float, dz: float) -> None:
    """What the browser sends when a handle is dropped ``(dx, dy, dz)`` from where it is."""
    handle = next(o for o in scene.objects.values() if o.name == f"ik:{link}")
    args = {
        "type": "dragend",
        "object_id": handle.id,
        "object_name": handle.name,
        "x": handle.x + dx,
        "y": handle.y + dy,
        "z": handle.z + dz,
    }
    scene._handle_drag(GenericEventArguments(sender=scene, client=scene.client, args=args))


def test_posing_aids_in_the_editor(kxr_project_path: Path, tmp_path: Path) -> None:
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await user.should_see(marker="tab-editor")
        await open_in_editor(user, src)
        one(user, "editor-motion").set_value(HOME)
        one(user, "editor-pose").set_value(0)
        await until(lambda: one(user, "editor-balance").text.startswith("stands"))
        scene = one(user, "editor-3d")
        # out of reach: 30 cm ahead
        drop(scene, "r_foot", 0.3, 0.0, 0.0)
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        assert "out of reach" in one(user, "editor-reach").text
        user.find(marker="editor-undo").click()
        await until(lambda: "no edits" in one(user, "editor-status").text)
        # keep balance: the right foot lifted 2 cm, the body moves over the left foot
        one(user, "editor-keep-balance").set_value(True)
        drop(scene, "r_foot", 0.0, 0.0, 0.02)
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        assert one(user, "editor-reach").text == ""
        await until(lambda: "(l_foot)" in one(user, "editor-balance").text)
        # easing: the bow's pose 3 over 4 poses, one edit
        one(user, "editor-motion").set_value(BOW)
        one(user, "editor-pose").set_value(2)
        await until(lambda: len(one(user, "editor-pose").options) == 5)
        user.find(marker="editor-ease").click()
        await until(lambda: "2 edits" in one(user, "editor-status").text)
        assert len(one(user, "editor-pose").options) == 8
        # a preview plays: the handles, which belong to the edited pose, leave the view
        handles = [o for o in scene.objects.values() if (o.name or "").startswith("ik:")]
        assert handles and all(h.visible_ for h in handles)
        one(user, "editor-physics").set_value(False)
        user.find(marker="editor-preview").click()
        await until(lambda: not any(h.visible_ for h in handles), 30)
        one(user, "editor-pose").set_value(1)  # a pose picked again: they are back
        await until(lambda: all(h.visible_ for h in handles))

    run(scenario)
