"""``rcb4hv motion`` (play, stop, resume, wait, status) and ``rcb4hv button press``: the
board's program and its virtual remote control."""

from __future__ import annotations

import time

import click

from rcb4hv.cli._util import (
    MOTION_SLOT,
    Connection,
    handle_errors,
    pass_connection,
    print_json,
)
from rcb4hv.client import MotionLayout, Robot
from rcb4hv.errors import ProgramStoppedError
from rcb4hv.protocol import Button
from rcb4hv.rom.layout import LAYOUTS as ROM_LAYOUTS

__all__ = ["register"]

LAYOUTS: dict[str, MotionLayout] = {v: ROM_LAYOUTS[v] for v in ("1.3", "2.0", "2.1", "2.2")}


def _parse_button(name: str) -> Button:
    try:
        return Button[name.upper()]
    except KeyError as exc:
        names = ", ".join(b.name for b in Button if b.name and b is not Button.NONE)
        raise click.BadParameter(f"unknown button {name!r} (one of {names})") from exc


layout_option = click.option(
    "--layout",
    type=click.Choice([*sorted(LAYOUTS), "auto"]),
    default="auto",
    show_default=True,
    help="HeartToHeart4 version the ROM image was written with (auto: read from the ROM).",
)


START_CHECK_S = 0.25
"""How long `motion play` may watch the program run the motion's first instruction (a slot
that holds no motion stops it there with a ROM error, in the board's next cycle)."""


def _check_started(robot: Robot, number: int, address: int) -> None:
    """ProgramStoppedError if the program stopped with a ROM error as motion ``number`` (at
    ``address``) started; returns once it is past the first instruction or out of the motion
    (or after :data:`START_CHECK_S`), without waiting for the end (as ``wait_motion`` does)."""
    deadline = time.monotonic() + START_CHECK_S
    while True:
        st = robot.motion_status()
        if st.rom_error:
            why = f"slot {number} holds no motion" if st.pc == address else f"motion {number}"
            raise ProgramStoppedError(
                f"{why}: the board's program stopped with a ROM error at PC {st.pc:06X} "
                "(`rcb4hv motion stop` sets it going again)",
                st.pc,
                st.motion,
            )
        if st.pc != address or not st.running or time.monotonic() >= deadline:
            return
        time.sleep(0.01)


@click.group()
def motion() -> None:
    """Play, stop and wait for ROM motions (HeartToHeart4 layout)."""


@motion.command("play")
@click.argument("number", type=MOTION_SLOT)
@click.option("--wait/--no-wait", default=False, show_default=True)
@click.option("--wait-timeout", type=click.FloatRange(min=0), default=60.0, show_default=True)
@layout_option
@pass_connection
@handle_errors
def motion_play(
    conn: Connection, number: int, wait: bool, wait_timeout: float, layout: str
) -> None:
    """Play motion NUMBER (1 to the layout's motion count: 120, or 50 in 1.3).

    Exit status 1 when the board's program stops with a ROM error as the motion starts (a
    slot that holds no motion); --wait also waits for the end (and reports a later stop).
    """
    with conn.open() as robot:
        robot.layout = LAYOUTS.get(layout) or robot.layout
        address = robot.board_layout().address(number)
        t0 = time.monotonic()
        robot.play_motion(number)
        _check_started(robot, number, address)
        click.echo(f"playing motion {number} ({address:06X})")
        if wait:
            robot.wait_motion(timeout=wait_timeout)
            click.echo(f"motion {number} ended after {time.monotonic() - t0:.2f} s")


@motion.command("stop")
@click.option("--pause", is_flag=True, help="Only pause (resume continues it).")
@layout_option
@pass_connection
@handle_errors
def motion_stop(conn: Connection, pause: bool, layout: str) -> None:
    """Stop the motion: back to the main loop (or --pause the ROM program)."""
    with conn.open() as robot:
        robot.layout = LAYOUTS.get(layout) or robot.layout
        robot.stop_motion(reset=not pause)
    click.echo("paused" if pause else "stopped; board back in its main loop")


@motion.command("resume")
@pass_connection
@handle_errors
def motion_resume(conn: Connection) -> None:
    """Let a paused ROM program run on."""
    with conn.open() as robot:
        robot.resume_motion()
    click.echo("resumed")


@motion.command("wait")
@click.option("--wait-timeout", type=click.FloatRange(min=0), default=60.0, show_default=True)
@layout_option
@pass_connection
@handle_errors
def motion_wait(conn: Connection, wait_timeout: float, layout: str) -> None:
    """Wait until no motion plays (exit status 1 on timeout)."""
    with conn.open() as robot:
        robot.layout = LAYOUTS.get(layout) or robot.layout
        t0 = time.monotonic()
        robot.wait_motion(timeout=wait_timeout)
    click.echo(f"no motion playing (waited {time.monotonic() - t0:.2f} s)")


@motion.command("status")
@layout_option
@pass_connection
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def motion_status(conn: Connection, layout: str, as_json: bool) -> None:
    """The motion being played (if any), PC, call depth, update flags."""
    with conn.open() as robot:
        robot.layout = LAYOUTS.get(layout) or robot.layout
        st = robot.motion_status()
    if as_json:
        print_json(
            {
                "motion": st.motion,
                "pc": f"{st.pc:06X}",
                "call_depth": st.call_depth,
                "update_flags": st.update_flags.hex(),
                "running": st.running,
                "state": st.state,
            }
        )
    else:
        what = f"motion {st.motion}" if st.motion is not None else "no motion"
        click.echo(
            f"{what} ({st.state}); PC {st.pc:06X}, call depth {st.call_depth}, "
            f"update flags {st.update_flags.hex(' ')}"
        )


@click.group()
def button() -> None:
    """Virtual remote control (button word at 0350h)."""


@button.command("press")
@click.argument("names", nargs=-1, required=True, metavar="BUTTON...")
@click.option("-d", "--duration", type=click.FloatRange(min=0), default=0.3, show_default=True)
@pass_connection
@handle_errors
def button_press(conn: Connection, names: tuple[str, ...], duration: float) -> None:
    """Hold BUTTONs (up, down, left, right, triangle, cross, circle, square, s1-s4)."""
    pressed = Button.NONE
    for n in names:
        pressed |= _parse_button(n)
    with conn.open() as robot:
        robot.press_button(pressed, duration)
    label = "+".join(b.name or "" for b in Button if b and b in pressed)
    click.echo(f"pressed {label} for {duration:g} s")


def register(cli: click.Group) -> None:
    cli.add_command(motion)
    cli.add_command(button)
