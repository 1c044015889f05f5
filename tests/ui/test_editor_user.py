"""The Editor page through NiceGUI's simulated `User`: open the fixture, edit a pose, mirror a
motion into a free slot, undo / redo, send a pose, store a trim, save."""

from __future__ import annotations

from pathlib import Path

from nicegui.testing.user import User

from rcb4hv import hth4
from rcb4hv.emulator import Board
from rcb4hv.hth4.diff import diff_projects
from rcb4hv.hth4.edit import set_pose
from rcb4hv.hth4.poses import motion_poses
from rcb4hv.project.relocate import project_image
from rcb4hv.ui.context import UiContext
from rcb4hv.ui.trim_panel import new_trim
from tests.ui.test_user import one, open_in_editor, output, run, until

WALK, TURN_LEFT, TURN_RIGHT, FREE = 66, 69, 70, 73


def commit(user: User, marker: str, value: object) -> None:
    """Type ``value`` into the field and press Enter, then leave it, as a user does."""
    one(user, marker).set_value(value)
    user.find(marker=marker).trigger("keydown.enter").trigger("blur")


def test_editor_edits_mirrors_and_saves(kxr_project_path: Path, tmp_path: Path) -> None:
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())
    out = tmp_path / "edited.h4p"

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await user.should_see(marker="tab-editor")
        await open_in_editor(user, src)
        assert "kxr-l2" in one(user, "editor-3d-caption").text.lower()
        one(user, "editor-motion").set_value(WALK)
        one(user, "editor-pose").set_value(1)
        await until(lambda: one(user, "editor-raw-10").value == 7900)
        # typed digit by digit: nothing applies until Enter (8, 77 and 770 were each an edit,
        # or refused as past the joint's limit, and reset the field under the user's fingers)
        for partial in (7, 77, 770):
            one(user, "editor-raw-10").set_value(partial)
        await user.should_not_see("outside the joint's hard (mechanical) limits")
        assert "no edits" in one(user, "editor-status").text
        commit(user, "editor-raw-10", 7700)
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        assert "unsaved" in one(user, "editor-status").text
        # past the hip's mechanical limit: refused with the reason, nothing changes
        commit(user, "editor-raw-10", 12000)
        await user.should_see("outside the joint's hard (mechanical) limits")
        assert "1 edit " in one(user, "editor-status").text
        # undo / redo
        user.find(marker="editor-undo").click()
        await until(lambda: "no edits" in one(user, "editor-status").text)
        user.find(marker="editor-redo").click()
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        # insert and delete: two more edits that cancel out
        user.find(marker="editor-duplicate").click()
        await until(lambda: len(one(user, "editor-pose").options) == 12)
        user.find(marker="editor-delete").click()
        await until(lambda: len(one(user, "editor-pose").options) == 11)
        # send the pose to the (emulated) board
        user.find(marker="editor-send").click()
        await until(lambda: output(board, 10) == 7700, 10)
        # mirror TURN_LEFT into a free slot
        one(user, "editor-motion").set_value(TURN_LEFT)
        one(user, "editor-mirror-to").set_value(FREE)
        one(user, "editor-mirror-name").set_value("TURN_RIGHT_MIRROR")
        user.find(marker="editor-mirror-motion").click()
        await until(lambda: "4 edits" in one(user, "editor-status").text)
        # bind the mirror to S3 + right (free in the fixture); a taken binding is refused
        one(user, "editor-motion").set_value(FREE)
        user.find(marker="bind-pad-s3").click()
        user.find(marker="bind-pad-right").click()
        user.find(marker="bind-apply").click()
        await until(lambda: "5 edits" in one(user, "editor-status").text)
        user.find(marker="bind-pad-s3").click()  # right alone
        user.find(marker="bind-apply").click()
        await user.should_see("already starts motion 12")
        user.find(marker="editor-undo").click()
        await until(lambda: "4 edits" in one(user, "editor-status").text)
        # preview the mirror: simulated in virtual time, played in the 3D view
        one(user, "editor-motion").set_value(FREE)
        user.find(marker="editor-preview").click()
        await until(lambda: one(user, "editor-preview-status").text.startswith("t = "), 30)
        assert one(user, "editor-scrubber").props["max"] > 0.5  # the turn lasts ~0.6 s
        # the one preview player: at the motion's end it stops and shows Play again (the
        # editor's own copy kept showing "Pause", its clock ticking on)
        await until(lambda: one(user, "editor-play").text == "Play", 30)
        status = one(user, "editor-preview-status").text  # "t = 0.63 / 0.63 s"
        assert status.split(" / ")[0].removeprefix("t = ") == status.split(" / ")[1][:-2]
        one(user, "editor-path").set_value(str(out))
        user.find(marker="editor-save").click()
        await until(lambda: out.exists() and one(user, "editor-status").text.endswith(" - saved"))
        await user.should_see(marker="editor-download-h4p")

    run(scenario)
    original, edited = hth4.load_project(src), hth4.load_project(out)
    assert src.read_bytes() == kxr_project_path.read_bytes()  # saved elsewhere: untouched
    changes = [(c.kind, c.slot, c.pose, c.ics) for c in diff_projects(original, edited)]
    assert changes == [("pose-servo", WALK, 2, 10), ("motion-added", FREE, None, None)]
    assert motion_poses(edited.motion(FREE)) == motion_poses(original.motion(TURN_RIGHT))
    assert edited.motion(FREE).name == "TURN_RIGHT_MIRROR"


def test_trim_panel_stores_a_trim(kxr_project_path: Path, tmp_path: Path) -> None:
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "trim-ics").set_value(10)
        user.find(marker="trim-free").click()
        await until(lambda: output(board, 10) == 0x8000)
        one(user, "trim-position").set_value(7560)
        user.find(marker="trim-position").trigger("change", 7560)  # released at 7560
        await until(lambda: output(board, 10) == 7560)
        user.find(marker="trim-store").click()
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        await user.should_see("set on the board")
        blk = int(board.ram[0x44 + 20]) | int(board.ram[0x45 + 20]) << 8

        def base() -> int:
            return int.from_bytes(bytes(board.ram[blk + 2 : blk + 4]), "little", signed=True)

        # the new trim with the output 7500: the servo is sent what it was (7560 - 250); the
        # output reaches 7500 at the board's next output period
        await until(lambda: output(board, 10) == 7500)
        assert base() == new_trim(-250, 7560) == -190
        user.find(marker="trim-write").click()
        await user.should_see("trims written to the board")
        assert base() == -190 and output(board, 10) == 7500  # not offset a second time
        user.find(marker="editor-save").click()
        await until(lambda: one(user, "editor-status").text.endswith(" - saved"))

    run(scenario)
    assert hth4.load_project(src).servo(10).trim == -190


def test_play_motion_writes_the_edit_and_plays_it(kxr_project_path: Path, tmp_path: Path) -> None:
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "editor-motion").set_value(39)  # the home position: one pose
        commit(user, "editor-raw-10", 7700)
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        user.find(marker="editor-play-board").click()
        await user.should_see(marker="editor-play-confirm")
        user.find(marker="editor-play-confirm").click()
        await until(lambda: output(board, 10) == 7700, 120)
        edited = set_pose(hth4.load_project(src), 39, 0, {10: 7700})
        assert bytes(board.rom) == project_image(edited)[0]  # the edit is in the board's ROM

    run(scenario)


def test_typing_frames_is_one_edit(kxr_project_path: Path, tmp_path: Path) -> None:
    """Typing 120 into the frames box is one edit when the user presses Enter (1, 12 and 120
    were three undo steps)."""
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "editor-motion").set_value(WALK)
        one(user, "editor-pose").set_value(1)
        await until(lambda: one(user, "editor-raw-10").value == 7900)
        for partial in (1, 12):
            one(user, "editor-frames").set_value(partial)
        commit(user, "editor-frames", 120)
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        commit(user, "editor-frames", 120)  # the same value again: no edit
        assert "1 edit " in one(user, "editor-status").text
        assert one(user, "editor-frames").value == 120

    run(scenario)


def test_new_motion_starts_at_home(kxr_project_path: Path, tmp_path: Path) -> None:
    """A new motion in a free slot, from the Editor: one pose with every servo at its home
    position, selected to edit (the Editor offered no way to start one)."""
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "editor-mirror-to").set_value(FREE)
        one(user, "editor-mirror-name").set_value("my wave")
        user.find(marker="editor-new-motion").click()
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        assert one(user, "editor-motion").value == FREE
        assert one(user, "editor-raw-10").value == hth4.load_project(src).servo(10).home_position
        user.find(marker="editor-save").click()
        await until(lambda: one(user, "editor-status").text.endswith(" - saved"))

    run(scenario)
    project = hth4.load_project(src)
    poses = list(motion_poses(project.motion(FREE)))
    assert project.motion(FREE).name == "my wave" and len(poses) == 1
    assert poses[0].values == {s.device_number: s.home_position for s in project.servos if s.in_use}
