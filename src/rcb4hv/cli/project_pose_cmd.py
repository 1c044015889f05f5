"""``rcb4hv project poses`` (static balance and servo load per pose) and ``rcb4hv project
ease`` (easing between two poses). Registered into the ``project`` group by
:mod:`rcb4hv.cli.project_cmd`."""

from __future__ import annotations

from pathlib import Path

import click

from rcb4hv.cli._util import handle_errors, print_json, print_table
from rcb4hv.cli.edit_cmd import ROBOT_OPTION
from rcb4hv.hth4 import load_project
from rcb4hv.hth4.session import EditSession

__all__ = ["register"]


@click.command("poses")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--motion", "slot", type=click.IntRange(1, 999), required=True, help="Slot.")
@ROBOT_OPTION
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def poses_command(file: Path, slot: int, robot_name: str | None, as_json: bool) -> None:
    """Static balance and servo load of every pose of motion --motion in FILE.

    For each pose: whether it stands still (``balanced``: the centre of mass inside the
    support polygon of whatever touches the floor by more than a 6 mm reserve, which physics
    needs to stand: docs/posing.md), the margin to the polygon's edge in metres (positive
    inside), and each servo's static torque as a fraction of its stall torque."""
    from rcb4hv.hth4.edit import used_motion
    from rcb4hv.hth4.robotpick import project_model
    from rcb4hv.project.posebalance import motion_balance

    project = load_project(file)
    model = project_model(project, robot_name)
    motion = used_motion(project, slot)
    reports = motion_balance(model, motion)
    if as_json:
        print_json(
            {
                "file": str(file),
                "motion": slot,
                "robot": model.name,
                "poses": [r.to_dict() for r in reports],
            }
        )
        return
    rows = []
    for r in reports:
        b = r.balance
        worst = max(b.torque_ratio.items(), key=lambda kv: kv[1], default=("-", 0.0))
        rows.append(
            [
                r.index + 1,
                "yes" if b.balanced else "NO",
                f"{b.margin_m * 1000:.1f}",
                ", ".join(b.contacts) or "-",
                f"{worst[0]} {worst[1]:.0%}",
            ]
        )
    click.echo(f"motion {slot} ({motion.name}) on {model.name}:")
    print_table(["pose", "stands", "margin mm", "touching", "most loaded servo"], rows)


@click.command("ease")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--motion", "slot", type=click.IntRange(1, 999), required=True, help="Slot.")
@click.option(
    "--pose", "pose", type=click.IntRange(2, None), required=True, help="Pose (1 = first)."
)
@click.option("--over", type=click.IntRange(2, None), required=True, help="Poses to split it into.")
@click.option(
    "--curve",
    type=click.Choice(["in-out", "in", "out"]),
    default="in-out",
    show_default=True,
    help="Ease in and out, in only (start slowly) or out only (stop slowly).",
)
@ROBOT_OPTION
@click.option("--force", is_flag=True, help="Keep values outside ranges or joint limits.")
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), required=True)
@handle_errors
def ease_command(
    file: Path,
    slot: int,
    pose: int,
    over: int,
    curve: str,
    robot_name: str | None,
    force: bool,
    output: Path,
) -> None:
    """Ease the move into pose --pose of motion --motion over --over poses and write -o.

    The board moves linearly from pose to pose; the move into --pose is split into --over
    moves along an easing curve (the same time on the board, the same end pose), so the
    servos start and stop gently."""
    from rcb4hv.errors import NoRobotModelError
    from rcb4hv.hth4.ease import ease_pose
    from rcb4hv.hth4.poses import Checks
    from rcb4hv.hth4.robotpick import project_model

    session = EditSession.open(file)
    try:
        model = project_model(session.project, robot_name)
    except NoRobotModelError:
        model = None  # no joint limits to check: the documented ranges still are
    session.apply(ease_pose, slot, pose - 1, over, curve, Checks(model, force))  # type: ignore[arg-type]
    session.save(output)
    click.echo(f"{output}: motion {slot} pose {pose} eased ({curve}) over {over} poses")


def register(project: click.Group) -> None:
    """Add ``poses`` and ``ease`` to the ``project`` group."""
    project.add_command(poses_command)
    project.add_command(ease_command)
