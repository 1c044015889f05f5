"""``rcb4hv trim get|set|save``: the board's servo trims (the base value, +2 of each servo
block in RAM, spec 9), and storing them into a HeartToHeart4 project.

``set`` changes the trim in RAM, which the board uses at once and forgets at reset; ``save``
writes the board's trims into the project's servo settings, so building and uploading the
project (``rcb4hv project upload``) makes them permanent.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Final

import click

from rcb4hv.cli._util import (
    Connection,
    handle_errors,
    output_option,
    pass_connection,
    print_json,
    print_table,
)
from rcb4hv.protocol.memory import SERVO

if TYPE_CHECKING:
    from rcb4hv.client import Robot
    from rcb4hv.hth4.model import Project

__all__ = ["register"]


def register(cli: click.Group) -> None:
    cli.add_command(trim)


@click.group()
def trim() -> None:
    """Servo trims on the board: read them, set one, store them into a project."""


def board_trims(conn: Connection) -> dict[int, int]:
    """ICS number -> trim of every servo the board has."""
    with conn.open() as robot:
        return trims_of(robot)


def trims_of(robot: Robot) -> dict[int, int]:
    """ICS number -> trim of every servo ``robot``'s board has."""
    return {s.ics: s.trim for s in robot.discover_servos()}


MOTION_PROBE: Final = 64
"""Bytes of each motion compared between the project and the board's ROM."""


def holds_a_motion_of(robot: Robot, motions: list[tuple[int, bytes]]) -> bool | None:
    """Whether the board's ROM holds one of ``motions`` ((address, first bytes) of a
    project's motions) byte for byte: a board the project was uploaded to does, even after
    later edits of some motions; another robot's board does not. None when there is nothing
    to compare (a project without motions)."""
    if not motions:
        return None
    return any(robot.client.read_rom(a, len(code)) == code for a, code in motions)


def project_motions(project: Project) -> list[tuple[int, bytes]]:
    """(ROM address, first :data:`MOTION_PROBE` bytes) of each motion of ``project``."""
    return [
        (m.address, b"".join(m.frames)[:MOTION_PROBE])
        for m in project.motions
        if m.frames and m.address
    ]


@trim.command("get")
@click.option("--json", "as_json", is_flag=True, help="Print {ics: trim} as JSON.")
@pass_connection
@handle_errors
def get_command(conn: Connection, as_json: bool) -> None:
    """Print each servo's trim."""
    trims = board_trims(conn)
    if as_json:
        print_json({str(k): v for k, v in trims.items()})
    else:
        print_table(["ICS", "trim"], [[k, v] for k, v in sorted(trims.items())])


@trim.command("set", context_settings={"ignore_unknown_options": True})
@click.argument("ics", type=click.IntRange(0, 34))
@click.argument("value", type=int)
@pass_connection
@handle_errors
def set_command(conn: Connection, ics: int, value: int) -> None:
    """Set servo ICS's trim to VALUE in the board's RAM (lost at reset: `trim save` keeps it).

    VALUE may be negative as written (`trim set 2 -240`)."""
    from rcb4hv.hth4.edit import TRIM_LIMIT

    if not -TRIM_LIMIT <= value <= TRIM_LIMIT:
        raise ValueError(f"trim {value} outside -{TRIM_LIMIT}..{TRIM_LIMIT}")
    with conn.open() as robot:
        servos = {s.ics: s for s in robot.discover_servos()}
        if ics not in servos:
            raise ValueError(f"no servo at ICS {ics} (known: {sorted(servos)})")
        address, size = SERVO.F_BASE.span(servos[ics].block_address)
        robot.write_ram(address, value.to_bytes(size, "little", signed=True))
    click.echo(f"ICS {ics}: trim {servos[ics].trim} -> {value}")


@trim.command("save")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@output_option("Where to write the project (default: FILE itself, atomically).", required=False)
@click.option(
    "--force",
    is_flag=True,
    help="Store them even when the board's servos are not the project's.",
)
@pass_connection
@handle_errors
def save_command(conn: Connection, file: Path, output: Path | None, force: bool) -> None:
    """Store the board's trims into project FILE's servo settings.

    The board must be the project's robot, or its trims would land on other joints: its
    servos the project's (the same ICS numbers in use) and its ROM holding at least one of
    the project's motions as uploaded. Another robot's board is refused unless --force,
    which stores only the trims of the servos both use. Each trim that changes is listed."""
    from rcb4hv.errors import EditError
    from rcb4hv.hth4.edit import set_trim
    from rcb4hv.hth4.session import EditSession

    session = EditSession.open(file)
    used = {s.device_number for s in session.project.servos if s.in_use}
    with conn.open() as robot:  # one link: the trims and the motions the ROM holds
        trims = trims_of(robot)
        ours = None if force else holds_a_motion_of(robot, project_motions(session.project))
    if set(trims) != used and not force:
        only_board, only_file = sorted(set(trims) - used), sorted(used - set(trims))
        raise EditError(
            f"the board's servos are not {file.name}'s (ICS only on the board: "
            f"{only_board or 'none'}; only in the project: {only_file or 'none'}): is it "
            "this robot's board? (--force stores the trims of the servos both use)"
        )
    if ours is False:
        raise EditError(
            f"the board's ROM holds none of {file.name}'s motions: is it this robot's board? "
            "(upload the project first, or --force stores the board's trims anyway)"
        )
    both = sorted(set(trims) & used)
    before = {s.device_number: s.trim for s in session.project.servos}
    for ics in both:
        session.apply(set_trim, ics, trims[ics])
    session.save(output or file)
    for ics in both:
        if before.get(ics) != trims[ics]:
            click.echo(f"  ICS {ics}: trim {before.get(ics)} -> {trims[ics]}")
    skipped = len(trims) - len(both)
    note = f" ({skipped} of the board's not in the project: left out)" if skipped else ""
    click.echo(f"{output or file}: trims of {len(both)} servos stored{note}")
