"""``rcb4hv project simulate --physics``: the motions played on the robot in MuJoCo.

Wired into :mod:`rcb4hv.cli.project_sim_cmd` (the options) and
:mod:`rcb4hv.cli.project_check_cmd` (``check --physics``); the work is
:mod:`rcb4hv.project.physics_sim`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from rcb4hv.cli._util import print_json, print_table
from rcb4hv.robot.geometry import convex_hull

if TYPE_CHECKING:
    from rcb4hv.hth4 import Project
    from rcb4hv.project.physicsresult import ShapeFrame
    from rcb4hv.project.runresult import SimulationRun
    from rcb4hv.robot.model import RobotModel
    from rcb4hv.robot.stride import Stride
    from rcb4hv.rom.layout import MotionLayout

__all__ = [
    "draw_frames",
    "parse_sequence",
    "physics_robot",
    "plot_run",
    "print_physics",
    "stride_text",
]


def parse_sequence(text: str, lay: MotionLayout) -> list[int]:
    """``33,15`` -> [33, 15]: motion slots of the image's layout ``lay`` (1-120 in
    HeartToHeart4 2.x, 1-50 in 1.3)."""
    try:
        slots = [int(p) for p in text.replace(" ", "").split(",")]
    except ValueError:
        raise click.BadParameter(f"{text!r}: give motion slots separated by commas") from None
    if not slots or any(not 1 <= s <= lay.motion_count for s in slots):
        raise click.BadParameter(
            f"{text!r}: motion slots are 1-{lay.motion_count} (HeartToHeart4 {lay.version} layout)"
        )
    return slots


def physics_robot(project: Project | None, image: bytes, robot: str | None) -> RobotModel:
    """The robot model of ``image`` (built from ``project``, None for a raw image):
    ``--robot``, or detected from the project's servo table, title and home pose (else from
    the servo slots the image uses)."""
    from rcb4hv.hth4.robotpick import project_model, servo_table
    from rcb4hv.protocol.memory import NO_BLOCK, read_alloc
    from rcb4hv.rom import layout

    names = None if project is None else servo_table(project)
    used = [
        n
        for n in range(layout.SERVO_BLOCK_COPY_COUNT)
        if read_alloc(image, n, at=layout.ALLOC_IMAGE) != NO_BLOCK
    ]
    if names is not None:
        used = [n for n in used if n in names]
    return project_model(project if project is not None else names, robot, used)


def stride_text(stride: Stride | None) -> str:
    """A motion's no-slip travel as a table cell: dx, dy (m) and turn (degrees)."""
    if stride is None:
        return "-"
    return f"{stride.dx_m:+.3f} {stride.dy_m:+.3f} {stride.dyaw_deg:+.0f}°"


def print_physics(run: SimulationRun, as_json: bool) -> None:
    """The table (or JSON) of a physics run: per motion, the pose it started in (``down at
    start`` when it was down although it stood before), whether it fell, its end pose, where
    it went."""
    if as_json:
        print_json(run.to_dict())
        return
    setup = run.physics
    assert setup is not None
    tilt = dict(setup.what_if).get("floor_tilt_deg", 0.0)
    ground = f"ground tilted {tilt:g}°" if tilt else "flat ground"
    click.echo(
        f"robot {setup.robot} ({setup.engine}): boot {run.boot.status}, then on {ground} "
        f"({setup.start}), settled {setup.settled_pose} after {setup.settle_s:g} s "
        f"({run.virtual_s:.3f} s virtual in {run.wall_s:.3f} s)"
    )
    if setup.what_if:
        changed = ", ".join(f"{name}={value:g}" for name, value in setup.what_if)
        click.echo(f"what-if: {changed} (not the documented model)")
    rows = []
    strides = any(m.stride is not None for m in run.motions)
    for m in run.motions:
        o = m.outcome
        assert o is not None
        if o.fallen_at_start:
            fell = f"down at start ({o.start_pose})"
        elif o.fell_at_s is not None:
            fell = f"at {o.fell_at_s:.2f} s"
        else:
            fell = "no"
        rows.append(
            [
                m.result.slot or "-",
                m.result.name,
                m.result.status,
                o.start_pose,
                fell,
                o.end_pose,
                f"{o.dx_m:+.3f}",
                f"{o.dy_m:+.3f}",
                f"{o.dyaw_deg:+.1f}",
                f"{o.max_tilt_deg:.1f}",
                f"{o.max_tracking_error_deg:.1f}",
            ]
            + ([stride_text(m.stride)] if strides else [])
        )
    print_table(
        ("slot", "name", "status", "start pose", "fell", "end pose", "dx m", "dy m", "dyaw°",
         "tilt°", "err°") + (("no slip",) if strides else ()),
        rows,
    )  # fmt: skip
    for m in run.motions:
        if m.outcome is not None and m.outcome.saturated_joints:
            click.echo(
                f"slot {m.result.slot}: at the torque limit: "
                + ", ".join(m.outcome.saturated_joints)
            )


def draw_frames(
    ax: Any, frames: tuple[ShapeFrame, ...], axis: int = 0, spacing: float = 0.3, t0: float = 0.0
) -> None:
    """Side views of the robot (``axis`` 0: seen from its side, x-z; 1: from the front, y-z),
    one per frame, ``spacing`` m apart, time under each (from ``t0``: a motion's start, the
    time ``--trace`` counts from)."""
    from matplotlib.patches import Polygon

    for k, frame in enumerate(frames):
        shift = k * spacing
        origin = frame.shapes[0][0][axis] if frame.shapes else 0.0
        for corners in frame.shapes:
            hull = convex_hull([(c[axis] - origin + shift, c[2]) for c in corners])
            ax.add_patch(Polygon(hull, closed=True, facecolor="0.6", edgecolor="0.2", lw=0.4))
        ax.annotate(f"{frame.t - t0:.2f} s", (shift, -0.02), ha="center", va="top", fontsize=7)
    ax.axhline(0.0, color="0.3", linewidth=0.8)
    ax.set_xlim(-spacing / 2, max(1, len(frames)) * spacing - spacing / 2)
    ax.set_ylim(-0.05, 0.45)
    ax.set_aspect("equal")
    ax.set_yticks([])
    ax.set_xticks([])


def plot_run(path: Path, run: SimulationRun) -> None:
    """``--plot`` with ``--physics``: each motion's filmstrip (side view) and the torso's
    path on the floor, fallen stretches in red."""
    import matplotlib

    from rcb4hv.project.physics_sim import FALL_TILT_DEG

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(run.motions)
    longest = max((len(m.frames) for m in run.motions), default=1)
    fig = plt.figure(figsize=(max(8.0, min(30.0, 0.6 * longest + 4)), 2.2 * n + 4), dpi=100)
    grid = fig.add_gridspec(n + 1, 1, height_ratios=[1.0] * n + [2.0])
    try:
        for k, m in enumerate(run.motions):
            ax = fig.add_subplot(grid[k])
            draw_frames(ax, m.frames, t0=m.start_s)
            o = m.outcome
            assert o is not None
            ax.set_title(
                f"slot {m.result.slot}: {o.end_pose}"
                + (f" (down at start: {o.start_pose})" if o.fallen_at_start else "")
                + (f", fell at {o.fell_at_s:.2f} s" if o.fell_at_s is not None else ""),
                fontsize=9,
                loc="left",
            )
        ax = fig.add_subplot(grid[n])
        for m in run.motions:
            if not m.track:
                continue
            x0, y0 = m.track[0].x, m.track[0].y
            xs = [p.x - x0 for p in m.track]
            ys = [p.y - y0 for p in m.track]
            ax.plot(xs, ys, linewidth=1.0, label=f"slot {m.result.slot}")
            down = [(p.x - x0, p.y - y0) for p in m.track if p.tilt >= math.radians(FALL_TILT_DEG)]
            if down:
                ax.scatter([d[0] for d in down], [d[1] for d in down], s=3, color="tab:red")
        ax.scatter([0.0], [0.0], marker="o", color="black")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("x (m; each path from its motion's start, red: fallen)")
        ax.set_ylabel("y (m)")
        ax.grid(True, linewidth=0.3)
        if n <= 12:
            ax.legend(fontsize=7, loc="best")
        fig.tight_layout()
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path)
    finally:
        plt.close(fig)
