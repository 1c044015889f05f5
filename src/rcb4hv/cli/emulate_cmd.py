"""``rcb4hv emulate``: serve an emulated RCB-4HV on a pty or a TCP socket;
``rcb4hv emulate-ics``: serve an emulated ICS servo bus the same way."""

from __future__ import annotations

import logging
import os
import signal
import sys
import threading
from pathlib import Path
from types import FrameType
from typing import TYPE_CHECKING

import click

from rcb4hv.cli._util import handle_errors

if TYPE_CHECKING:
    from rcb4hv.emulator.server import PtyServer, Served, TcpServer

log = logging.getLogger(__name__)

# emulate-ics on a pty holds a reply until the client has reconfigured the port (rcb4's ics.py
# does, ~2 ms after writing: tx time + 2 ms) or for this long (see emulator.ptywatch); a client
# that never reconfigures waits it once per command, well inside the 0.1 s ICS reply timeout.
ICS_REPLY_GATE_S = 0.04


def _parse_hostport(value: str) -> tuple[str, int]:
    host, sep, port = value.rpartition(":")
    if not sep or not port.isdigit() or not 0 <= int(port) <= 65535:
        raise click.BadParameter("expected HOST:PORT, e.g. 127.0.0.1:0")
    return host or "127.0.0.1", int(port)


def _parse_ad(value: str) -> tuple[int, int]:
    ch, sep, counts = value.partition("=")
    ch = ch.strip().upper().removeprefix("AD")
    if not sep or not ch.isdigit() or not counts.strip().isdigit():
        raise ValueError(f"expected CH=COUNTS, e.g. 1=300, got {value!r}")
    return int(ch), int(counts)


@click.command("emulate")
@click.option("--pty", "use_pty", is_flag=True, help="Serve on a new pseudo-terminal.")
@click.option("--tcp", "tcp", metavar="HOST:PORT", help="Serve on TCP (e.g. 127.0.0.1:0).")
@click.option(
    "--rom",
    "rom",
    type=click.Path(dir_okay=False),
    help="Persistent 256 KB ROM image file (created from the default board if missing, in a "
    "directory that exists; rewritten only when the ROM changes); a HeartToHeart4 project's "
    "image is made with `rcb4hv project build`.",
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
@click.option(
    "--ics-comm",
    is_flag=True,
    help="Answer 0Eh (ICS communication) from emulated ICS servos on the SIO lines "
    "(the servo slots' servos); without it 0Eh is NAKed as before.",
)
@click.option(
    "--ad",
    "ad",
    multiple=True,
    metavar="CH=COUNTS",
    help="The input of AD channel CH (1-10), 0..1023 counts of 0-5 V (repeatable). The "
    "measured register reads the input minus the channel's reference (e.g. a gyro at rest "
    "reads its reference: measured 0).",
)
@handle_errors
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
    ics_comm: bool,
    ad: tuple[str, ...],
) -> None:
    """Run the board emulator until interrupted (SIGINT/SIGTERM: clean exit 0).

    Prints one line, ``PTY <path>`` or ``TCP <host>:<port>``, as soon as it is ready.
    """
    from rcb4hv.emulator import Board, BootClock, EmulatorConfig, boot_to_main_loop
    from rcb4hv.emulator.config import ad_inputs_from

    if use_pty == (tcp is not None):
        raise click.UsageError("give exactly one of --pty or --tcp HOST:PORT")
    if not speed > 0:
        raise click.BadParameter("must be > 0", param_hint="--speed")
    kwargs: dict[str, object] = {"pace_replies": pace, "ics_comm": ics_comm}
    try:
        kwargs["ad_inputs"] = ad_inputs_from(_parse_ad(a) for a in ad)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--ad") from exc
    if latency is not None:
        kwargs["min_reply_latency_s"] = latency
    if frame_timeout is not None:
        kwargs["frame_timeout_s"] = frame_timeout
    try:
        config = EmulatorConfig(**kwargs)  # type: ignore[arg-type]
    except ValueError as exc:
        raise click.UsageError(str(exc)) from exc
    if rom is not None and Path(rom).exists():
        from rcb4hv.cli.project_common import read_rom_image

        read_rom_image(  # a file of another size is refused before the board starts
            Path(rom),
            f"--rom takes a ROM image; build the project's with `rcb4hv project build {rom} "
            "-o IMAGE.bin`",
        )
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
    _serve(board, use_pty, tcp, f"speed {speed:g}")


def _serve(
    device: Served, use_pty: bool, tcp: str | None, what: str, reply_gate_s: float = 0.0
) -> None:
    """Serve ``device`` on a pty or TCP until SIGINT/SIGTERM; print ``PTY``/``TCP`` first."""
    stop = threading.Event()

    def handler(signum: int, frame: FrameType | None) -> None:
        stop.set()

    try:
        server, line = _open_server(device, use_pty, tcp, reply_gate_s)
    except BaseException:
        _close(device)
        raise
    signal.signal(signal.SIGINT, handler)  # once serving: a failed start exits as errors do
    signal.signal(signal.SIGTERM, handler)
    server.start()
    print(line, flush=True)
    log.info("emulator serving (%s), %s", line, what)
    try:
        while not stop.wait(0.5):
            if server.error is not None:
                break
    finally:
        server.stop()
        _close(device)
    if server.error is not None:
        sys.exit(1)


def _open_server(
    device: Served, use_pty: bool, tcp: str | None, reply_gate_s: float
) -> tuple[PtyServer | TcpServer, str]:
    """The (not yet started) server of ``device`` and the line that announces it."""
    from rcb4hv.emulator.ptywatch import WatchingPtyServer
    from rcb4hv.emulator.server import PtyServer, TcpServer

    if use_pty:
        pty = (
            WatchingPtyServer(device, reply_gate_s=reply_gate_s)
            if reply_gate_s > 0
            else PtyServer(device)
        )
        return pty, f"PTY {pty.path}"
    assert tcp is not None
    host, port = _parse_hostport(tcp)
    try:
        server = TcpServer(device, host, port)
    except OSError as exc:  # an address not of this host, a port in use: one line, no trace
        why = os.strerror(exc.errno) if exc.errno else str(exc)
        raise OSError(f"cannot listen on TCP {host}:{port}: {why}") from None
    return server, f"TCP {server.address[0]}:{server.address[1]}"


def _close(device: Served) -> None:
    close = getattr(device, "close", None)
    if close is not None:
        close()


@click.command("emulate-ics")
@click.option("--pty", "use_pty", is_flag=True, help="Serve on a new pseudo-terminal.")
@click.option("--tcp", "tcp", metavar="HOST:PORT", help="Serve on TCP (e.g. 127.0.0.1:0).")
@click.option("--ids", default="0", show_default=True, help="Servo IDs on the bus, e.g. 0,1,5.")
@click.option(
    "--baud",
    type=click.Choice(["115200", "625000", "1250000"]),
    default="115200",
    show_default=True,
    help="The servos' baud rate (EEPROM). A pty cannot see the host's rate or parity: "
    "every servo answers whatever the host set.",
)
@click.option("--speed", type=float, default=1.0, show_default=True, help="Clock speed factor.")
@click.option(
    "--version",
    "ics_version",
    type=click.Choice(["3.5", "3.6"]),
    default="3.6",
    show_default=True,
    help="3.5: the servos do not answer the ICS 3.6 position read (sc 5).",
)
@click.option("--pace", is_flag=True, help="Pace replies at the baud rate (11 bits a byte).")
@handle_errors
def emulate_ics(
    use_pty: bool,
    tcp: str | None,
    ids: str,
    baud: str,
    speed: float,
    ics_version: str,
    pace: bool,
) -> None:
    """Run an emulated ICS 3.5/3.6 servo bus until interrupted (one servo, ID 0, by default).

    Prints one line, ``PTY <path>`` or ``TCP <host>:<port>``, as soon as it is ready. The
    host hears its own bytes echoed before each reply, as on the real half-duplex wire.
    """
    from rcb4hv.emulator import RealClock
    from rcb4hv.ics import EmulatedBus, IcsSettings, ServeOptions, parse_ids

    if use_pty == (tcp is not None):
        raise click.UsageError("give exactly one of --pty or --tcp HOST:PORT")
    if not speed > 0:
        raise click.BadParameter("must be > 0", param_hint="--speed")
    try:
        id_list = parse_ids(ids)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--ids") from exc
    settings = IcsSettings(version="3.5" if ics_version == "3.5" else "3.6")
    bus = EmulatedBus.with_ids(id_list, clock=RealClock(speed), settings=settings, baud=int(baud))
    bus.config = ServeOptions(pace_replies=pace)
    _serve(bus, use_pty, tcp, f"ICS IDs {list(id_list)} at {baud} baud", ICS_REPLY_GATE_S)


def register(cli: click.Group) -> None:
    """Add this module's commands to ``cli``."""
    cli.add_command(emulate)
    cli.add_command(emulate_ics)
