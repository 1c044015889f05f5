"""The Editor page's program panel through NiceGUI's simulated `User`: add a button branch and
a counter loop to a motion, change a field, step the motion in the emulator, undo, save."""

from __future__ import annotations

from pathlib import Path

from nicegui.testing.user import User

from rcb4hv import hth4
from rcb4hv.emulator import Board
from rcb4hv.hth4.blocks import motion_program
from rcb4hv.hth4.diff import diff_projects
from rcb4hv.ui.context import UiContext
from tests.ui.test_user import one, open_in_editor, run, until

TURN_LEFT = 69


def test_program_panel_adds_branches_and_steps(kxr_project_path: Path, tmp_path: Path) -> None:
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())
    out = tmp_path / "edited.h4p"

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        one(user, "editor-motion").set_value(TURN_LEFT)
        await until(lambda: 'data-block="7"' in one(user, "flow-chart").content)
        user.find(marker="flow-chart").trigger("click", "1")  # select block 1 (a pose)
        one(user, "flow-kind").set_value("button_branch")
        user.find(marker="flow-add").click()
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        await until(lambda: one(user, "flow-field-buttons").value == '["UP"]')
        one(user, "flow-field-buttons").set_value('["S1", "S2"]')
        assert "not_equal" in one(user, "flow-field-if").options  # a condition is chosen
        one(user, "flow-field-if").set_value("not_equal")
        user.find(marker="flow-apply").click()
        await until(lambda: "2 edits" in one(user, "editor-status").text)
        one(user, "flow-kind").set_value("counter_loop")
        user.find(marker="flow-add").click()
        await until(lambda: "3 edits" in one(user, "editor-status").text)
        await user.should_see("point `to` at the block after the loop")  # the form says how
        one(user, "flow-target").set_value(1)
        user.find(marker="flow-connect").click()
        await until(lambda: "4 edits" in one(user, "editor-status").text)
        # a block a branch goes to cannot be removed
        user.find(marker="flow-chart").trigger("click", "0")
        user.find(marker="flow-remove").click()
        await user.should_see("branches to block 0")
        user.find(marker="flow-restart").click()
        await until(lambda: "at block 0" in one(user, "flow-step-status").text)
        user.find(marker="flow-step").click()
        await until(lambda: "at block 1 after 1 instructions" in one(user, "flow-step-status").text)
        assert 'stroke="#2e7d32"' in one(user, "flow-chart").content  # the current block
        # bind the motion on the pad's layout: S3 + right is free in the fixture
        assert "↑+← → M013" in one(user, "bind-list").text
        assert "M069" not in one(user, "bind-list").text
        user.find(marker="bind-pad-s3").click()
        user.find(marker="bind-pad-right").click()
        await until(lambda: "(0804h)" in one(user, "bind-word").text)
        user.find(marker="bind-apply").click()
        await until(lambda: "5 edits" in one(user, "editor-status").text)
        assert "→+S3 → M069" in one(user, "bind-list").text
        user.find(marker="editor-undo").click()
        await until(lambda: "4 edits" in one(user, "editor-status").text)
        user.find(marker="editor-undo").click()
        await until(lambda: "3 edits" in one(user, "editor-status").text)
        user.find(marker="editor-redo").click()
        await until(lambda: "4 edits" in one(user, "editor-status").text)
        one(user, "editor-path").set_value(str(out))
        user.find(marker="editor-save").click()
        await until(lambda: out.exists() and one(user, "editor-status").text.endswith(" - saved"))

    run(scenario)
    original, edited = hth4.load_project(src), hth4.load_project(out)
    assert {c.slot for c in diff_projects(original, edited)} == {TURN_LEFT}
    blocks = motion_program(edited, TURN_LEFT).blocks
    assert [b.kind for b in blocks[:5]] == ["pose", "pose", "button_branch", "counter_loop", "pose"]
    assert blocks[2].fields["buttons"] == ["S1", "S2"]
    assert blocks[2].fields["if"] == "not_equal"
    assert blocks[3].fields["to"] == blocks[1].label


def test_settings_panel_edits_the_project_settings(kxr_project_path: Path, tmp_path: Path) -> None:
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await open_in_editor(user, src)
        assert one(user, "settings-startup").value == 39  # the fixture starts with M039
        assert one(user, "settings-ad-1").value == 273
        one(user, "settings-startup").set_value(0)
        user.find(marker="settings-startup-apply").click()
        await until(lambda: "1 edit " in one(user, "editor-status").text)
        board.set_ad_input(1, 300)  # AD1 now reads 300 (measured + reference = the input)
        user.find(marker="settings-ad-read").click()
        await until(lambda: one(user, "settings-ad-1").value == 300)
        one(user, "settings-ad-1").set_value(273)
        one(user, "settings-ad-2").set_value(280)
        user.find(marker="settings-ad-apply").click()
        await until(lambda: "2 edits" in one(user, "editor-status").text)
        one(user, "settings-mix-servo").set_value(14)
        one(user, "settings-mix-source").set_value("AD1")
        one(user, "settings-mix-rate").set_value(8)
        user.find(marker="settings-mix-apply").click()
        await until(lambda: "3 edits" in one(user, "editor-status").text)
        one(user, "settings-mix-source").set_value("nowhere")
        user.find(marker="settings-mix-apply").click()
        await user.should_see("mixing source 'nowhere'")
        assert one(user, "settings-period").value == 15  # the fixture's 821Bh
        one(user, "settings-period").set_value(10)
        user.find(marker="settings-period-apply").click()
        await until(lambda: "4 edits" in one(user, "editor-status").text)
        user.find(marker="editor-save").click()
        await until(lambda: one(user, "editor-status").text.endswith(" - saved"))

    run(scenario)
    p = hth4.load_project(src)
    assert p.startup_motion_address == -1
    assert p.adc_reference_words[1:3] == (273, 280)
    assert (p.servo(14).mixing1_address, p.servo(14).mixing1_rate) == (0x0024, 8)
    assert p.system_register == 0x820B  # 10 ms: bits 5-4 cleared, nothing else
