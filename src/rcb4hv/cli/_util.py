"""Helpers shared by the CLI modules: the connection options, error handling, tables, JSON."""

from __future__ import annotations

import functools
import json
import math
import sys
import unicodedata
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Final, TypeVar
from urllib.parse import parse_qs, urlsplit

import click

from rcb4hv.client import DEFAULT_TIMEOUT, Robot
from rcb4hv.errors import Rcb4Error
from rcb4hv.transport import BAUD_RATES, DEFAULT_BAUD
from rcb4hv.values import parse_address

__all__ = [
    "ADDRESS",
    "BAUD",
    "INTEGER",
    "MOTION_SLOT",
    "NUMBER_FORMS",
    "OUTPUT_FILE",
    "AddressType",
    "BaudType",
    "Connection",
    "IntegerType",
    "connection_options",
    "error_line",
    "handle_errors",
    "open_robot",
    "output_option",
    "parse_int",
    "pass_connection",
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


if TYPE_CHECKING:  # click >= 8.2 types ParamType by its value; older click is not generic
    _IntParam = click.ParamType[int, Any]
    _BaudParam = click.ParamType[int | None, Any]
    _FloatParam = click.ParamType[float, Any]
else:
    _IntParam = _BaudParam = _FloatParam = click.ParamType


class FiniteFloat(_FloatParam):
    """A real number that is not inf or nan (a target, an angle)."""

    name = "number"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        try:
            number = float(value)
        except (TypeError, ValueError):
            self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        return number


FINITE = FiniteFloat()


NUMBER_FORMS: Final = "decimal, 0x.., ..h or $.."
"""The forms :func:`rcb4hv.values.parse_address` reads, as the CLI's errors and help name them."""


class IntegerType(_IntParam):
    """An integer in decimal, ``0x..``, ``..h`` or ``$..`` hex (``_`` separators allowed):
    :func:`rcb4hv.values.parse_address`, the one parser of the CLI's numbers and addresses."""

    name = "integer"
    what = "a number"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> int:
        if isinstance(value, int):  # a default given as an int
            return value
        try:
            return parse_address(str(value))
        except ValueError:
            self.fail(f"{value!r} is not {self.what} ({NUMBER_FORMS})", param, ctx)


class AddressType(IntegerType):
    """A board address: ``0B80h``, ``0x0B80``, ``$000B80`` or ``2944`` (decimal). Every
    command that takes an address reads it with this type; the command checks its range."""

    name = "address"
    what = "an address"


class BaudType(_BaudParam):
    """A baud rate of the board (115200, 625000, 1250000), or ``auto``: ``None``, found by an
    ACK check at each rate."""

    name = "baud"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> int | None:
        if value is None or value == "auto":
            return None
        try:
            rate = int(value)
        except ValueError:
            self.fail(f"{value!r} is not a baud rate or 'auto'", param, ctx)
        if rate not in BAUD_RATES:
            self.fail(f"{rate} is not one of {', '.join(map(str, BAUD_RATES))}", param, ctx)
        return rate


INTEGER: Final = IntegerType()
ADDRESS: Final = AddressType()
MOTION_SLOT: Final = click.IntRange(min=1)
"""A motion slot number. Its upper bound is the layout's (120 in HeartToHeart4 2.x, 50 in
1.3), which the command checks once it knows the layout (``MotionLayout.address``)."""
BAUD: Final = BaudType()
OUTPUT_FILE: Final = click.Path(dir_okay=False, path_type=Path)
"""A file a command writes (through :func:`rcb4hv.files.write_atomic`)."""


def output_option(help: str, *, required: bool = True) -> Callable[[F], F]:
    """``-o/--output FILE``: where the command writes its result."""
    return click.option("-o", "--output", type=OUTPUT_FILE, required=required, help=help)


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
        type=BAUD,
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


def open_robot(port: str | None, baud: int | None, timeout: float) -> Robot:
    """Open the board. An in-process ``rcb4emu://`` board is new for every command, so wait for
    its start-up program (it copies the servo table to RAM) before the command looks at it; a
    real board, an emulator served by ``rcb4hv emulate``, or a board already running in this
    process (``rcb4emu://?board=N``, whose motion a ``motion status`` must see) is used as
    it is."""
    robot = Robot.open(port, baudrate=baud, timeout=timeout)
    if (
        port is not None
        and port.startswith("rcb4emu:")
        and "board" not in parse_qs(urlsplit(port).query)
    ):
        try:
            robot.wait_ready(timeout=10.0)
        except BaseException:
            robot.close()
            raise
    return robot


@dataclass(frozen=True, slots=True)
class Connection:
    """The link a command was given (``--port``, ``--baud``, ``--timeout``): the context object
    :func:`pass_connection` hands to a command. :meth:`open` opens the board when the command
    needs it (after it has checked its own arguments)."""

    port: str | None
    baud: int | None
    timeout: float

    def open(self) -> Robot:
        return open_robot(self.port, self.baud, self.timeout)


_pass_connection_object = click.make_pass_decorator(Connection)


def pass_connection(func: Callable[..., Any]) -> Callable[..., Any]:
    """The connection options on a command, and its :class:`Connection` as the first argument.

    The options become ``ctx.obj`` and reach the command through
    ``click.make_pass_decorator(Connection)``, so every command that talks to a board takes
    one object instead of three options.
    """

    @functools.wraps(func)
    def wrapper(*args: Any, port: str | None, baud: int | None, timeout: float, **kw: Any) -> Any:
        ctx = click.get_current_context()
        ctx.obj = Connection(port, baud, timeout)
        return ctx.invoke(_pass_connection_object(func), *args, **kw)

    return connection_options(wrapper)


def parse_int(text: str | int) -> int:
    """An integer in decimal, ``0x..``, ``..h`` or ``$..`` hex (as :data:`INTEGER`, for values
    found inside another argument such as ``ICS=VALUE``)."""
    return INTEGER.convert(text, None, None)


def print_json(data: object) -> None:
    click.echo(json.dumps(data, indent=2))


def display_width(text: str) -> int:
    """Columns ``text`` takes in a terminal: East Asian wide and full-width characters
    (Japanese servo and motion names) take two, combining marks none."""
    return sum(
        0 if unicodedata.combining(c) else 2 if unicodedata.east_asian_width(c) in "WF" else 1
        for c in text
    )


def print_table(headers: Sequence[str], rows: Sequence[Sequence[object]]) -> None:
    """A plain aligned table (numbers right-aligned), aligned by :func:`display_width`."""
    cells = [[str(c) for c in r] for r in rows]
    widths = [
        max([display_width(h)] + [display_width(r[i]) for r in cells])
        for i, h in enumerate(headers)
    ]
    numeric = [
        all(isinstance(r[i], (int, float)) for r in rows) if rows else False
        for i in range(len(headers))
    ]

    def fmt(row: Sequence[str]) -> str:
        out = []
        for c, w, num in zip(row, widths, numeric, strict=True):
            pad = " " * (w - display_width(c))
            out.append(pad + c if num else c + pad)
        return "  ".join(out).rstrip()

    click.echo(fmt(list(headers)))
    click.echo("  ".join("-" * w for w in widths))
    for r in cells:
        click.echo(fmt(r))
