"""``rcb4hv gait``: generate a walk for a robot model and store it as a HeartToHeart4 motion."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import get_args

import click

from rcb4hv.cli._util import MOTION_SLOT, connection_options, handle_errors, open_robot
from rcb4hv.files import write_atomic
from rcb4hv.gait.pattern import Direction


def register(cli: click.Group) -> None:
    cli.add_command(gait_command)


@click.command("gait")
@click.option("--robot", "robot_name", required=True, help="Robot model (rcb4hv robot list).")
@click.option(
    "--direction", type=click.Choice(list(get_args(Direction))), default="forward",
    show_default=True,
)  # fmt: skip
@click.option("--steps", type=click.IntRange(1, 40), default=6, show_default=True)
@click.option("--stride", type=float, default=None, help="Metres the body travels per step.")
@click.option("--turn", type=float, default=None, help="Degrees the body turns per step.")
@click.option("--lift", type=float, default=None, help="Swing foot height (m).")
@click.option("--width", type=float, default=None, help="Distance between the feet (m).")
@click.option("--step-time", type=float, default=None, help="Seconds per step.")
@click.option(
    "--into", type=click.Path(dir_okay=False, path_type=Path), default=None,
    help="Add the walk to this .h4p (a new project for the robot if it does not exist).",
)  # fmt: skip
@click.option("--slot", type=MOTION_SLOT, default=None, help="Motion slot (default: first free).")
@click.option("--button", default="", help="Bind to remote buttons, e.g. UP or UP+S1.")
@click.option("--name", default=None, help="Motion name (default: 'gait DIRECTION').")
@click.option("--replace", is_flag=True, help="Overwrite a used slot.")
@click.option("--json", "as_json", is_flag=True, help="Print the walk's summary as JSON.")
@click.option("--play", is_flag=True, help="Play the walk on the board at --port.")
@connection_options
@handle_errors
def gait_command(
    robot_name: str, direction: Direction, steps: int, stride: float | None,
    turn: float | None, lift: float | None, width: float | None, step_time: float | None,
    into: Path | None, slot: int | None, button: str, name: str | None, replace: bool,
    as_json: bool, play: bool, port: str | None, baud: int | None, timeout: float,
) -> None:  # fmt: skip
    """Generate a walk (ZMP preview control and the one IK) for ROBOT and store it as a
    motion (--into), and/or play it on a board (--play --port URL)."""
    from rcb4hv.cli.project_common import parse_buttons
    from rcb4hv.gait.generate import default_params, walk
    from rcb4hv.gait.motion import load_or_new, period_ms, store, walk_motion
    from rcb4hv.hth4 import dump_project, parse_project
    from rcb4hv.hth4.keyframes import free_slots
    from rcb4hv.project.relocate import project_layout
    from rcb4hv.robot.builtin import load_robot

    if into is None and not play:
        raise click.UsageError("say where the walk goes: --into FILE.h4p and/or --play")
    model = load_robot(robot_name)
    params = default_params(
        model, direction, steps=steps, stride=stride, turn=turn, lift=lift, width=width,
        step_time=step_time,
    )  # fmt: skip
    project = load_or_new(into, model) if into is not None else None
    period = period_ms(project) if project is not None else 15
    w = walk(model, params, period / 1000.0)
    if slot is None:
        free = free_slots(project) if project is not None else [2]
        if not free:
            raise ValueError(f"{into} has no free motion slot")
        slot = free[0]
    motion, every = walk_motion(
        model, w, slot=slot, name=name or f"gait {direction}", period=period,
        button=parse_buttons(button) if button else 0,
        layout=project_layout(project) if project is not None else None,
    )  # fmt: skip
    summary = {
        "robot": model.name, "direction": direction, "steps": steps, "slot": slot,
        "stride_m": params.stride, "turn_deg": params.turn, "lift_m": params.lift,
        "width_m": params.width, "step_time_s": params.step_time,
        "commanded": params.commanded, "seconds": len(w.poses) * period / 1000.0,
        "periods_per_pose": every, "ik_missed": w.missed, "ik_worst_mm": w.worst_error * 1000,
    }  # fmt: skip
    if project is not None and into is not None:
        data = dump_project(store(project, motion, replace_used=replace))
        if dump_project(parse_project(data)) != data:
            raise ValueError("the new project does not round-trip; nothing written")
        write_atomic(into, data)
    if play:
        robot = open_robot(port, baud, timeout)
        try:
            from rcb4hv.hth4.poses import motion_blocks

            for b in motion_blocks(motion):
                if b.pose is not None:
                    robot.client.run_const_frame_servo(b.pose.speed, b.pose.values)
                    time.sleep(b.pose.speed * period / 1000.0)
        finally:
            robot.close()
    if as_json:
        click.echo(json.dumps(summary, indent=2))
        return
    where = f"{into}: motion {slot} {motion.name!r}" if into is not None else "played"
    unit = "°" if direction.startswith("turn") else " m"
    click.echo(
        f"{where}: {model.name} {direction}, {steps} steps, {params.commanded:.3g}{unit} "
        f"commanded, {summary['seconds']:.2f} s, a pose every {every} output periods"
    )
