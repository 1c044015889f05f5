"""``rcb4hv project simulate --physics``: the motions played on the robot in MuJoCo.

Wired into :mod:`rcb4hv.cli.project_sim_cmd` (the options) and
:mod:`rcb4hv.cli.project_check_cmd` (``check --physics``); the work is
:mod:`rcb4hv.project.physics_sim`.
"""

from __future__ import annotations

import math
import time
from pathlib import Path

import click

from rcb4hv.cli._output import plot_to
from rcb4hv.cli._util import print_json, print_table
from rcb4hv.project.physics_sim import FALL_TILT_DEG, PhysicsOutcome, TrackPoint
from rcb4hv.project.simresult import MotionResult
from rcb4hv.robot.model import RobotModel
from rcb4hv.rom.layout import MotionLayout

__all__ = [
    "parse_sequence",
    "physics_robot",
    "plot_trajectory",
    "print_physics",
    "run_physics",
]


def parse_sequence(text: str) -> list[int]:
    """``33,15`` -> [33, 15] (motion slots 1-120)."""
    try:
        slots = [int(p) for p in text.replace(" ", "").split(",") if p]
    except ValueError:
        raise click.BadParameter(f"{text!r}: give motion slots separated by commas") from None
    if not slots or any(not 1 <= s <= 120 for s in slots):
        raise click.BadParameter(f"{text!r}: motion slots are 1-120")
    return slots


def physics_robot(file: Path, image: bytes, robot: str | None) -> RobotModel:
    """The robot model for ``file``: ``--robot`` or detected from the project's servo table."""
    from rcb4hv.project.physics_sim import project_robot
    from rcb4hv.protocol.memory import NO_BLOCK, read_alloc
    from rcb4hv.rom import layout

    names = None
    if file.suffix.lower() == ".h4p":
        from rcb4hv.hth4 import load_project

        project = load_project(file)
        names = {s.ics_number: s.name or "" for s in project.servos if s.in_use}
    used = [
        n
        for n in range(layout.SERVO_BLOCK_COPY_COUNT)
        if read_alloc(image, n, at=layout.ALLOC_IMAGE) != NO_BLOCK
    ]
    if names is not None:
        used = [n for n in used if n in names]
    return project_robot(robot, names, used)


def run_physics(
    image: bytes,
    lay: MotionLayout,
    names: dict[int, str],
    slots: list[int],
    model: RobotModel,
    *,
    sequence: bool,
    limit: float,
    hold: int,
    hold_for: float,
    track: bool,
) -> tuple[
    MotionResult, list[tuple[MotionResult, PhysicsOutcome]], dict[str, object], list[TrackPoint]
]:
    """Play ``slots`` on ``model``; (boot, results, the top-level ``physics`` object, path)."""
    from rcb4hv.project.physics_sim import play_physics

    t0 = time.perf_counter()
    boot, results, virtual, path = play_physics(
        image,
        model,
        slots,
        names,
        motion_layout=lay,
        sequence=sequence,
        limit=limit,
        hold=hold,
        hold_for=hold_for,
        track=track,
    )
    wall = time.perf_counter() - t0
    summary: dict[str, object] = {
        "robot": model.name,
        "virtual_s": round(virtual, 3),
        "wall_s": round(wall, 3),
    }
    return boot, results, summary, path


def print_physics(
    boot: MotionResult,
    results: list[tuple[MotionResult, PhysicsOutcome]],
    summary: dict[str, object],
    as_json: bool,
) -> None:
    """The table (or JSON) of a physics run."""
    if as_json:
        motions = []
        for r, o in results:
            d = r.to_dict()
            d["physics"] = o.to_dict()
            motions.append(d)
        print_json({"boot": boot.to_dict(), "motions": motions, "physics": summary})
        return
    click.echo(
        f"robot {summary['robot']}: boot {boot.status}, then standing on flat ground "
        f"({summary['virtual_s']} s virtual in {summary['wall_s']} s)"
    )
    print_table(
        ("slot", "name", "status", "fell", "end pose", "dx m", "dy m", "dyaw°", "tilt°", "err°"),
        [
            [
                r.slot or "-",
                r.name,
                r.status,
                f"at {o.fell_at_s:.2f} s" if o.fell_at_s is not None else "no",
                o.end_pose,
                f"{o.dx_m:+.3f}",
                f"{o.dy_m:+.3f}",
                f"{o.dyaw_deg:+.1f}",
                f"{o.max_tilt_deg:.1f}",
                f"{o.max_tracking_error_deg:.1f}",
            ]
            for r, o in results
        ],
    )
    for r, o in results:
        if o.saturated_joints:
            click.echo(f"slot {r.slot}: at the torque limit: {', '.join(o.saturated_joints)}")


def plot_trajectory(path: Path, points: list[TrackPoint]) -> None:
    """The torso's path on the floor (x, y), fallen stretches in red."""
    with plot_to(path, (7.0, 7.0)) as ax:
        xs = [p.x for p in points]
        ys = [p.y for p in points]
        ax.plot(xs, ys, linewidth=1.0, color="tab:blue", label="torso")
        down = [p for p in points if p.tilt >= math.radians(FALL_TILT_DEG)]
        if down:
            ax.scatter([p.x for p in down], [p.y for p in down], s=4, color="tab:red",
                       label=f"fallen (tilt ≥ {FALL_TILT_DEG:g}°)")  # fmt: skip
        if points:
            ax.scatter([xs[0]], [ys[0]], marker="o", color="black", label="start")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (m, forward at the start)")
        ax.set_ylabel("y (m, left)")
        ax.legend(fontsize=8, loc="best")
        ax.grid(True, linewidth=0.3)
