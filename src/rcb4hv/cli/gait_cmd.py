"""``rcb4hv gait``: generate a walk for a robot model and store it as a HeartToHeart4 motion."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import get_args

import click

from rcb4hv.cli._util import MOTION_SLOT, connection_options, handle_errors, open_robot
from rcb4hv.errors import GaitError, RobotModelError
from rcb4hv.files import write_atomic
from rcb4hv.gait.pattern import Direction
from rcb4hv.robot.model import RobotModel

DIRECTION = click.option(
    "--direction", type=click.Choice(list(get_args(Direction))), default="forward",
    show_default=True,
)  # fmt: skip
STRIDE = click.option(
    "--stride", type=float, default=None, help="Metres the body travels per step."
)
TURN = click.option("--turn", type=float, default=None, help="Degrees the body turns per step.")
RAY = click.option(
    "--ray", "ray_address", is_flag=False, flag_value="", default=None, metavar="[ADDRESS]",
    help="Run the trials as Ray tasks (a local Ray, or the cluster at ADDRESS).",
)  # fmt: skip
"""``--ray [ADDRESS]`` of ``gait tune`` and ``project robust``."""


def register(cli: click.Group) -> None:
    cli.add_command(gait_command)


def _given(ctx: click.Context, name: str) -> bool:
    return ctx.get_parameter_source(name) == click.core.ParameterSource.COMMANDLINE


def _check_ignored(ctx: click.Context, direction: str, into: Path | None) -> None:
    """A usage error for an option this walk would ignore: ``--turn`` on a walk that does
    not turn, ``--stride`` on a turn, and the stored motion's ``--slot``, ``--button``,
    ``--name`` and ``--replace`` without ``--into`` (a walk only played is stored nowhere)."""
    turning = direction.startswith("turn-")
    if _given(ctx, "turn") and not turning:
        raise click.UsageError(
            f"--turn is the turn per step of turn-left/turn-right; a {direction} walk does not turn"
        )
    if _given(ctx, "stride") and turning:
        raise click.UsageError(f"--stride is a walk's step length; {direction} turns on the spot")
    if into is None:
        stored = [f"--{n}" for n in ("slot", "button", "name", "replace") if _given(ctx, n)]
        if stored:
            raise click.UsageError(
                f"{', '.join(stored)}: the motion is stored only with --into FILE.h4p"
            )


@click.group("gait", invoke_without_command=True)
@click.option("--robot", "robot_name", default=None, help="Robot model (rcb4hv robot list).")
@DIRECTION
@click.option("--steps", type=click.IntRange(1, 40), default=6, show_default=True)
@STRIDE
@TURN
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
@click.option("--play", is_flag=True, help="Play the walk on the board (implied by --port URL).")
@connection_options
@handle_errors
@click.pass_context
def gait_command(
    ctx: click.Context, robot_name: str | None, direction: Direction, steps: int,
    stride: float | None, turn: float | None, lift: float | None, width: float | None,
    step_time: float | None,
    into: Path | None, slot: int | None, button: str, name: str | None, replace: bool,
    as_json: bool, play: bool, port: str | None, baud: int | None, timeout: float,
) -> None:  # fmt: skip
    """Generate a walk (ZMP preview control and the one IK) for ROBOT and store it as a
    motion (--into), and/or play it on a board (--play --port URL). ``gait tune`` searches
    the parameters that fall least."""
    if ctx.invoked_subcommand is not None:
        return
    if robot_name is None:
        raise click.UsageError("which robot: --robot NAME (rcb4hv robot list)")
    # --port on the command line sends the walk to that board (RCB4HV_PORT alone does not)
    play = play or _given(ctx, "port")
    from rcb4hv.cli.project_common import parse_buttons
    from rcb4hv.gait.generate import default_params, walk
    from rcb4hv.gait.motion import load_or_new, period_ms, walk_motion
    from rcb4hv.hth4 import dump_project, parse_project
    from rcb4hv.hth4.keyframes import add_motion, free_slots
    from rcb4hv.project.relocate import project_layout
    from rcb4hv.robot.builtin import load_robot

    _check_ignored(ctx, direction, into)
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
            raise GaitError(f"{into} has no free motion slot")
        slot = free[0]
    stored = walk_motion(
        model, w, slot=slot, name=name or f"gait {direction}", period=period,
        button=parse_buttons(button) if button else 0,
        layout=project_layout(project) if project is not None else None,
    )  # fmt: skip
    motion, every, loop = stored.motion, stored.every, stored.loop
    turning = direction.startswith("turn-")
    summary = {
        "robot": model.name, "direction": direction, "steps": steps,
        "slot": slot if into is not None else None,
        "stride_m": None if turning else params.stride,
        "turn_deg": params.turn if turning else None, "lift_m": params.lift,
        "width_m": params.width, "step_time_s": params.step_time,
        "commanded": params.commanded, "commanded_unit": "deg" if turning else "m",
        "seconds": len(w.poses) * period / 1000.0,
        "periods_per_pose": every, "looped_cycles": 0 if loop is None else loop.repeats,
        "ik_missed": w.missed, "ik_worst_mm": w.worst_error * 1000,
    }  # fmt: skip
    if project is not None and into is not None:
        data = dump_project(add_motion(project, motion, replace_used=replace))
        if dump_project(parse_project(data)) != data:
            raise ValueError("the new project does not round-trip; nothing written")
        write_atomic(into, data)
    if play:
        from rcb4hv.gait.motion import play_moves

        robot = open_robot(port, baud, timeout)
        try:
            _check_board(robot.servo_ids(), model)
            play_moves(robot.client, stored.moves, period, time.sleep)
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
        + ("" if loop is None else f", its middle {loop.repeats} cycles of two steps looped")
    )


def _check_board(board: list[int], model: RobotModel) -> None:
    """Refuse to play ``model``'s walk on a board that has not its servos (a KXR-L2 walk on
    a KHR-3HV board sends every leg value to the wrong joint)."""
    missing = sorted({s.index for s in model.servos} - set(board))
    if missing:
        raise RobotModelError(
            f"the board has no servo at ICS {', '.join(map(str, missing))}, which "
            f"{model.name}'s walk drives: is it the robot the walk is for? (--robot)"
        )


@gait_command.command("tune")
@click.option("--robot", "robot_name", required=True, help="Robot model (rcb4hv robot list).")
@DIRECTION
@click.option("--steps", type=click.IntRange(1, 40), default=4, show_default=True)
@STRIDE
@TURN
@click.option("--trials", type=click.IntRange(min=1), default=8, show_default=True)
@click.option(
    "--evaluations",
    type=click.IntRange(min=1),
    default=16,
    show_default=True,
    help="Walks to try, in generations of 4 (CMA-ES asks 4 at a time); fewer if it converges.",
)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--workers", type=click.IntRange(min=1), default=None, help="Processes (cores).")
@RAY
@click.option(
    "--into", type=click.Path(dir_okay=False, path_type=Path), required=True,
    help="Store the best walk in this .h4p (new if missing).",
)  # fmt: skip
@click.option("--slot", type=MOTION_SLOT, default=None, help="Motion slot (default: first free).")
@click.option(
    "--report", type=click.Path(dir_okay=False, path_type=Path), default=None,
    help="Write every candidate and the best as JSON here.",
)  # fmt: skip
@handle_errors
def tune_command(
    robot_name: str, direction: Direction, steps: int, stride: float | None, turn: float | None,
    trials: int, evaluations: int, seed: int, workers: int | None, ray_address: str | None,
    into: Path, slot: int | None, report: Path | None,
) -> None:  # fmt: skip
    """CMA-ES over lift, step time, double support and width: the walk that falls least over
    TRIALS physics trials (docs/gait.md), stored in --into, with a --report. A progress bar on
    a terminal; Ctrl-C stops the search, stores the best walk so far and exits with 130."""
    from dataclasses import asdict

    from tqdm import tqdm

    from rcb4hv.gait.generate import default_params, walk
    from rcb4hv.gait.motion import load_or_new, period_ms, walk_motion
    from rcb4hv.gait.tune import TuneProgress, planned, tune
    from rcb4hv.hth4 import dump_project
    from rcb4hv.hth4.keyframes import add_motion, free_slots
    from rcb4hv.project.relocate import project_layout
    from rcb4hv.robot.builtin import load_robot

    model = load_robot(robot_name)
    base = default_params(model, direction, steps=steps, stride=stride, turn=turn)
    project = load_or_new(into, model)  # a project for another robot: refused before the search
    period = period_ms(project)  # the candidates play as the walk will: at the project's period
    # the bar of `project robust`: none on a stderr that is no terminal (tqdm's disable=None)
    with tqdm(total=planned(evaluations), unit="walk", disable=None, leave=False) as bar:

        def show(p: TuneProgress) -> None:
            bar.set_postfix_str(f"best {p.best.score:.3f}", refresh=False)
            bar.update(p.done - bar.n)

        result = tune(
            model, base, trials=trials, evaluations=evaluations, seed=seed, workers=workers,
            use_ray=ray_address is not None, ray_address=ray_address or None, period_ms=period,
            progress=show,
        )  # fmt: skip
    best, tried = result.best, result.tried
    stopped = (
        f"interrupted after {len(tried)} of {result.planned} evaluations"
        if result.interrupted
        else ""
    )
    if best is None:  # interrupted before the first walk was scored
        click.echo(f"{stopped}: no walk evaluated; {into} not written", err=True)
        sys.exit(130)
    if slot is None:
        free = free_slots(project)
        slot = free[0] if free else 2
    motion = walk_motion(
        model, walk(model, best.params, period / 1000.0), slot=slot, name=f"tuned {direction}",
        period=period, layout=project_layout(project),
    ).motion  # fmt: skip
    write_atomic(into, dump_project(add_motion(project, motion)))
    doc = {
        "robot": model.name, "trials": trials, "seed": seed, "interrupted": result.interrupted,
        "evaluations": len(tried),
        "best": {**asdict(best.params), "fall_probability": best.fall_probability,
                 "progress": best.progress, "score": best.score},
        "candidates": [{**asdict(c.params), "fall_probability": c.fall_probability,
                        "progress": c.progress, "score": c.score} for c in tried],
    }  # fmt: skip
    if report is not None:
        write_atomic(report, json.dumps(doc, indent=2) + "\n")
    p = best.params
    click.echo(
        f"{into}: motion {slot}: best of {len(tried)}{f' ({stopped})' if stopped else ''}: "
        f"falls {best.fall_probability:.2f}, "
        f"progress {best.progress:.3g} of {p.commanded:.3g}; lift {p.lift * 1000:.1f} mm, "
        f"step {p.step_time:.2f} s, double support {p.double_support:.2f}, "
        f"width {p.width * 1000:.1f} mm"
    )
    if result.interrupted:
        sys.exit(130)
