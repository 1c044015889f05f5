"""``rcb4hv project simulate``: play a project's motions in the emulator, in virtual time."""

from __future__ import annotations

import contextlib
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import click

from rcb4hv.cli._output import plot_to
from rcb4hv.cli._util import MOTION_SLOT, handle_errors, print_json, print_table
from rcb4hv.cli.project_common import (
    LAYOUT_OPTION,
    STATUS_EXIT,
    build_options,
    image_slots,
    load_file,
    parse_buttons,
)
from rcb4hv.cli.project_physics import (
    parse_sequence,
    physics_robot,
    plot_run,
    print_physics,
    stride_text,
)
from rcb4hv.errors import RobotModelError
from rcb4hv.protocol import position_to_degrees
from rcb4hv.robot.stride import has_stride

if TYPE_CHECKING:
    from rcb4hv.physics.options import PhysicsOptions
    from rcb4hv.project.physics_sim import StartPose
    from rcb4hv.project.runresult import SimulationRun


@click.command("simulate")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option(
    "--motion",
    "motion",
    type=MOTION_SLOT,
    multiple=True,
    help="Motion slot to play (repeatable; default: every used slot).",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.option(
    "--plot",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Draw servo angles over virtual time into this PNG (with --physics: the torso's "
    "path on the floor).",
)
@click.option(
    "--trace",
    type=click.Path(dir_okay=False, path_type=Path),
    help="With --physics: write each motion's track to this CSV file, a row per output period "
    "(the torso's position, heading, tilt and lean, every joint's angle).",
)
@click.option(
    "--hold-button",
    "hold_button",
    metavar="NAME|bound|none",
    default="bound",
    show_default=True,
    help="Remote button(s) held while each motion plays: 'bound' holds the button each "
    "motion reads (the one its loop tests, else its binding), as a user drives it (a walk "
    "that loops on UP walks while UP is held); a NAME (UP, CIRCLE, UP+S1...) holds it for "
    "every motion; 'none' holds nothing (a remote-driven walk then stops after one pass).",
)
@click.option(
    "--for",
    "hold_for",
    type=click.FloatRange(min=0),
    default=3.0,
    show_default=True,
    help="Seconds to hold the button, then release it.",
)
@click.option(
    "--limit",
    type=click.FloatRange(min=0.001),
    default=None,
    help="Virtual seconds per motion before it counts as a timeout (default: as long as it "
    "makes progress - servos, loop counters or variables change within 60 s - up to 1 h).",
)
@click.option(
    "--physics",
    is_flag=True,
    help="Play on the robot in MuJoCo (needs rcb4hv[sim]): report falls, end pose, "
    "displacement and turn per motion.",
)
@click.option(
    "--robot",
    metavar="NAME|FILE",
    help="The robot: khr3hv, khr3hv-22, kxr-l2, kxr-l2-gripper, a KXR kit code (kxr:L6) or "
    "a URDF file [default: detected from the project's title and servo table; without "
    "--physics a project no model fits plays without the no-slip travel].",
)
@click.option(
    "--start",
    type=click.Choice(["upright", "on_back", "on_front"]),
    default="upright",
    show_default=True,
    help="With --physics: how the robot lies before each motion (or the sequence): "
    "standing, or on its back or front (for get-up motions).",
)
@click.option(
    "--sequence",
    metavar="SLOTS",
    help="With --physics: play these slots (e.g. 33,15) one after another on the same "
    "robot, without standing it up again between them.",
)
@click.option(
    "--what-if",
    "what_if",
    metavar="NAME=VALUE",
    multiple=True,
    help="With --physics: play on a changed model (repeatable): NAME a field of "
    "rcb4hv.physics.PhysicsOptions, a factor on one of the physics' chosen figures "
    "(friction=0.5 halves the floor's) or a figure of its own (floor_tilt_deg=2); an unknown "
    "NAME lists them. Reports name what they changed (docs/physics.md, 'How sensitive the "
    "verdicts are').",
)
@click.option(
    "--no-slip",
    "no_slip",
    is_flag=True,
    help="Also each motion's no-slip travel: where its poses take the robot when the feet it "
    "stands on never slip (the run then takes longer: about six times as long without "
    "--physics, about half as long again with it).",
)
@build_options
@LAYOUT_OPTION
@handle_errors
def simulate(
    file: Path,
    motion: tuple[int, ...],
    as_json: bool,
    plot: Path | None,
    trace: Path | None,
    hold_button: str,
    hold_for: float,
    limit: float | None,
    physics: bool,
    robot: str | None,
    start: StartPose,
    sequence: str | None,
    what_if: tuple[str, ...],
    no_slip: bool,
    layout_name: str | None,
) -> None:
    """Boot FILE (.h4p or 256 KB image) in the emulator and play its motions in virtual time.

    Each motion is played as a host does (suspend, PC to the main loop, CALL, resume); one
    that reads the remote plays with the button it loops on held for --for seconds
    (--hold-button bound, the default; 'held' in --json names the word), as a user drives
    it. Status:
    completed (returned to the main loop), waiting (loops reading an input, e.g. a button
    or AD sensor, as its program defines), holding (loops without reading an input while
    servos are mixed from an AD sensor, e.g. a gyro balancing the robot), stalled (repeats
    itself without reading any input), timeout (no progress for 60 s, 1 h in all, or
    --limit reached) or error (ROMERR, command error, call-stack overflow/underflow; with the
    PC and the instruction). A boot that fails is reported with its cause and the motions are
    still played from the host. Exit status 0 when the boot and every motion completed, wait
    or hold, 1 if any error, 2 if any timeout or stall.

    With --physics each motion plays on the robot standing on flat ground in the pose the
    board holds after its boot (--sequence: one after another without standing it up again)
    and reports whether it fell (and when), the end pose, the displacement dx/dy (m, x forward
    where the robot faced at the start, y left) and turn dyaw (degrees, counter-clockwise),
    the largest tilt and tracking error and the joints at their torque limit; --plot then
    draws the torso's path on the floor, --trace writes the robot's state every output
    period to a CSV file (see why a motion fell). A robot that is down as a motion starts
    (it fell while settling, or an earlier motion of the sequence left it lying) is reported
    "down at start" with the pose it lies in, and cannot "fall" in that motion.

    --no-slip adds each motion's no-slip travel ('no slip'; 'stride' in --json) when the
    robot model (--robot, or detected) stands on feet: where its poses take the robot when
    the feet it stands on never slip, the motion's design without physics (with --physics:
    beside what the robot did).
    """
    from rcb4hv.emulator import Board
    from rcb4hv.project.run import Hold, run_motions

    loaded = load_file(file, layout_name)
    image, lay, names = loaded.image, loaded.layout, loaded.names
    hold: Hold = "bound"
    if hold_button.lower() != "bound":
        hold = 0 if hold_button.lower() == "none" else parse_buttons(hold_button)
    slots = list(motion)
    if sequence is not None:
        if not physics:
            raise click.UsageError("--sequence plays motions on the simulated robot: add --physics")
        if slots:
            raise click.UsageError("give either --motion or --sequence")
        slots = parse_sequence(sequence, lay)
    loaded.check_slots(slots)  # an empty slot fails as in `project poses`, not with a ROMERR
    if not slots:
        slots = sorted(names) if names else image_slots(image, lay)
    if not physics and (start != "upright" or what_if):
        given = [o for o, on in (("--start", start != "upright"), ("--what-if", what_if)) if on]
        verb = "set" if len(given) > 1 else "sets"
        why = f"{' and '.join(given)} {verb} up the robot of --physics"
        raise click.UsageError(f"{why}: add --physics")
    if trace is not None and not physics:
        raise click.UsageError("--trace writes the simulated robot's track: add --physics")
    _check_outputs(file, plot, trace)
    options = _what_if(what_if)
    model = None
    if physics or robot is not None:
        model = physics_robot(loaded.project, image, robot)
    elif no_slip:
        with contextlib.suppress(RobotModelError):  # no model fits: no stride
            model = physics_robot(loaded.project, image, None)
    follow = no_slip and model is not None and has_stride(model)
    samples: list[tuple[float, dict[int, int | None]]] = []

    def record(t: float, board: Board) -> None:
        samples.append((t, board.sent_angles()))

    # a failed boot is reported; every motion is still played from the host (spec 11.4)
    run = run_motions(
        image, slots, names=names, motion_layout=lay, limit=limit, hold=hold, hold_for=hold_for,
        robot=model if physics else None, sequence=sequence is not None, start=start,
        track=physics and (plot is not None or trace is not None), options=options,
        listener=record if plot is not None and not physics else None,
        stride=model if follow else None,
    )  # fmt: skip
    if physics:
        print_physics(run, as_json)
    elif as_json:
        print_json(run.to_dict())
    else:
        _print_plain(run)
    if plot is not None:
        if physics:
            plot_run(plot, run)
        else:
            _plot(plot, samples, [(m.start_s, m.result.slot or 0) for m in run.motions])
        if not as_json:
            click.echo(f"wrote {plot}")
    if trace is not None:
        from rcb4hv.files import write_atomic
        from rcb4hv.project.trace import trace_csv

        write_atomic(trace, trace_csv(run))
        if not as_json:
            click.echo(f"wrote {trace}")
    codes = {STATUS_EXIT.get(r.status, 0) for r in [run.boot, *run.results]}
    sys.exit(1 if 1 in codes else max(codes))


def _check_outputs(file: Path, plot: Path | None, trace: Path | None) -> None:
    """Before the simulation runs: --plot and --trace are not the input (they overwrote the
    project), not each other, and the plot is a picture matplotlib can write."""
    outs = {"--plot": plot, "--trace": trace}
    for name, out in outs.items():
        if out is not None and out.resolve() == file.resolve():
            raise click.BadParameter(f"{out} is the file simulated: give another", param_hint=name)
    if plot is not None and trace is not None and plot.resolve() == trace.resolve():
        raise click.BadParameter("--plot and --trace name the same file", param_hint="--trace")
    if plot is not None and plot.suffix.lower() not in PLOT_SUFFIXES:
        raise click.BadParameter(
            f"{plot}: a picture, one of {', '.join(sorted(PLOT_SUFFIXES))}", param_hint="--plot"
        )


PLOT_SUFFIXES = frozenset({".png", ".svg", ".pdf", ".jpg", ".jpeg"})
"""What ``--plot`` writes (matplotlib's formats a user would want)."""


def _what_if(items: tuple[str, ...]) -> PhysicsOptions | None:
    """The physics options of ``--what-if`` (None: the documented model)."""
    if not items:
        return None
    from rcb4hv.physics.options import PhysicsOptions

    try:
        return PhysicsOptions.parse(items)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint="--what-if") from None


def _print_plain(run: SimulationRun) -> None:
    boot = run.boot
    click.echo(
        f"boot: {boot.status} after {boot.duration:.3f} s virtual"
        + (f" ({boot.detail})" if boot.detail else "")
    )
    strides = any(m.stride is not None for m in run.motions)
    print_table(
        ("slot", "address", "name", "status", "virtual s", "instr", "held", "detail")
        + (("no slip",) if strides else ()),
        [
            [
                r.slot or "-",
                f"{r.address:05X}",
                r.name,
                r.status,
                f"{r.duration:.3f}",
                r.instructions,
                r.held or "",
                r.detail,
            ]
            + ([stride_text(m.stride)] if strides else [])
            for m in run.motions
            for r in [m.result]
        ],
    )
    parts = ", ".join(f"{n} {s}" for s, n in sorted(run.summary().items()))
    virtual = f"{run.virtual_s:.3f} s virtual (boot included)"
    click.echo(f"{len(run.motions)} motions: {parts or 'none'}; {virtual}")


def _plot(
    path: Path, samples: list[tuple[float, dict[int, int | None]]], starts: list[tuple[float, int]]
) -> None:
    channels = sorted({k for _, outs in samples for k in outs})
    with plot_to(path, (max(8.0, min(60.0, len(samples) / 150)), 6)) as ax:
        times = [t for t, _ in samples]
        for ics in channels:
            ys = []
            for _, outs in samples:
                v = outs.get(ics)
                ys.append(float("nan") if v is None else position_to_degrees(v))
            ax.plot(times, ys, linewidth=0.8, label=f"ICS {ics}")
        for t, slot in starts:
            ax.axvline(t, color="grey", linewidth=0.5, linestyle=":")
            ax.annotate(
                str(slot), (t, 1.0), xycoords=("data", "axes fraction"), fontsize=6, va="bottom"
            )
        ax.set_xlabel("virtual time (s)")
        ax.set_ylabel("servo angle (degrees, trim included)")
        if channels:
            ax.legend(fontsize=6, ncol=2, loc="upper right")


def register(project: click.Group) -> None:
    """Add ``simulate`` to the ``project`` group."""
    project.add_command(simulate)
