"""``rcb4hv project poses`` (static balance and servo load per pose) and ``rcb4hv project
ease`` (easing between two poses). Registered into the ``project`` group by
:mod:`rcb4hv.cli.project_cmd`."""

from __future__ import annotations

from pathlib import Path

import click

from rcb4hv.cli._util import handle_errors, print_json, print_table
from rcb4hv.cli.edit_cmd import ROBOT_OPTION

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
    support polygon of whatever touches the floor), the margin to the polygon's edge in
    metres, and each servo's static torque as a fraction of its stall torque."""
    from rcb4hv.hth4 import load_project
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


def register(project: click.Group) -> None:
    """Add ``poses`` to the ``project`` group."""
    project.add_command(poses_command)
