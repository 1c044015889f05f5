"""The dashboard app: a header with the link status and an always-visible STOP, one tab per
page, and the server (uvicorn on a socket we bind, so port 0 works, behind the guard)."""

from __future__ import annotations

import logging
import socket
import webbrowser
from collections.abc import Callable

from nicegui import ui

from rcb4hv.session import BoardSession
from rcb4hv.ui import (
    board_page,
    editor_page,
    gait_page,
    ics_page,
    motions_page,
    project_page,
    remote_page,
    servos_page,
    teach_page,
)
from rcb4hv.ui.context import UiContext, attempt, tid
from rcb4hv.ui.security import AccessPolicy, GuardMiddleware

__all__ = ["PAGES", "build_root", "create_app", "parse_bind", "serve"]

log = logging.getLogger(__name__)

PAGES: tuple[tuple[str, Callable[[UiContext], None]], ...] = (
    ("Board", board_page.build),
    ("Servos", servos_page.build),
    ("Remote", remote_page.build),
    ("Motions", motions_page.build),
    ("Project", project_page.build),
    ("Teach", teach_page.build),
    ("Walk", gait_page.build),
    ("Editor", editor_page.build),
    ("Servo tools", ics_page.build),
)


def build_root(ctx: UiContext) -> Callable[[], None]:
    """The page function NiceGUI calls for each browser tab."""

    def root() -> None:
        async def stop() -> None:
            if await attempt(ctx.session.stop(), "STOP"):  # type: ignore[arg-type]
                ui.notify("STOP: motion stopped, all servos hold", type="warning")

        ui.page_title("rcb4hv")
        with ui.header().classes("items-center bg-slate-800"):
            ui.label("rcb4hv").classes("text-lg font-bold")
            link = tid(ui.label(""), "link-status")
            ui.space()
            tid(
                ui.button("STOP", icon="front_hand", color="red").classes("text-lg"),
                "stop",
            ).on_click(stop)
        banner = tid(ui.label("").classes("w-full bg-red-100 text-red-900 p-2"), "link-error")
        with ui.tabs().classes("w-full") as tabs:
            tab_of = {
                name: tid(ui.tab(name), f"tab-{name.lower().replace(' ', '-')}")
                for name, _ in PAGES
            }
        with ui.tab_panels(tabs, value=tab_of["Servos"]).classes("w-full"):
            for name, build in PAGES:
                with ui.tab_panel(tab_of[name]):
                    build(ctx)

        def refresh() -> None:
            ctx.recheck_robot()
            st = ctx.session.state
            motion = "" if st.motion is None else f" - motion {st.motion}"
            link.text = (
                f"{st.url} - {st.version}{motion}" if st.connected else f"{st.url} - not connected"
            )
            banner.text = (
                "" if st.connected or st.error is None else (f"Link error: {st.error}. Retrying...")
            )
            banner.set_visibility(bool(banner.text))

        refresh()
        ui.timer(0.5, refresh)

    return root


def create_app(ctx: UiContext, policy: AccessPolicy) -> GuardMiddleware:
    """The ASGI app: NiceGUI mounted on FastAPI, wrapped in the Host/Origin/token guard."""
    from fastapi import FastAPI

    api = FastAPI(openapi_url=None, docs_url=None, redoc_url=None)
    ui.run_with(
        api,
        root=build_root(ctx),
        title="rcb4hv",
        favicon="🤖",
        show_welcome_message=False,
        reconnect_timeout=5.0,
    )
    return GuardMiddleware(api, policy)


def parse_bind(bind: str) -> tuple[str, int]:
    """``HOST:PORT`` (``[::1]:8765`` for IPv6) -> (host, port)."""
    host, sep, port = bind.rpartition(":")
    if not sep or not port.isdigit() or not host:
        raise ValueError(f"--bind takes HOST:PORT, not {bind!r}")
    value = int(port)
    if not 0 <= value <= 65535:
        raise ValueError(f"port {value} outside 0..65535")
    return host.strip("[]"), value


def serve(
    url: str,
    bind: str = "127.0.0.1:8765",
    *,
    baudrate: int | None = None,
    token: str | None = None,
    open_browser: bool = False,
    poll_hz: float = 10.0,
    robot: str | None = None,
    announce: Callable[[str], None] = print,
) -> None:
    """Run the dashboard until interrupted (SIGINT/SIGTERM); ``baudrate`` None detects it;
    ``robot`` (a built-in name or a URDF file) fixes the robot model, else it is detected."""
    import uvicorn

    host, port = parse_bind(bind)
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.bind((host, port))
    policy = AccessPolicy(bind_host=host, port=sock.getsockname()[1], token=token)
    session = BoardSession(url, baudrate=baudrate, poll_hz=poll_hz).start()
    try:
        try:
            session.wait_connected(timeout=8.0)
        except TimeoutError as exc:  # the pages show the link error and the session retries
            log.warning("%s", exc)
        ctx = UiContext(session, auto_robot=robot is None)
        ctx.choose_robot(robot)
        app = create_app(ctx, policy)
        shown = f"[{host}]" if family == socket.AF_INET6 else host
        address = f"http://{shown}:{policy.port}/"
        if token is not None:
            address += f"?token={token}"
        model = ctx.robot.name if ctx.robot is not None else "-"
        announce(f"rcb4hv ui: {address} (board {url}, robot {model}: {ctx.robot_source})")
        if open_browser:
            webbrowser.open(address)
        config = uvicorn.Config(app, log_level="warning", lifespan="on", ws="auto")
        uvicorn.Server(config).run(sockets=[sock])
    finally:
        session.close()
        sock.close()
