"""``rcb4hv project new``, ``bind`` and ``settings``: a project for a robot model, remote
bindings and the project-wide settings (the API is :mod:`rcb4hv.hth4.newproject`)."""

from __future__ import annotations

from pathlib import Path

import click

from rcb4hv.cli._util import handle_errors
from rcb4hv.cli.project_common import parse_buttons
from rcb4hv.errors import EditError
from rcb4hv.hth4 import save_project
from rcb4hv.hth4.edit import bind_button
from rcb4hv.hth4.newproject import (
    mixing_source,
    new_project,
    set_ad_reference,
    set_low_power,
    set_mixing,
    set_output_period,
    set_priority,
    set_startup,
)
from rcb4hv.hth4.session import EditSession

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
@click.option(
    "--title", default=None, help="Project title (default: the model's name, e.g. kxr-l2)."
)
@_OUT
@handle_errors
def new_command(robot_name: str, title: str | None, output: Path) -> None:
    """Write a new project for robot model NAME: its servo table (trims 0, home positions:
    the model's home pose; a multi-legged KXR kit's, Kondo's home position for it), slot 1
    "home position" and the start-up program calling it."""
    from rcb4hv.robot.builtin import load_robot

    model = load_robot(robot_name)
    if output.exists():
        raise EditError(f"{output} exists; a new project does not overwrite a file")
    save_project(new_project(model, title=title), output)
    count = "" if "servos" in model.title else f" ({len(model.servos)} servos)"
    click.echo(f"{output}: new {model.title} project{count}")


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
    if word:
        click.echo(f"{output}: motion {slot} bound to button word {word:04X}h")
    else:
        click.echo(f"{output}: motion {slot} unbound (no remote button starts it)")


def _slot_or_none(value: int) -> int | None:
    return None if value == 0 else value


def _pair(text: str, what: str) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    if not sep:
        raise click.BadParameter(f"{what}: expected KEY=VALUE, not {text!r}")
    return key.strip(), value.strip()


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
@click.option(
    "--period",
    type=click.Choice(["10", "15", "20", "25"]),
    default=None,
    help="Servo output period in ms: a pose's frames are periods, so every motion plays at "
    "another speed.",
)
@click.option(
    "--priority",
    multiple=True,
    metavar="I=SLOT,PORT,COMPARE,VALUE",
    help="Priority check I (0-12) calls SLOT when PORT (Battery, AD0-AD10, PA1-PA4) compares "
    "COMPARE (Equals, LessThanOrEqualTo, ...) to VALUE, e.g. 0=2,Battery,LessThanOrEqualTo,223; "
    "I=0 (0 after the =, e.g. 3=0) clears check I.",
)
@_OUT
@handle_errors
def settings_command(
    file: Path,
    startup: int | None,
    low_power: int | None,
    low_power_value: int | None,
    mixing: tuple[str, ...],
    ad_reference: tuple[str, ...],
    period: str | None,
    priority: tuple[str, ...],
    output: Path,
) -> None:
    """Change the start-up and low-power motions, mixing, the AD calibration and the output
    period of FILE."""
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
            address = mixing_source(source)
        except EditError as exc:
            raise click.BadParameter(f"--mixing: {exc}") from None
        try:
            args = (int(ics), int(which or "1"), address, int(rate or "1"))
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
    if period is not None:
        session.apply(set_output_period, int(period))
    for text in priority:
        session.apply(set_priority, *_priority(text))
    session.save(output)
    click.echo(f"{output}: settings written")


def _priority(text: str) -> tuple[int, int | None, str, str, int]:
    from rcb4hv.hth4.newproject import COMPARE, priority_port_source

    index, value = _pair(text, "--priority")
    parts = [p.strip() for p in value.split(",")]
    try:
        if parts == ["0"]:
            return int(index), None, "Battery", "LessThanOrEqualTo", 0
        slot, port, compare, threshold = parts
        if compare not in COMPARE:
            raise click.BadParameter(f"--priority: {compare!r} is not one of {', '.join(COMPARE)}")
        try:
            priority_port_source(port)
        except ValueError as exc:
            raise click.BadParameter(f"--priority: {exc}") from None
        return int(index), int(slot), port, compare, int(threshold, 0)
    except ValueError:
        raise click.BadParameter(f"--priority: {text!r} is not I=SLOT,PORT,COMPARE,VALUE") from None
