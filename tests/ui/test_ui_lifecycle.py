"""What the dashboard keeps per browser tab, and what it forgets when the tab is gone;
messages of the Project page's upload boxes; the Board page while the link is down."""

from __future__ import annotations

from pathlib import Path
from typing import Any

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


def test_a_link_down_is_logged_once_and_the_board_page_marks_its_values_stale(
    caplog: pytest.LogCaptureFixture,
) -> None:
    """While the link was down the log got a WARNING per retry (one a second) and the Board
    page went on showing the last battery, PC and "ROM program running" as if live."""
    import asyncio
    import logging

    from nicegui.testing.user_simulation import user_simulation

    from rcb4hv.emulator import EmulatorConfig, RealClock, TcpServer
    from rcb4hv.rom.default import DEFAULT_ICS, default_image
    from rcb4hv.session import BoardSession
    from rcb4hv.ui.app import build_root
    from rcb4hv.ui.board_page import STALE_MARK

    caplog.set_level(logging.DEBUG, logger="rcb4hv.session.core")
    board = Board(
        EmulatorConfig(virtual_servos=DEFAULT_ICS), clock=RealClock(), rom_image=default_image()
    )
    server = TcpServer(board, "127.0.0.1", 0).__enter__()
    host, port = server.address
    session = BoardSession(f"socket://{host}:{port}", poll_hz=20, retry=0.05)
    ctx = UiContext(session)

    def rows(user: User) -> dict[str, str]:
        return {r["field"]: r["value"] for r in one(user, "board-table").rows}

    def warnings() -> list[str]:
        return [
            r.getMessage()
            for r in caplog.records
            if r.name == "rcb4hv.session.core" and r.levelno >= logging.WARNING
        ]

    async def main() -> None:
        nonlocal server
        async with user_simulation(root=build_root(ctx)) as user:
            await user.open("/")
            await until(lambda: rows(user)["version"].startswith("CB-4"))
            assert STALE_MARK not in str(rows(user))
            await user.should_not_see(marker="board-stale")
            server.__exit__(None, None, None)  # the board goes away
            await until(lambda: not session.state.connected)

            def retries() -> int:
                return sum("still down" in r.getMessage() for r in caplog.records)

            # the failure, and each change of error on the way (dropped, reset, refused)
            await until(lambda: retries() >= 1)
            down = warnings()
            assert 1 <= len(down) <= 3 and all("failed" in w for w in down), down
            # then ten more retries that failed the same way: not one warning a retry
            seen = retries()
            await until(lambda: retries() >= seen + 10)
            assert warnings() == down
            await until(lambda: STALE_MARK in rows(user)["battery"])
            assert STALE_MARK in rows(user)["ROM program"] and STALE_MARK in rows(user)["PC"]
            assert rows(user)["connected"] == "no"
            assert "link is down" in one(user, "board-stale").text
            server = TcpServer(board, "127.0.0.1", port).__enter__()  # it is back
            await until(lambda: session.state.connected, 15)
            await until(lambda: any("is back" in w for w in warnings()))
            await until(lambda: STALE_MARK not in str(rows(user)))
            await user.should_not_see(marker="board-stale")

    try:
        session.start()
        session.wait_connected(timeout=10)
        asyncio.run(main())
    finally:
        session.close()
        server.__exit__(None, None, None)
        board.close()


def _http_scope(path: str) -> dict[str, object]:
    return {
        "type": "http",
        "asgi": {"version": "3.0"},
        "http_version": "1.1",
        "method": "GET",
        "scheme": "http",
        "path": path,
        "raw_path": path.encode(),
        "query_string": b"",
        "root_path": "",
        "headers": [(b"host", b"127.0.0.1:8765")],
        "client": ("127.0.0.1", 50000),
        "server": ("127.0.0.1", 8765),
    }


def test_a_tab_closed_mid_request_is_no_traceback(caplog: pytest.LogCaptureFixture) -> None:
    """A browser tab closed while a request was served: Starlette's BaseHTTPMiddleware (as
    NiceGUI uses) raised "No response returned." and uvicorn logged a full traceback. The
    guard lets it pass quietly (debug); any other error still propagates."""
    import asyncio
    import logging

    from starlette.middleware.base import BaseHTTPMiddleware

    from rcb4hv.ui.security import AccessPolicy, GuardMiddleware

    async def passthrough(request: Any, call_next: Any) -> Any:
        return await call_next(request)

    async def abandoned(scope: Any, receive: Any, send: Any) -> None:
        while (await receive())["type"] != "http.disconnect":
            pass  # the client left: there is no one to answer

    async def broken(scope: Any, receive: Any, send: Any) -> None:
        raise RuntimeError("a real bug")

    def serve(app: Any) -> list[dict[str, object]]:
        guard = GuardMiddleware(BaseHTTPMiddleware(app, passthrough), AccessPolicy(port=8765))
        incoming = [{"type": "http.request", "body": b"", "more_body": False}]
        sent: list[dict[str, object]] = []

        async def receive() -> dict[str, object]:
            if incoming:
                return incoming.pop(0)
            await asyncio.sleep(0.01)
            return {"type": "http.disconnect"}

        async def send(message: dict[str, object]) -> None:
            sent.append(message)

        asyncio.run(guard(_http_scope("/"), receive, send))  # type: ignore[arg-type]
        return sent

    caplog.set_level(logging.DEBUG, logger="rcb4hv.ui.security")
    assert serve(abandoned) == []
    assert any("the client left" in r.getMessage() for r in caplog.records)
    with pytest.raises(RuntimeError, match="a real bug"):
        serve(broken)
