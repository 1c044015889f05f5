"""``rcb4hv emulate``: serve an emulated RCB-4HV on a pty or a TCP socket."""

from __future__ import annotations

import logging
import signal
import sys
import threading
from types import FrameType

import click

log = logging.getLogger(__name__)


def _parse_hostport(value: str) -> tuple[str, int]:
    host, sep, port = value.rpartition(":")
    if not sep or not port.isdigit() or not 0 <= int(port) <= 65535:
        raise click.BadParameter("expected HOST:PORT, e.g. 127.0.0.1:0")
    return host or "127.0.0.1", int(port)


@click.command("emulate")
@click.option("--pty", "use_pty", is_flag=True, help="Serve on a new pseudo-terminal.")
@click.option("--tcp", "tcp", metavar="HOST:PORT", help="Serve on TCP (e.g. 127.0.0.1:0).")
@click.option(
    "--rom",
    "rom",
    type=click.Path(dir_okay=False),
    help="Persistent ROM image file (created from the default board if missing).",
)
@click.option(
    "--layout",
    type=click.Choice(["2.2", "2.1", "2.0", "1.3"]),
    default=None,
    help="HeartToHeart4 layout of the default board [default: 2.2]; ignored when --rom "
    "names an existing image.",
)
@click.option("--speed", type=float, default=1.0, show_default=True, help="Clock speed factor.")
@click.option(
    "--latency",
    type=float,
    default=None,
    help="Minimum reply latency in seconds [default: 0.001].",
)
@click.option(
    "--boot",
    type=click.Choice(["ready", "live"]),
    default="ready",
    show_default=True,
    help="ready: serve a board whose start-up program has already run (servos homed, main "
    "loop); live: serve it from power-on, start-up in real time.",
)
@click.option("--pace", is_flag=True, help="Pace replies at the configured COM baud.")
@click.option("--frame-timeout", type=float, default=None, help="Partial-frame timeout in seconds.")
def emulate(
    use_pty: bool,
    tcp: str | None,
    rom: str | None,
    layout: str | None,
    speed: float,
    latency: float | None,
    boot: str,
    pace: bool,
    frame_timeout: float | None,
) -> None:
    """Run the board emulator until interrupted (SIGINT/SIGTERM: clean exit 0).

    Prints one line, ``PTY <path>`` or ``TCP <host>:<port>``, as soon as it is ready.
    """
    from rcb4hv.emulator import Board, BootClock, EmulatorConfig, boot_to_main_loop
    from rcb4hv.emulator.server import PtyServer, TcpServer

    if use_pty == (tcp is not None):
        raise click.UsageError("give exactly one of --pty or --tcp HOST:PORT")
    if not speed > 0:
        raise click.BadParameter("must be > 0", param_hint="--speed")
    kwargs: dict[str, object] = {"pace_replies": pace}
    if latency is not None:
        kwargs["min_reply_latency_s"] = latency
    if frame_timeout is not None:
        kwargs["frame_timeout_s"] = frame_timeout
    try:
        config = EmulatorConfig(**kwargs)  # type: ignore[arg-type]
    except ValueError as exc:
        raise click.UsageError(str(exc)) from exc
    image, lay = None, None
    if layout is not None:
        from rcb4hv.rom.default import default_image
        from rcb4hv.rom.layout import LAYOUTS

        lay = LAYOUTS[layout]
        image = default_image(lay)
    clock = BootClock(speed)
    board = Board(config, clock=clock, rom_image=image, rom_path=rom)
    if boot == "ready":
        boot_to_main_loop(board, clock, lay)
    clock.go_real()
    stop = threading.Event()

    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    signal.signal(signal.SIGINT, handler)
    signal.signal(signal.SIGTERM, handler)
    server: PtyServer | TcpServer
    if use_pty:
        server = PtyServer(board)
        line = f"PTY {server.path}"
    else:
        assert tcp is not None
        host, port = _parse_hostport(tcp)
        server = TcpServer(board, host, port)
        line = f"TCP {server.address[0]}:{server.address[1]}"
    server.start()
    print(line, flush=True)
    log.info("emulator serving (%s), speed %g", line, speed)
    try:
        while not stop.wait(0.5):
            if server.error is not None:
                break
    finally:
        server.stop()
        board.close()
    if server.error is not None:
        sys.exit(1)


def register(cli: click.Group) -> None:
    """Add this module's commands to ``cli``."""
    cli.add_command(emulate)
