"""``rcb4hv project motion-export``, ``motion-import`` and ``motion-xml``: motions as program
files (JSON, :mod:`rcb4hv.hth4.blocks`) and as HeartToHeart4 flowchart XML."""

from __future__ import annotations

import re
from pathlib import Path

import click

from rcb4hv.cli._util import handle_errors
from rcb4hv.errors import EditError, FileClashError
from rcb4hv.files import file_error, read_bytes, write_atomic
from rcb4hv.hth4.blocks import dump_program, load_program, motion_program, put_program
from rcb4hv.hth4.blocks.flowxml import motion_xml, put_flowchart
from rcb4hv.hth4.edit import bind_button, binding_holders, used_motion
from rcb4hv.hth4.model import Project
from rcb4hv.hth4.motionlist import button_label
from rcb4hv.hth4.session import EditSession
from rcb4hv.project.check import unlisted_servos

__all__ = ["register"]

_FILE = click.Path(exists=True, dir_okay=False, path_type=Path)
_SLOT_FILE = re.compile(r"(\d{1,3})\.(json|xml)")


def register(project: click.Group) -> None:
    """Add ``motion-export``, ``motion-import`` and ``motion-xml`` to the ``project`` group."""
    project.add_command(export_command)
    project.add_command(import_command)
    project.add_command(xml_command)


def _one_or_all(slot: int | None, every: bool) -> None:
    if (slot is None) == (not every):
        raise click.UsageError("give --motion N or --all (one of them)")


@click.command("motion-export")
@click.argument("file", type=_FILE)
@click.option("--motion", "slot", type=click.IntRange(1, 999), default=None, help="Slot.")
@click.option("--all", "every", is_flag=True, help="Every used motion, as DIR/NNN.json.")
@click.option(
    "-o",
    "--output",
    type=click.Path(allow_dash=True, path_type=Path),
    default=None,
    help="File ('-' or none: stdout), or DIR with --all.",
)
@handle_errors
def export_command(file: Path, slot: int | None, every: bool, output: Path | None) -> None:
    """Write motion --motion of FILE as a JSON program (stdout without -o), or --all of them
    into directory -o (one NNN.json per used motion)."""
    _one_or_all(slot, every)
    session = EditSession.open(file)
    project = session.project
    if slot is not None:
        used_motion(project, slot)  # an empty slot has no program to export (as motion-xml)
        text = dump_program(motion_program(project, slot))
        if output is None or str(output) == "-":
            click.echo(text, nl=False)
        else:
            write_atomic(output, text.encode())
            click.echo(f"{output}: motion {slot}")
        return
    if output is None or str(output) == "-":
        raise click.UsageError("--all needs -o DIR")
    _make_directory(output)
    for m in project.used_motions:
        path = output / f"{m.slot:03d}.json"
        write_atomic(path, dump_program(motion_program(project, m.slot)).encode())
    click.echo(f"{output}: {len(project.used_motions)} motions")


def _make_directory(output: Path) -> None:
    """Directory ``output`` for ``--all`` (made if missing); a file there is refused."""
    if output.exists() and not output.is_dir():
        raise FileClashError(
            f"{output} is a file, not a directory: --all writes one NNN.json per motion "
            "into a directory (give -o DIR)",
            str(output),
        )
    try:
        output.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise file_error(exc, output, "create directory") from None


def _put_file(project: Project, slot: int, path: Path) -> Project:
    """``project`` with ``path`` compiled into ``slot``; every error about the file's
    content starts with its name (``turn.json.blocks[1].frames: …``)."""
    if path.suffix.lower() == ".xml":
        return put_flowchart(project, slot, read_bytes(path))
    program = load_program(path)  # its errors start with the file's name
    try:
        return put_program(project, slot, program)
    except EditError as exc:
        if str(exc).startswith("blocks["):
            raise EditError(f"{path.name}.{exc}") from None
        raise


def _drop_taken_bindings(session: EditSession, slots: list[int]) -> list[str]:
    """Unbind each imported motion whose remote binding another motion (not imported) holds:
    the board starts the first one, so the copy would never play from the remote and the
    original would change hands by slot order. Returns a note per binding dropped."""
    notes = []
    for slot in slots:
        m = session.project.motion(slot)
        if m is None or m.is_empty:
            continue
        holders = binding_holders(session.project, *m.button, besides=slots)
        if holders:
            holder = holders[0]
            session.apply(bind_button, slot, 0)
            notes.append(
                f"motion {slot}: {button_label(m.button_data)} already starts motion "
                f"{holder.slot} ({holder.name}): imported without it (`project bind --force` "
                "takes it)"
            )
    return notes


def _unlisted(project: Project, slots: list[int]) -> dict[int, list[int]]:
    return {
        slot: unlisted_servos(project, slot)
        for slot in slots
        if project.motion(slot) is not None and not project.motion(slot).is_empty
    }


def _unlisted_notes(before: Project, after: Project, slots: list[int]) -> list[str]:
    """A note when imported motions move servos the project has not and none of its motions
    moved before: the board skips them, so a program of another robot's project plays only
    in part. (Kondo's projects move a servo or two they do not list.)"""
    used = [m.slot for m in before.used_motions]
    known = {k for ks in _unlisted(before, used).values() for k in ks}
    new = {slot: set(ks) - known for slot, ks in _unlisted(after, slots).items()}
    at = [slot for slot, ks in new.items() if ks]
    if not at:
        return []
    ics = ", ".join(map(str, sorted(set().union(*new.values()))))
    who = f"motion {at[0]} moves" if len(at) == 1 else f"{len(at)} of the imported motions move"
    return [
        f"{who} servos this project's servo table has not (ICS {ics}; the board skips them): "
        "a program of another robot? `project check` lists each"
    ]


@click.command("motion-import")
@click.argument("file", type=_FILE)
@click.argument("program", type=click.Path(exists=True, path_type=Path))
@click.option("--motion", "slot", type=click.IntRange(1, 999), default=None, help="Slot.")
@click.option("--all", "every", is_flag=True, help="Every NNN.json / NNN.xml of directory PROGRAM.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    required=True,
    help="Where to write the project (not '-': a project is a file).",
)
@handle_errors
def import_command(file: Path, program: Path, slot: int | None, every: bool, output: Path) -> None:
    """Compile PROGRAM (a JSON program or a HeartToHeart4 flowchart .xml) into slot --motion of
    FILE, or with --all every NNN.json / NNN.xml of directory PROGRAM into slot NNN; write -o.

    Branches by label follow the program wherever it goes; slots without a file keep their
    motion."""
    _one_or_all(slot, every)
    if str(output) == "-":
        raise click.BadParameter("a project is written to a file, not stdout", param_hint="-o")
    session = EditSession.open(file)
    before = session.project
    if slot is not None:
        if program.is_dir():
            raise click.UsageError("--motion N takes one program file; --all takes a directory")
        session.apply(_put_file, slot, program)
        done = [slot]
    else:
        if not program.is_dir():
            raise click.UsageError("--all takes a directory of NNN.json / NNN.xml files")
        done = []
        for path in sorted(program.iterdir()):
            m = _SLOT_FILE.fullmatch(path.name)
            if m is None:
                continue
            session.apply(_put_file, int(m[1]), path)
            done.append(int(m[1]))
        if not done:
            raise EditError(f"{program}: no NNN.json or NNN.xml files")
    notes = _drop_taken_bindings(session, done)
    notes += _unlisted_notes(before, session.project, done)
    for note in notes:
        click.echo(note, err=True)
    changed = session.changed_slot_numbers  # against the file as loaded, so before saving
    emptied = sorted(set(changed) - {m.slot for m in session.changed_motions})
    session.save(output)
    gone = f" (slot(s) {', '.join(map(str, emptied))} now empty)" if emptied else ""
    click.echo(f"{output}: {len(done)} motion(s) imported, {len(changed)} changed{gone}")


@click.command("motion-xml")
@click.argument("file", type=_FILE)
@click.option("--motion", "slot", type=click.IntRange(1, 999), required=True, help="Slot.")
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, allow_dash=True, path_type=Path),
    required=True,
    help="The .xml file ('-': stdout).",
)
@handle_errors
def xml_command(file: Path, slot: int, output: Path) -> None:
    """Write motion --motion of FILE as a HeartToHeart4 flowchart (.xml), branches included."""
    project = EditSession.open(file).project
    data = motion_xml(project, slot)
    if str(output) == "-":
        text = data.decode("utf-8-sig") if isinstance(data, bytes) else data
        click.echo(text, nl=not text.endswith("\n"))
        return
    write_atomic(output, data)
    click.echo(f"{output}: motion {slot} as a flowchart")
