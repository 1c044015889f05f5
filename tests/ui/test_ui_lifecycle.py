"""What the dashboard keeps per browser tab, and what it forgets when the tab is gone;
messages of the Project page's upload boxes; the Board page while the link is down."""

from __future__ import annotations

from pathlib import Path

import pytest
from nicegui import Client
from nicegui.testing.user import User

from rcb4hv.emulator import Board
from rcb4hv.ui import project_page
from rcb4hv.ui.context import UiContext
from rcb4hv.ui.project_page import load_upload
from tests.ui.test_user import one, run, until


def test_a_closed_tab_stops_following_the_project(
    kxr_project_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every tab's pages follow the open project (redraw, re-run `project check`); a closed
    tab's did too, for the server's life, so each save got slower with every tab ever opened
    (a reload is a new tab). Once NiceGUI deletes a closed tab, nothing of it is called."""
    checks: list[int] = []
    real = project_page.check_rows

    def counted(project: object) -> object:
        checks.append(1)
        return real(project)  # type: ignore[arg-type]

    monkeypatch.setattr(project_page, "check_rows", counted)

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        first = user.client
        start = ctx.listener_count
        assert start > 0
        tabs: list[Client] = []
        for _ in range(4):
            tabs.append(await user.open("/"))
        assert ctx.listener_count == 5 * start
        for tab in tabs:  # closed, and past NiceGUI's reconnect timeout
            tab.delete()
        assert ctx.listener_count == start
        checks.clear()
        load_upload(ctx, "kxr.h4p", kxr_project_path.read_bytes())
        assert len(checks) == 1  # the one open tab's Project page
        assert first is not None and not first.is_deleted

    run(scenario)


def test_an_uploaded_flowchart_is_titled_with_its_file(kxr_dir: Path) -> None:
    """The title over an uploaded flowchart .xml read "select a motion" (or the motion shown
    before, with that motion's disassembly beside the file's chart)."""
    from nicegui.elements.upload_files import SmallFileUpload

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        title = one(user, "project-motion-title")
        assert title.text == "select a motion"
        data = (kxr_dir / "HAC_KXR_TURN_LEFT.xml").read_bytes()
        up = one(user, "flowchart-upload")
        await up.handle_uploads([SmallFileUpload("turn.xml", "text/xml", data)])
        await until(lambda: title.text.startswith("turn.xml: flowchart, "))
        assert "boxes" in title.text
        assert one(user, "project-disasm").content == ""
        await up.handle_uploads([SmallFileUpload("bad.xml", "text/xml", b"<nope")])
        await user.should_see("cannot open bad.xml")
        assert title.text.startswith("turn.xml")  # a refused file keeps what is shown

    run(scenario)
