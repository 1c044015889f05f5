"""The Editor page keeps the user's work and files (NiceGUI's simulated `User`): Open and
"Edit the Project page's project" ask before discarding unsaved edits, Save asks before
writing over a file it did not read, and the small refusals say what happened (a new-user
sweep found each of these silent)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest
from nicegui.testing.user import User

from rcb4hv import hth4
from rcb4hv.emulator import Board
from rcb4hv.errors import EditError
from rcb4hv.hth4 import dump_project
from rcb4hv.hth4.edit import set_pose
from rcb4hv.hth4.newproject import new_project
from rcb4hv.robot.builtin import load_robot
from rcb4hv.ui.context import UiContext
from rcb4hv.ui.editor_state import Editor
from tests.ui.test_editor_user import WALK, commit
from tests.ui.test_user import one, open_in_editor, run, until

HOME = 39  # the fixture's home position: one pose, its own mirror


def _copy(src: Path, to: Path) -> Path:
    to.write_bytes(src.read_bytes())
    return to


def status(user: User) -> str:
    return str(one(user, "editor-status").text)


def test_taking_the_project_pages_project_never_saves_over_the_file_open_before(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """Finding 1: open A, take the Project page's project B, Save. The path box still named A
    and Save wrote B over A (its 65 motions lost) without a question."""
    a = _copy(kxr_project_path, tmp_path / "a.h4p")
    original = a.read_bytes()
    other = set_pose(hth4.load_project(a), HOME, 0, {10: 7700})

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, a)
        ctx.set_project(other, "b.h4p")
        user.find(marker="editor-take").click()
        await until(lambda: status(user).startswith("no file yet"))
        assert one(user, "editor-path").value == ""  # B has no file of its own
        user.find(marker="editor-save").click()
        await user.should_see("no file to save to")
        # the user types A's path: A is not the file this session came from, so Save asks
        one(user, "editor-path").set_value(str(a))
        user.find(marker="editor-save").click()
        await user.should_see(marker="editor-overwrite-confirm")
        user.find(marker="editor-overwrite-confirm-cancel").click()
        await user.should_see("not saved")
        assert a.read_bytes() == original
        user.find(marker="editor-save").click()
        await user.should_see(marker="editor-overwrite-confirm")
        user.find(marker="editor-overwrite-confirm").click()
        await until(lambda: status(user) == f"{a} - no edits - saved")

    run(scenario)
    assert a.read_bytes() == dump_project(other)  # written after the explicit yes


def test_open_and_take_ask_before_discarding_unsaved_edits(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """Finding 2: with unsaved edits, Open of another path (or taking the Project page's
    project) replaced the session without a question, and Undo could not bring it back."""
    a = _copy(kxr_project_path, tmp_path / "a.h4p")
    b = _copy(kxr_project_path, tmp_path / "b.h4p")

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        ctx.set_project(hth4.load_project(b), "b.h4p")
        await open_in_editor(user, a)
        one(user, "editor-motion").set_value(WALK)
        one(user, "editor-pose").set_value(1)
        commit(user, "editor-raw-10", 7700)
        await until(lambda: status(user) == f"{a} - 1 edit - unsaved changes")
        # Open another file: asked; Cancel keeps the edit and the box names A again
        one(user, "editor-path").set_value(str(b))
        user.find(marker="editor-open").click()
        await user.should_see(marker="editor-discard-confirm")
        user.find(marker="editor-discard-confirm-cancel").click()
        await user.should_see("kept your unsaved changes")
        assert status(user) == f"{a} - 1 edit - unsaved changes"
        assert one(user, "editor-path").value == str(a)
        assert one(user, "editor-raw-10").value == 7700
        # the Project page's project: asked too
        user.find(marker="editor-take").click()
        await user.should_see(marker="editor-discard-confirm")
        user.find(marker="editor-discard-confirm-cancel").click()
        await user.should_not_see(marker="editor-discard-confirm")
        assert status(user) == f"{a} - 1 edit - unsaved changes"
        # Discard: the other file opens
        one(user, "editor-path").set_value(str(b))
        user.find(marker="editor-open").click()
        await user.should_see(marker="editor-discard-confirm")
        user.find(marker="editor-discard-confirm").click()
        await until(lambda: status(user) == f"{b} - no edits - saved")
        # no edits: Open asks nothing
        one(user, "editor-path").set_value(str(a))
        user.find(marker="editor-open").click()
        await until(lambda: status(user) == f"{a} - no edits - saved")
        await user.should_not_see(marker="editor-discard-confirm")

    run(scenario)
    assert a.read_bytes() == b.read_bytes() == kxr_project_path.read_bytes()


def test_save_asks_before_writing_over_another_existing_file(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """Finding 7: Save with the path box changed to an existing file replaced it at once.
    A new file and the session's own file are written without a question."""
    a = _copy(kxr_project_path, tmp_path / "a.h4p")
    victim = tmp_path / "victim.h4p"
    victim.write_bytes(dump_project(new_project(load_robot("khr3hv"))))
    kept = victim.read_bytes()
    fresh = tmp_path / "fresh.h4p"

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, a)
        one(user, "editor-motion").set_value(WALK)
        one(user, "editor-pose").set_value(1)
        commit(user, "editor-raw-10", 7700)
        await until(lambda: "1 edit " in status(user))
        one(user, "editor-path").set_value(str(victim))
        user.find(marker="editor-save").click()
        await user.should_see(marker="editor-overwrite-confirm")
        await user.should_see("victim.h4p exists and is not the file you opened")
        user.find(marker="editor-overwrite-confirm-cancel").click()
        await user.should_see("not saved")
        assert victim.read_bytes() == kept and "unsaved changes" in status(user)
        # a new file: no question; it is then the session's file, saved again without one
        one(user, "editor-path").set_value(str(fresh))
        user.find(marker="editor-save").click()
        await until(lambda: status(user) == f"{fresh} - 1 edit - saved")
        commit(user, "editor-raw-10", 7710)
        user.find(marker="editor-save").click()
        await until(lambda: status(user) == f"{fresh} - 2 edits - saved")
        await user.should_not_see(marker="editor-overwrite-confirm")

    run(scenario)
    assert victim.read_bytes() == kept
    assert a.read_bytes() == kxr_project_path.read_bytes()
    assert hth4.load_project(fresh).motion(WALK) != hth4.load_project(a).motion(WALK)


def test_status_and_save_rule_of_the_edit_state(kxr_project_path: Path, tmp_path: Path) -> None:
    """The status counts "1 edit" (was "1 edits"); Editor.save refuses another existing file
    unless told to overwrite, and writes its own file or a new one."""
    a = _copy(kxr_project_path, tmp_path / "a.h4p")
    other = _copy(kxr_project_path, tmp_path / "other.h4p")
    ed = Editor()
    ed.open(a.read_bytes(), a)
    ed.apply(set_pose, HOME, 0, {10: 7700}, None, ed.checks)
    assert ed.status() == f"{a} - 1 edit - unsaved changes"
    ed.apply(set_pose, HOME, 0, {10: 7710}, None, ed.checks)
    assert ed.status() == f"{a} - 2 edits - unsaved changes"
    assert ed.overwrite_question(a) is None and ed.overwrite_question(None) is None
    assert ed.overwrite_question(tmp_path / "new.h4p") is None
    assert "other.h4p exists and is not the file you opened" in str(ed.overwrite_question(other))
    with pytest.raises(EditError, match="nothing written"):
        ed.save(other)
    assert other.read_bytes() == kxr_project_path.read_bytes()
    ed.save(other, overwrite=True)
    assert ed.overwrite_question(other) is None  # the file last saved to
    assert ed.overwrite_question(a) is not None  # no longer the session's file
    ed.open(dump_project(hth4.load_project(a)), None)  # the Project page's project: no file
    assert "not the project you edit" in str(ed.overwrite_question(a))


def _unmodelled(path: Path) -> Path:
    """A project no robot model fits (six unnamed servos): no sliders, raw boxes only."""
    project = new_project(load_robot("khr3hv"), title="arm")
    keep = {1, 6, 7, 22, 23, 24}
    servos = tuple(
        s if s.device_number in keep else replace(s, mode="None", name="") for s in project.servos
    )
    path.write_bytes(dump_project(replace(project, servos=servos)))
    return path


def test_a_value_outside_the_documented_range_is_kept_with_a_notice(tmp_path: Path) -> None:
    """Finding 5: 12000 is kept (Kondo's motions use such values) but, with no model (no
    slider, no ⚠), the only trace was a line in the server's log."""
    src = _unmodelled(tmp_path / "arm.h4p")

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src, motions=1)
        assert one(user, "editor-3d-caption").text.startswith("no 3D view")
        commit(user, "editor-raw-2", 12000)
        await until(lambda: "1 edit " in status(user))
        await user.should_see("ICS 2: 12000 outside the documented 3500..11500")

    run(scenario)


def test_raw_box_refuses_fractions_and_shows_the_value_again(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """Finding 10: 7600.7 was stored as 7600 without a word; an emptied box stayed blank while
    the pose kept its value."""
    src = _copy(kxr_project_path, tmp_path / "kxr.h4p")

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "editor-motion").set_value(WALK)
        one(user, "editor-pose").set_value(1)
        await until(lambda: one(user, "editor-raw-10").value == 7900)
        commit(user, "editor-raw-10", 7600.7)
        await user.should_see("ICS 10: 7600.7 is not a whole number: kept 7900")
        assert one(user, "editor-raw-10").value == 7900 and "no edits" in status(user)
        commit(user, "editor-raw-10", None)  # emptied, then Enter
        assert one(user, "editor-raw-10").value == 7900 and "no edits" in status(user)
        commit(user, "editor-frames", 12.5)
        await user.should_see("frames: 12.5 is not a whole number")
        assert "no edits" in status(user)

    run(scenario)


def test_store_trim_says_when_nothing_changes(kxr_project_path: Path, tmp_path: Path) -> None:
    """Finding 11: "Store trim" at output 7500 (the trim unchanged) said it stored."""
    src = _copy(kxr_project_path, tmp_path / "kxr.h4p")

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "trim-ics").set_value(10)
        user.find(marker="trim-store").click()
        await user.should_see("ICS 10: trim -250 unchanged (the output is 7500): nothing stored")
        await user.should_not_see("stored in the project")
        assert "no edits" in status(user)

    run(scenario)


def test_mirror_pose_says_when_the_pose_is_its_own_mirror(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """Finding 12: "Mirror pose" on a pose that is its own mirror did nothing without a word."""
    src = _copy(kxr_project_path, tmp_path / "kxr.h4p")

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "editor-motion").set_value(HOME)
        user.find(marker="editor-mirror-pose").click()
        await user.should_see("pose 1 is already symmetric")
        assert "no edits" in status(user)

    run(scenario)


def test_program_panel_shows_the_blocks_value_after_a_refused_apply(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """Finding 14: Apply of frames 999 was refused but the form kept 999."""
    src = _copy(kxr_project_path, tmp_path / "kxr.h4p")

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "editor-motion").set_value(69)
        await until(lambda: 'data-block="1"' in one(user, "flow-chart").content)
        user.find(marker="flow-chart").trigger("click", "1")  # a pose
        await until(lambda: len(user.find(marker="flow-field-frames").elements) == 1)
        shown = one(user, "flow-field-frames").value
        one(user, "flow-field-frames").set_value("999")
        user.find(marker="flow-apply").click()
        await user.should_see("999 outside 0..255")
        await until(lambda: one(user, "flow-field-frames").value == shown)
        assert "no edits" in status(user)
        # 0: what the command can store (a file may hold it), kept with a warning
        one(user, "flow-field-frames").set_value("0")
        user.find(marker="flow-apply").click()
        await until(lambda: "1 edit " in status(user))
        await user.should_see("frames 0 kept: outside the documented 1..255")

    run(scenario)


def test_teach_warns_when_the_board_and_the_project_have_other_servos(
    kxr_project_path: Path,
) -> None:
    """Finding 9: poses captured from the default board (KHR-3HV servos: ICS 0, no 8 and 9)
    saved into the KXR-L2 project without a word; `project check` then warned unknown-ics."""

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        ctx.set_project(hth4.load_project(kxr_project_path), "kxr.h4p")
        user.find(marker="teach-capture").click()
        await until(lambda: one(user, "teach-count").text == "1 keyframes")
        user.find(marker="teach-save").click()
        await until(lambda: "saved as motion" in one(user, "teach-status").text, 30)
        await user.should_see("servo table has not (ICS 0; the board skips them)")
        await user.should_see("leaves out the project's ICS 8, 9")

    run(scenario)


def test_teach_says_nothing_when_the_servos_agree(kxr_project_path: Path) -> None:
    """The warning is for a mismatch only: keyframes of exactly the project's servos."""
    from rcb4hv.hth4.keyframes import Keyframe, free_slots
    from rcb4hv.ui.teach_page import save_keyframes, servo_mismatch

    project = hth4.load_project(kxr_project_path)
    servos = {s.device_number: s.home_position for s in project.servos if s.in_use}
    frames = [Keyframe(0.5, servos, "Pos1"), Keyframe(0.5, {**servos, 10: 7700}, "Pos2")]
    slot = free_slots(project)[0]
    saved = save_keyframes(project, frames, slot=slot, name="agreed")
    assert servo_mismatch(saved.project, slot, frames) == ""
    fewer = [Keyframe(0.5, {k: v for k, v in servos.items() if k != 8}, "Pos1")]
    saved = save_keyframes(project, fewer, slot=slot, name="fewer")
    assert servo_mismatch(saved.project, slot, fewer).startswith(
        f"motion {slot} leaves out the project's ICS 8 (they stay where they are)"
    )
