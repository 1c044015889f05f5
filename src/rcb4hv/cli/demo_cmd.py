"""``rcb4hv demo``: the library at work on the in-process emulator, and a plot of it."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import TYPE_CHECKING

import click

from rcb4hv.cli._output import plot_to
from rcb4hv.cli._util import handle_errors, print_table
from rcb4hv.cli.board_cmd import SERVO_HEADERS, servo_rows
from rcb4hv.cli.project_physics import draw_frames
from rcb4hv.client import PositionRecorder, Robot
from rcb4hv.rom.layout import HTH4_22

if TYPE_CHECKING:
    from rcb4hv.project.physicsresult import ShapeFrame


@click.command()
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False, path_type=Path),
    default=Path("demo-servo-angles.png"),
    show_default=True,
    help="Where to write the plot of servo angles over time.",
)
@click.option(
    "--port",
    default=None,
    metavar="URL",
    help="Run on this board instead of the in-process emulator (careful: it moves!).",
)
@click.option(
    "--speed",
    type=click.FloatRange(min=0.1),
    default=1.0,
    show_default=True,
    help="Emulator clock speed factor.",
)
@click.option(
    "--motion",
    "motion_number",
    type=click.IntRange(1, HTH4_22.motion_count),
    default=1,
    show_default=True,
)
@handle_errors
def demo(output: Path, port: str | None, speed: float, motion_number: int) -> None:
    """Drive a virtual robot end to end and plot its servo angles."""
    run_demo(output, port, speed, motion_number)


def run_demo(output: Path, port: str | None, speed: float, motion_number: int) -> None:
    """`make demo`: the library at work on the in-process emulator, and a plot of it."""
    t_start = time.monotonic()
    url = port or f"rcb4emu://?speed={speed:g}&boot=live"  # show the start-up too
    clock = 1.0 if port else speed

    def since(t0: float) -> str:
        """Seconds since ``t0`` on the board's clock (the emulator's runs ``speed`` times as
        fast as the wall's), so "in 0.8 s ... done after" compares like with like."""
        wall = time.monotonic() - t0
        if clock == 1.0:
            return f"{wall:.2f} s"
        return f"{wall * clock:.2f} s on the board's clock ({wall:.2f} s at x{clock:g})"

    click.echo(f"rcb4hv demo on {url}")
    with Robot.open(url, timeout=0.5) as robot:
        click.echo(f"board: {robot.version().text!r}, ACK in {robot.ping() * 1000:.2f} ms")
        sysreg = robot.system_register()
        click.echo(
            f"system register {sysreg.to_word():04X}h: output period "
            f"{sysreg.frame_period_ms} ms, ROM program {'running' if sysreg.rom_run else 'idle'}"
        )
        t0 = time.monotonic()
        robot.wait_ready(timeout=10.0)
        click.echo(f"ROM start-up program finished after {since(t0)}")
        servos = robot.discover_servos()
        click.echo(f"\n{len(servos)} servos found through the ICS allocation table:")
        print_table(SERVO_HEADERS, servo_rows(servos, robot))
        if not servos:
            raise ValueError("the board has no servo to move")
        ids = [s.ics for s in servos]
        # a few joints to move by hand: the first four servos after the head (if any)
        joints = ids[1:5] if len(ids) > 4 else ids[:4]
        recorder = PositionRecorder(robot, period=0.02)
        with recorder:
            recorder.mark("hold")
            robot.hold()
            time.sleep(0.2 / speed)
            recorder.mark("move")
            angles = (30.0, -20.0, 45.0, -40.0)
            targets = {k: angles[i % 4] for i, k in enumerate(joints)}
            click.echo(
                "\nmoving "
                + ", ".join(f"ICS {k} to {a:+.0f} deg" for k, a in targets.items())
                + " in 0.8 s"
            )
            t0 = time.monotonic()
            robot.move_angles(targets, 0.8, wait=True)
            click.echo(f"  done after {since(t0)}")
            back = {k: -a / 2 for k, a in targets.items()}
            click.echo("then to half the opposite angle in 0.5 s")
            robot.move_angles(back, 0.5, wait=True)
            click.echo("then all servos to neutral in 0.6 s")
            robot.neutral(duration=0.6, wait=True)
            recorder.mark("motion")
            click.echo(f"\nplaying motion {motion_number}")
            t0 = time.monotonic()
            robot.play_motion(motion_number)
            time.sleep(0.05)
            robot.wait_motion(timeout=30.0)
            click.echo(f"  motion {motion_number} ended after {since(t0)}")
            time.sleep(0.2)
        click.echo(
            f"\nsampled {len(recorder.samples)} bulk position reads "
            f"({recorder.errors} failed) through the client while it worked"
        )
        frames = _physics_scene()
        path = _plot(recorder, robot, output, joints, frames)
    click.echo(f"plot written to {path.resolve()}")
    click.echo(f"demo finished in {time.monotonic() - t_start:.1f} s")


SCENE_ROBOT = "kxr-l2"
SCENE_POSES: tuple[tuple[float, dict[str, float]], ...] = (
    (0.6, {"r_hip_pitch": -0.7, "l_hip_pitch": -0.7}),  # a bow (joint angles, radians)
    (0.6, {}),  # standing straight
    (0.5, {"r_shoulder_roll": -2.6, "r_elbow_pitch": -0.6}),  # the right arm up
    (0.4, {"r_shoulder_roll": -2.6, "r_elbow_pitch": -1.4}),  # a wave
    (0.4, {"r_shoulder_roll": -2.6, "r_elbow_pitch": -0.6}),
    (0.8, {"r_knee_pitch": 1.2, "l_knee_pitch": 1.2, "r_hip_pitch": -0.6,
           "l_hip_pitch": -0.6, "r_ankle_pitch": -0.6, "l_ankle_pitch": -0.6}),  # a squat
)  # fmt: skip
"""The physics part of the demo: (seconds, joint angles) moves from the robot's home pose."""


def _physics_scene() -> tuple[ShapeFrame, ...]:
    """With MuJoCo installed (``rcb4hv[sim]``): a KXR-L2 in physics bows, waves and squats,
    driven by servo commands through an emulated board in virtual time; its frames, drawn
    under the plot. Without MuJoCo: none."""
    import importlib.util

    if importlib.util.find_spec("mujoco") is None:
        click.echo("\n(physics part skipped: install rcb4hv[sim] for MuJoCo)")
        return ()
    from rcb4hv.physics import PhysicsBackend, PhysicsWorld
    from rcb4hv.physics.standalone import robot_board
    from rcb4hv.project.physicsresult import ShapeFrame
    from rcb4hv.protocol import RunConstFrameServo
    from rcb4hv.robot.builtin import load_builtin

    model = load_builtin(SCENE_ROBOT)
    board = robot_board(model)
    board.feed(RunConstFrameServo(1, sorted(model.motion_values(model.home).items())).encode())
    board.run_for(0.1)
    world = PhysicsWorld(model)
    world.place(model.home)
    backend = PhysicsBackend(board, world)
    frames: list[ShapeFrame] = []
    t0 = time.monotonic()
    for seconds, angles in SCENE_POSES:
        pose = {**model.home, **angles}
        frames_n = max(1, round(seconds / board.output_period))
        board.feed(RunConstFrameServo(frames_n, sorted(model.motion_values(pose).items())).encode())
        board.run_for(seconds + 0.3)
        backend.sync()
        frames.append(ShapeFrame(board.now, world.shapes()))
    tilt = math.degrees(world.base().tilt)
    click.echo(
        f"\nphysics: a {model.title} bowed, waved and squatted in MuJoCo "
        f"({board.now:.1f} s virtual in {time.monotonic() - t0:.2f} s; torso tilt "
        f"{tilt:.1f} deg at the end)"
    )
    return tuple(frames)


def _plot(
    recorder: PositionRecorder,
    robot: Robot,
    output: Path,
    joints: list[int],
    frames: tuple[ShapeFrame, ...] = (),
) -> Path:
    samples = recorder.samples
    if not samples:
        raise ValueError("no position samples were recorded")
    ids = sorted(samples[-1].angles)
    moved = [
        k
        for k in ids
        if max(_finite(s.angles.get(k)) for s in samples)
        - min(_finite(s.angles.get(k)) for s in samples)
        > 1.0
    ]
    with plot_to(output, (11, 9.5 if frames else 6), dpi=110) as ax:
        if frames:
            fig = ax.figure
            grid = fig.add_gridspec(2, 1, height_ratios=(3, 2))
            ax.set_subplotspec(grid[0])
            film = fig.add_subplot(grid[1])
            draw_frames(film, frames, axis=0, spacing=0.22)
            film.set_title(
                f"the robot itself: a simulated {SCENE_ROBOT} (MuJoCo) after each servo move",
                fontsize=10,
            )
        for k in moved or ids:
            ts = [s.t for s in samples]
            ys = [s.angles.get(k, math.nan) for s in samples]
            style = "-" if k in joints else "--"
            sid, grp = divmod(k, 2)
            ax.plot(
                ts,
                ys,
                style,
                lw=1.6 if k in joints else 1.0,
                label=f"ICS {k} (ID {sid}, {'SIO1-4' if grp == 0 else 'SIO5-8'})",
            )
        marks = recorder.marks
        colours = {"hold": "#eeeeee", "move": "#e3f0ff", "motion": "#fff1dd"}
        for i, (t, label) in enumerate(marks):
            t_end = marks[i + 1][0] if i + 1 < len(marks) else samples[-1].t
            ax.axvspan(t, t_end, color=colours.get(label, "#f5f5f5"), zorder=0)
            text = {"hold": "hold", "move": "timed moves", "motion": "ROM motion"}.get(label, label)
            ax.text(t + 0.02, 1.01, text, transform=ax.get_xaxis_transform(), fontsize=9)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("measured angle [deg]")
        ax.set_title(
            f"rcb4hv demo: servo angles read through the client ({len(samples)} bulk reads, "
            f"output period {robot.output_period() * 1000:.0f} ms)",
            fontsize=11,
            pad=18,
        )
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=2, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return output


def _finite(v: float | None) -> float:
    return 0.0 if v is None or math.isnan(v) else v


def register(cli: click.Group) -> None:
    """Add ``demo`` to ``cli``."""
    cli.add_command(demo)
