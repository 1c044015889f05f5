"""``rcb4hv ics ...``: ICS servo maintenance (scan, ID, parameters, EEPROM backup, position).

The bus is a Kondo USB adapter HS switched to ICS mode (8E1), the ICS emulator
(``icsemu://``, or the pty/TCP of ``rcb4hv emulate-ics``), or a board in between
(``--via-board``: 0Eh, which the reference calls unusable on real boards).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

import click

from rcb4hv.cli._util import handle_errors, print_json, print_table
from rcb4hv.protocol import POSITION_MAX, POSITION_MIN

F = TypeVar("F", bound=Callable[..., Any])

# names `get`/`set` take: the EEPROM fields and flags, plus `baud`; "limits" is both pulses
NAMES = (
    "stretch",
    "speed",
    "punch",
    "dead_band",
    "damping",
    "safe_timer",
    "response",
    "max_pulse",
    "min_pulse",
    "temperature_limit",
    "current_limit",
    "user_offset",
    "reverse",
    "free",
    "rotation",
    "slave",
    "pwm_inhibit",
    "baud",
    "stretch_1",
    "stretch_2",
    "stretch_3",
)
ALIASES = {"limits": ("min_pulse", "max_pulse"), "deadband": ("dead_band",)}


@dataclass(frozen=True, slots=True)
class IcsTarget:
    """Where the bus is (the group's options)."""

    port: str | None
    baud: int
    via_board: bool
    line: int
    as_json: bool

    def open(self) -> Any:
        from rcb4hv.ics import BoardIcsLink, IcsBus, SerialIcsLink
        from rcb4hv.transport import SerialTransport
        from rcb4hv.transport.serial_port import resolve_port

        if self.via_board:  # the board's port
            url = resolve_port(self.port)
            if url.lower().startswith("icsemu:"):
                raise click.UsageError(
                    f"{url} is an ICS bus (servos), not a board, so --via-board does not apply: "
                    "drop it, or give a board's port (e.g. rcb4emu://?ics_comm=1)"
                )
            return IcsBus(BoardIcsLink(SerialTransport.open(url, self.baud), self.line))
        # the adapter in ICS mode: never the board's $RCB4HV_PORT (ICS bytes to an RCB-4)
        url = resolve_port(self.port, ICS_PORT_ENV, "icsemu://")
        # a servo that does not answer: the error says which --baud to try
        return IcsBus(SerialIcsLink(SerialTransport.open(url, self.baud), baud_option="--baud"))


ICS_PORT_ENV = "RCB4HV_ICS_PORT"
"""The ICS tools' default port (the adapter in ICS mode), apart from the board's."""

PORT_HELP = (
    "The adapter in ICS mode (/dev/ttyUSB0), a pty or socket:// of `rcb4hv emulate-ics`, "
    "icsemu://?ids=0,1 (in process), or with --via-board the board's port. "
    "Default: $RCB4HV_ICS_PORT, else the Kondo USB adapter."
)


def _target_options(func: F, *, group: bool) -> F:
    """The bus options (``--port``, ``--baud``, ``--via-board``, ``--line``, ``--json``), on the
    ``ics`` group (with their defaults) or on a subcommand (where an option given overrides
    the group's: ``rcb4hv ics scan --port X`` as ``rcb4hv ics --port X scan``, the way the
    board commands take ``--port`` after the command)."""
    options = [
        click.option(
            "--port",
            envvar=ICS_PORT_ENV if group else None,
            default=None,
            metavar="URL",
            help=PORT_HELP,
        ),
        click.option(
            "--baud",
            type=click.Choice(["115200", "625000", "1250000"]),
            default="115200" if group else None,
            show_default=group,
            help="ICS baud rate (the board's COM rate with --via-board).",
        ),
        click.option("--via-board", is_flag=True, help="Reach the servos through a board's 0Eh."),
        click.option(
            "--line",
            type=click.IntRange(0, 35),
            default=0 if group else None,
            show_default=group,
            help="With --via-board: the ICS number whose SIO line to use (even: SIO1-4, "
            "odd: SIO5-8).",
        ),
        click.option("--json", "as_json", is_flag=True, help="Print JSON."),
    ]
    for option in reversed(options):
        func = option(func)
    return func


def _pass_target(func: F) -> F:
    """The bus options on a subcommand, and the :class:`IcsTarget` (the group's options,
    overridden by the subcommand's) as its first argument."""

    @functools.wraps(func)
    def wrapper(
        *args: Any,
        port: str | None,
        baud: str | None,
        via_board: bool,
        line: int | None,
        as_json: bool,
        **kwargs: Any,
    ) -> Any:
        base = click.get_current_context().find_object(IcsTarget)
        assert base is not None  # set by the ics group
        target = IcsTarget(
            base.port if port is None else port,
            base.baud if baud is None else int(baud),
            base.via_board or via_board,
            base.line if line is None else line,
            base.as_json or as_json,
        )
        return func(target, *args, **kwargs)

    return _target_options(wrapper, group=False)  # type: ignore[return-value]


def _servo_id(bus: Any, servo_id: int | None) -> int:
    """The ID given, else the one servo on the bus (ID read, as Kondo's tools do)."""
    return int(bus.read_id()) if servo_id is None else servo_id


def _names(items: tuple[str, ...]) -> list[str]:
    out: list[str] = []
    for item in items or ("all",):
        if item == "all":
            out += [n for n in NAMES if n not in out]
        elif item in ALIASES:
            out += ALIASES[item]
        elif item in NAMES:
            out.append(item)
        else:
            raise click.BadParameter(f"{item!r}: one of {', '.join(NAMES)}, limits or all")
    return out


def _print_changes(target: IcsTarget, servo_id: int, changes: dict[str, Any]) -> None:
    if target.as_json:
        print_json({"id": servo_id, "changed": {k: list(v) for k, v in changes.items()}})
        return
    if not changes:
        click.echo(f"servo {servo_id}: nothing changed")
    for name, (before, after) in changes.items():
        click.echo(f"servo {servo_id}: {name} {before} -> {after}")
    if "baud" in changes:
        click.echo(
            f"warning: servo {servo_id} now talks at {changes['baud'][1]} baud; "
            "the host must follow (--baud) to reach it again",
            err=True,
        )


id_option = click.option(
    "--id", "servo_id", type=click.IntRange(0, 31), default=None, help="Servo ID [default: ask]."
)


@click.group("ics")
@functools.partial(_target_options, group=True)
@click.pass_context
def ics(
    ctx: click.Context, port: str | None, baud: str, via_board: bool, line: int, as_json: bool
) -> None:
    """ICS servo maintenance: IDs, parameters, EEPROM backups, positions."""
    ctx.obj = IcsTarget(port, int(baud), via_board, line, as_json)


@ics.command()
@click.option("--ids", default="0-31", show_default=True, help="IDs to try, e.g. 0-17 or 0,2,5.")
@_pass_target
@handle_errors
def scan(target: IcsTarget, ids: str) -> None:
    """List the IDs that answer."""
    wanted = _parse_range(ids)
    with target.open() as bus:
        found = bus.scan(wanted)
    if target.as_json:
        print_json({"ids": found})
    else:
        click.echo(" ".join(map(str, found)) if found else "no servo answered")
    if not found and target.via_board:
        click.echo(
            f"(through the board: it answered NAK to every 0Eh request on the line of ICS "
            f"{target.line}: no servo there, or a board that does not serve 0Eh; the emulator "
            "serves it with --ics-comm)",
            err=True,
        )


def _parse_range(text: str) -> list[int]:
    out: list[int] = []
    for part in text.split(","):
        lo, _, hi = part.strip().partition("-")
        try:
            a, b = int(lo), int(hi or lo)
        except ValueError:
            raise click.BadParameter(f"{text!r}: IDs like 0-31 or 0,2,5") from None
        if not 0 <= a <= b <= 31:
            raise click.BadParameter(f"{text!r}: IDs are 0..31")
        out += range(a, b + 1)
    return sorted(set(out))


@ics.command("id")
@click.option("--set", "new_id", type=click.IntRange(0, 31), default=None, help="New ID.")
@click.option("--yes", is_flag=True, help="Do not ask (only one servo is on the bus).")
@_pass_target
@handle_errors
def id_cmd(target: IcsTarget, new_id: int | None, yes: bool) -> None:
    """Read the ID of the one servo on the bus, or give it a new one (--set N).

    ID commands reach every servo on the wire: with several servos connected they all take
    the new ID. Connect exactly one servo first.
    """
    with target.open() as bus:
        old = bus.read_id()
        if new_id is None:
            print_json({"id": old}) if target.as_json else click.echo(old)
            return
        if not yes and target.as_json:  # no one to ask: a rename of every servo on the wire
            raise click.UsageError("--json cannot ask: give --yes to change the ID")
        if not yes:
            click.confirm(
                f"Only ONE servo may be on the bus: every servo connected takes the new ID.\n"
                f"Change ID {old} -> {new_id}?",
                abort=True,
            )
        got = bus.write_id(new_id)
    if target.as_json:
        print_json({"id": got, "changed": {"id": [old, got]}})
    else:
        click.echo(f"servo ID {old} -> {got}")


@ics.command()
@click.argument("names", nargs=-1)
@id_option
@_pass_target
@handle_errors
def get(target: IcsTarget, names: tuple[str, ...], servo_id: int | None) -> None:
    """Print parameters (default all): stretch, speed, punch, dead_band, damping, response,
    limits, reverse, free, rotation, baud, ..."""
    wanted = _names(names)
    with target.open() as bus:
        sid = _servo_id(bus, servo_id)
        servo = bus.servo(sid)
        fields = servo.eeprom().fields()
        values = {n: fields[n] for n in wanted}
        for live in ("stretch", "speed"):  # the working value, which 12h may have changed
            if live in values:
                values[f"{live}_live"] = servo.get(live)
    if target.as_json:
        print_json({"id": sid, **values})
    else:
        print_table(["name", "value"], [[k, v] for k, v in values.items()])


@ics.command("set")
@click.argument("assignments", nargs=-1, required=True)
@id_option
@click.option("--live", is_flag=True, help="stretch/speed only: the working value (not kept).")
@_pass_target
@handle_errors
def set_cmd(
    target: IcsTarget, assignments: tuple[str, ...], servo_id: int | None, live: bool
) -> None:
    """Set parameters, e.g. ``stretch=60 speed=100 reverse=1 baud=1250000``; written to the
    EEPROM (kept at power-off), read back and reported."""
    values: dict[str, int] = {}
    for a in assignments:
        name, sep, text = a.partition("=")
        if not sep or name not in NAMES:
            raise click.BadParameter(f"{a!r}: NAME=VALUE with NAME one of {', '.join(NAMES)}")
        try:
            values[name] = int(text, 0)
        except ValueError:
            raise click.BadParameter(f"{a!r}: the value is a number") from None
    with target.open() as bus:
        sid = _servo_id(bus, servo_id)
        changes = bus.servo(sid).set_params(live=live, **values)
    _print_changes(target, sid, changes)


@ics.group()
def eeprom() -> None:
    """Back up and restore a servo's EEPROM (JSON)."""


@eeprom.command("dump")
@click.argument("file", type=click.Path(dir_okay=False))
@id_option
@_pass_target
@handle_errors
def eeprom_dump(target: IcsTarget, file: str, servo_id: int | None) -> None:
    """Save the servo's 64 EEPROM bytes (and its fields, for reading) to FILE."""
    from rcb4hv.ics.backup import save_backup

    with target.open() as bus:
        sid = _servo_id(bus, servo_id)
        data = bus.servo(sid).eeprom()
    save_backup(file, data, sid)
    if target.as_json:
        print_json({"id": sid, "file": file, "fields": data.fields()})
    else:
        click.echo(f"servo {sid}: EEPROM saved to {file}")


@eeprom.command("restore")
@click.argument("file", type=click.Path(exists=True, dir_okay=False))
@id_option
@_pass_target
@handle_errors
def eeprom_restore(target: IcsTarget, file: str, servo_id: int | None) -> None:
    """Write FILE's parameters back; the servo's "do not change" bytes and ID are kept as read,
    and the result is read back and compared."""
    from rcb4hv.ics.backup import load_backup, restore

    backup = load_backup(file)
    with target.open() as bus:
        sid = _servo_id(bus, servo_id)
        changes = restore(bus.servo(sid), backup)
    _print_changes(target, sid, changes)


@ics.command()
@id_option
@click.option(
    "--move",
    "move_to",
    type=click.IntRange(POSITION_MIN, POSITION_MAX),
    default=None,
    help="Target.",
)
@click.option("--free", "make_free", is_flag=True, help="Let the servo go limp.")
@_pass_target
@handle_errors
def position(target: IcsTarget, servo_id: int | None, move_to: int | None, make_free: bool) -> None:
    """Read the position (ICS 3.6), move (--move 3500..11500) or free the servo."""
    if move_to is not None and make_free:
        raise click.UsageError("give --move or --free, not both")
    with target.open() as bus:
        sid = _servo_id(bus, servo_id)
        servo = bus.servo(sid)
        if move_to is not None:
            pos = servo.move(move_to)
        elif make_free:
            pos = servo.free()
        else:
            pos = servo.position()
    if target.as_json:
        print_json({"id": sid, "position": pos})
    else:
        click.echo(pos)


def register(cli: click.Group) -> None:
    """Add ``rcb4hv ics`` to ``cli``."""
    cli.add_command(ics)
