"""``rcb4hv project mirror`` and ``rcb4hv project diff``: scripted motion edits and comparing
two projects (the API is :mod:`rcb4hv.hth4.edit`, :mod:`rcb4hv.hth4.diff`)."""

from __future__ import annotations

from pathlib import Path

import click

from rcb4hv.cli._util import error_line, handle_errors, output_option, print_json
from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import load_project
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.hth4.session import EditSession

__all__ = ["register"]

ROBOT_OPTION = click.option(
    "--robot",
    "robot_name",
    default=None,
    metavar="NAME",
    help="Robot model (khr3hv, khr3hv-22, kxr-l2, kxr-l2-gripper, a KXR kit code such as "
    "kxr:L6, or a URDF file with its joint map); default: detected from the project's title "
    "and servo names.",
)


def register(project: click.Group) -> None:
    """Add ``mirror`` and ``diff`` to the ``project`` group."""
    project.add_command(mirror_command)
    project.add_command(diff_command)


@click.command("mirror")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--motion", "slot", type=click.IntRange(1, 999), required=True, help="Slot.")
@click.option(
    "--to",
    "to",
    type=click.IntRange(1, 999),
    default=None,
    help="Free slot for the mirror image (default: mirror the motion in place).",
)
@click.option("--name", default=None, help="Name of the new motion (default: NAME (mirror)).")
@ROBOT_OPTION
@click.option("--force", is_flag=True, help="Keep values outside ranges or joint limits.")
@output_option("Where to write the edited project.")
@handle_errors
def mirror_command(
    file: Path,
    slot: int,
    to: int | None,
    name: str | None,
    robot_name: str | None,
    force: bool,
    output: Path,
) -> None:
    """Mirror motion --motion of FILE left <-> right (into free slot --to) and write -o."""
    from rcb4hv.hth4.edit import mirror_motion
    from rcb4hv.hth4.poses import Checks

    session = EditSession.open(file)
    model = project_model(session.project, robot_name)
    checks = Checks(model, force)
    session.apply(mirror_motion, slot, model, to=to, name=name, checks=checks)
    session.save(output)
    made = session.project.motion(to or slot)
    where = f"slot {to}" if to else "in place"
    click.echo(f"{output}: motion {slot} mirrored {where} as {made.name!r} ({model.name})")


@click.command("diff")
@click.argument("a", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.argument("b", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help='Print {"changes": [...]}.')
def diff_command(a: Path, b: Path, as_json: bool) -> None:
    """What differs from project A to project B: settings, servos, motions, poses, values.

    Exit status 0 when they hold the same data, 1 when they differ, 2 when a file cannot be
    read (as diff(1))."""
    from rcb4hv.hth4.diff import diff_projects

    try:
        changes = diff_projects(load_project(a), load_project(b))
    except (Rcb4Error, ValueError, OSError) as exc:
        click.echo(error_line(exc), err=True)
        raise SystemExit(2) from exc
    if as_json:
        print_json({"changes": [c.to_json() for c in changes]})
    else:
        for c in changes:
            click.echo(c.text)
    raise SystemExit(1 if changes else 0)
