"""Helpers shared by the CLI modules: the connection options, error handling, tables, JSON."""

from __future__ import annotations

import functools
import json
import sys
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

import click

from rcb4hv.client import DEFAULT_TIMEOUT, Robot
from rcb4hv.errors import Rcb4Error
from rcb4hv.transport import BAUD_RATES, DEFAULT_BAUD

__all__ = [
    "connection_options",
    "error_line",
    "handle_errors",
    "open_robot",
    "parse_int",
    "print_json",
    "print_table",
]

F = TypeVar("F", bound=Callable[..., Any])


def error_line(exc: BaseException) -> str:
    """The one line the CLI prints for an error: ``error: <message> (<ErrorClass>)``."""
    name = type(exc).__name__
    return f"error: {exc} ({name})" if str(exc) else f"error: {name}"


def handle_errors(func: F) -> F:
    """Turn Rcb4Error / ValueError / OSError into ``error: ...`` on stderr and exit status 1."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return func(*args, **kwargs)
        except BrokenPipeError:
            raise  # the reader went away (e.g. `| head`): main() exits quietly
        except (Rcb4Error, ValueError, OSError) as exc:
            click.echo(error_line(exc), err=True)
            sys.exit(1)

    return wrapper  # type: ignore[return-value]


def _baud(value: str) -> int | None:
    if value == "auto":
        return None
    try:
        rate = int(value)
    except ValueError as exc:
        raise click.BadParameter(f"{value!r} is not a baud rate or 'auto'") from exc
    if rate not in BAUD_RATES:
        raise click.BadParameter(f"{rate} is not one of {', '.join(map(str, BAUD_RATES))}")
    return rate


def connection_options(func: F) -> F:
    """Add ``--port``, ``--baud`` and ``--timeout`` to a command (kwargs port, baud, timeout)."""
    func = click.option(
        "--timeout",
        type=click.FloatRange(min=0.001),
        default=DEFAULT_TIMEOUT,
        show_default=True,
        help="Seconds to wait for each reply.",
    )(func)
    func = click.option(
        "--baud",
        default=str(DEFAULT_BAUD),
        show_default=True,
        help="115200, 625000, 1250000, or 'auto' (ACK check at each rate).",
    )(func)
    func = click.option(
        "--port",
        "port",
        envvar="RCB4HV_PORT",
        default=None,
        metavar="URL",
        help="Serial device or URL: /dev/ttyUSB0, socket://host:port, rfc2217://..., "
        "spy://DEV (hex trace), rcb4emu:// (emulator in process), fault://SPEC@URL. "
        "Default: $RCB4HV_PORT, else the Kondo USB adapter (VID 165C).",
    )(func)
    return func


def open_robot(port: str | None, baud: str, timeout: float) -> Robot:
    """Open the board. An in-process ``rcb4emu://`` board is new for every command, so wait for
    its start-up program (it copies the servo table to RAM) before the command looks at it; a
    real board, or an emulator served by ``rcb4hv emulate``, is used as it is."""
    robot = Robot.open(port, baudrate=_baud(baud), timeout=timeout)
    if port is not None and port.startswith("rcb4emu:"):
        try:
            robot.wait_ready(timeout=10.0)
        except BaseException:
            robot.close()
            raise
    return robot


def parse_int(text: str | int) -> int:
    """An integer in decimal, ``0x..`` or ``..h`` hex (click passes int defaults as they are)."""
    if isinstance(text, int):
        return text
    t = text.strip().lower().replace("_", "")
    try:
        if t.endswith("h"):
            return int(t[:-1], 16)
        return int(t, 0)
    except ValueError as exc:
        raise click.BadParameter(f"{text!r} is not a number (decimal, 0x.. or ..h)") from exc


def print_json(data: object) -> None:
    click.echo(json.dumps(data, indent=2))


def print_table(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> None:
    """A plain aligned table (numbers right-aligned)."""
    cells = [[str(c) for c in r] for r in rows]
    widths = [max([len(h)] + [len(r[i]) for r in cells]) for i, h in enumerate(headers)]
    numeric = [
        all(isinstance(r[i], (int, float)) for r in rows) if rows else False
        for i in range(len(headers))
    ]

    def fmt(row: Sequence[str]) -> str:
        return "  ".join(
            c.rjust(w) if num else c.ljust(w)
            for c, w, num in zip(row, widths, numeric, strict=True)
        ).rstrip()

    click.echo(fmt(list(headers)))
    click.echo("  ".join("-" * w for w in widths))
    for r in cells:
        click.echo(fmt(r))
