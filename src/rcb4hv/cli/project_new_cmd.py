"""``rcb4hv project new``, ``bind`` and ``settings``: a project for a robot model, remote
bindings and the project-wide settings (the API is :mod:`rcb4hv.hth4.newproject`)."""

from __future__ import annotations

from pathlib import Path

import click

from rcb4hv.cli._util import IntegerType, handle_errors
from rcb4hv.cli.project_common import parse_buttons
from rcb4hv.errors import EditError
from rcb4hv.hth4 import save_project
from rcb4hv.hth4.edit import bind_button
from rcb4hv.hth4.newproject import (
    new_project,
    set_ad_reference,
    set_low_power,
    set_mixing,
    set_startup,
)
from rcb4hv.hth4.session import EditSession
from rcb4hv.protocol.memory import ADDR

__all__ = ["register"]

_FILE = click.Path(exists=True, dir_okay=False, path_type=Path)
_OUT = click.option(
    "-o", "--output", type=click.Path(dir_okay=False, path_type=Path), required=True
)


def register(project: click.Group) -> None:
    """Add ``new``, ``bind`` and ``settings`` to the ``project`` group."""
    project.add_command(new_command)
    project.add_command(bind_command)
    project.add_command(settings_command)


@click.command("new")
@click.option("--robot", "robot_name", required=True, metavar="NAME", help="Robot model.")
@click.option("--title", default=None, help="Project title (default: the model's).")
@_OUT
@handle_errors
def new_command(robot_name: str, title: str | None, output: Path) -> None:
    """Write a new project for robot model NAME: its servo table (trims 0, home positions),
    slot 1 "home position" and the start-up program calling it."""
    from rcb4hv.robot.builtin import load_robot

    model = load_robot(robot_name)
    if output.exists():
        raise EditError(f"{output} exists; a new project does not overwrite a file")
    save_project(new_project(model, title=title), output)
    click.echo(f"{output}: new {model.title} project ({len(model.servos)} servos)")


@click.command("bind")
@click.argument("file", type=_FILE)
@click.option("--motion", "slot", type=click.IntRange(1, 999), required=True, help="Slot.")
@click.option("--button", "buttons", required=True, help="Buttons, e.g. UP,S1; NONE unbinds.")
@click.option("--force", is_flag=True, help="Take the binding from another motion.")
@_OUT
@handle_errors
def bind_command(file: Path, slot: int, buttons: str, force: bool, output: Path) -> None:
    """Start motion --motion of FILE with the remote buttons --button (held together)."""
    word = 0 if buttons.strip().upper() == "NONE" else parse_buttons(buttons)
    session = EditSession.open(file)
    session.apply(bind_button, slot, word, force=force)
    session.save(output)
    click.echo(f"{output}: motion {slot} bound to button word {word:04X}h")


def _slot_or_none(value: int) -> int | None:
    return None if value == 0 else value


def _pair(text: str, what: str) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    if not sep:
        raise click.BadParameter(f"{what}: expected KEY=VALUE, not {text!r}")
    return key.strip(), value.strip()


def _address(text: str) -> int | None:
    """A mixing source: NONE, ADn (its measured word), a RAM address (hex with h or 0x)."""
    t = text.upper()
    if t == "NONE":
        return None
    if t.startswith("AD") and t[2:].isdigit() and int(t[2:]) < ADDR.AD_COUNT:
        return int(ADDR.AD_VALUES + 2 * int(t[2:]))
    return IntegerType().convert(text, None, None)


@click.command("settings")
@click.argument("file", type=_FILE)
@click.option("--startup", type=click.IntRange(0, 999), default=None, help="Slot (0: none).")
@click.option("--low-power", type=click.IntRange(0, 999), default=None, help="Slot (0: none).")
@click.option("--low-power-value", type=click.IntRange(0, 1023), default=None, help="AD0 count.")
@click.option(
    "--mixing",
    multiple=True,
    metavar="ICS.N=SOURCE*RATE",
    help="Mixing input N (1, 2) of servo ICS: SOURCE is ADn, a RAM address or NONE, e.g. "
    "14.1=AD1*8.",
)
@click.option("--ad-reference", multiple=True, metavar="CH=VALUE", help="AD calibration.")
@_OUT
@handle_errors
def settings_command(
    file: Path,
    startup: int | None,
    low_power: int | None,
    low_power_value: int | None,
    mixing: tuple[str, ...],
    ad_reference: tuple[str, ...],
    output: Path,
) -> None:
    """Change the start-up and low-power motions, mixing and the AD calibration of FILE."""
    session = EditSession.open(file)
    if startup is not None:
        session.apply(set_startup, _slot_or_none(startup))
    if low_power is not None or low_power_value is not None:
        slot = _slot_or_none(low_power) if low_power is not None else None
        if low_power is None and session.project.low_power_motion_address >= 0:
            motion = session.project.motion_at(session.project.low_power_motion_address)
            slot = motion.slot if motion is not None else None
        session.apply(set_low_power, slot, low_power_value)
    for text in mixing:
        key, value = _pair(text, "--mixing")
        ics, _, which = key.partition(".")
        source, _, rate = value.partition("*")
        try:
            args = (int(ics), int(which or "1"), _address(source), int(rate or "1"))
        except ValueError:
            raise click.BadParameter(f"--mixing: {text!r} is not ICS.N=SOURCE*RATE") from None
        session.apply(set_mixing, *args)
    for text in ad_reference:
        channel, value = _pair(text, "--ad-reference")
        try:
            session.apply(set_ad_reference, int(channel), int(value, 0))
        except ValueError as exc:
            if isinstance(exc, EditError):
                raise
            raise click.BadParameter(f"--ad-reference: {text!r} is not CH=VALUE") from None
    session.save(output)
    click.echo(f"{output}: settings written")
