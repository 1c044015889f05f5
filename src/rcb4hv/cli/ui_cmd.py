"""``rcb4hv ui``: serve the browser dashboard."""

from __future__ import annotations

import click

from rcb4hv.cli._util import BAUD
from rcb4hv.transport import EMULATOR_URL


def register(cli: click.Group) -> None:
    cli.add_command(ui_command)


@click.command("ui")
@click.option(
    "--port",
    "url",
    default=EMULATOR_URL,
    show_default=True,
    help="Board URL: a serial device, socket://HOST:PORT or rcb4emu:// (emulator).",
)
@click.option(
    "--baud",
    type=BAUD,
    default="auto",
    show_default=True,
    help="Board baud rate (115200, 625000, 1250000) or 'auto' (an ACK check at each).",
)
@click.option(
    "--bind",
    default="127.0.0.1:8765",
    show_default=True,
    help="HOST:PORT the web server listens on (port 0: any free port).",
)
@click.option(
    "--allow-remote",
    is_flag=True,
    help="Allow a bind address other than loopback; every request then needs a token.",
)
@click.option("--open", "open_browser", is_flag=True, help="Open the dashboard in a browser.")
@click.option("--poll-hz", default=10.0, show_default=True, help="Board polling rate.")
@click.option(
    "--robot",
    "robot",
    default=None,
    metavar="NAME|FILE",
    help="Robot model of the 3D view and joint names: khr3hv, khr3hv-22, kxr-l2, "
    "kxr-l2-gripper, a KXR kit code (kxr:L6) or a URDF file (with its .toml joint map). "
    "Default: detected from the open project or the board's servos.",
)
def ui_command(
    url: str,
    baud: int | None,
    bind: str,
    allow_remote: bool,
    open_browser: bool,
    poll_hz: float,
    robot: str | None,
) -> None:
    """Browser dashboard for a board or the emulator (servos, remote, motions, projects,
    teaching). Needs the 'ui' extra: pip install 'rcb4hv[ui]'."""
    try:
        from rcb4hv.ui.app import parse_bind, serve
        from rcb4hv.ui.security import new_token
    except ImportError as exc:
        raise click.ClickException(
            f"the dashboard needs the 'ui' extra (pip install 'rcb4hv[ui]'): {exc}"
        ) from None
    baudrate = baud
    try:
        host, _ = parse_bind(bind)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--bind") from None
    loopback = host in ("127.0.0.1", "localhost", "::1") or host.startswith("127.")
    if not loopback and not allow_remote:
        raise click.UsageError(
            f"--bind {bind} is reachable from other machines: add --allow-remote "
            "(a random access token is then required)"
        )
    token = None if loopback else new_token()
    if poll_hz <= 0:
        raise click.BadParameter("must be > 0", param_hint="--poll-hz")
    if robot is not None:
        from rcb4hv.errors import RobotModelError
        from rcb4hv.robot.builtin import load_robot

        try:
            load_robot(robot)
        except RobotModelError as exc:
            raise click.BadParameter(str(exc), param_hint="--robot") from None
    serve(
        url,
        bind,
        baudrate=baudrate,
        token=token,
        open_browser=open_browser,
        poll_hz=poll_hz,
        robot=robot,
        announce=lambda s: click.echo(s, nl=True),
    )
