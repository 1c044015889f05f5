"""``rcb4hv robot``: the robot models (list, show, export to URDF or MJCF)."""

from __future__ import annotations

import importlib
import math
import os
from pathlib import Path
from typing import Any

import click

from rcb4hv.cli._util import OUTPUT_FILE, handle_errors, output_option, print_json, print_table
from rcb4hv.errors import RobotModelError
from rcb4hv.files import write_atomic
from rcb4hv.robot.builtin import BUILTIN, load_builtin, load_robot
from rcb4hv.robot.jointmap import to_joint_map
from rcb4hv.robot.model import RobotModel
from rcb4hv.robot.urdf import to_urdf


def model_summary(model: RobotModel) -> dict[str, Any]:
    """The model as JSON-ready data: joints (servo index, sign, limits in degrees), mass."""
    joints = []
    for j in model.joints:
        s = model.servo_for_joint(j.name)
        joints.append(
            {
                "joint": j.name,
                "index": s.index if s else None,
                "sign": s.sign if s else None,
                "offset": s.offset if s else None,
                "kind": j.kind,
                "side": j.side,
                "mirror": j.mirror,
                "lower_deg": round(math.degrees(j.lower), 2),
                "upper_deg": round(math.degrees(j.upper), 2),
                "servo": s.servo.name if s and s.servo else None,
            }
        )
    return {
        "name": model.name,
        "title": model.title,
        "mass_kg": round(model.mass, 4),
        "links": len(model.links),
        "servos": len(model.servos),
        "indices": list(model.indices),
        "joints": joints,
        "sources": dict(model.sources),
    }


@click.group()
def robot() -> None:
    """Robot models: the built-in ones, and your own (a URDF with a joint map)."""


@robot.command("list")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def list_cmd(as_json: bool) -> None:
    """The built-in robot models."""
    rows = [load_builtin(n) for n in BUILTIN]
    if as_json:
        print_json(
            [
                {
                    "name": m.name,
                    "title": m.title,
                    "servos": len(m.servos),
                    "mass_kg": round(m.mass, 4),
                }
                for m in rows
            ]
        )
        return
    print_table(
        ["name", "servos", "mass kg", "title"],
        [[m.name, len(m.servos), round(m.mass, 3), m.title] for m in rows],
    )


@robot.command()
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def show(name: str, as_json: bool) -> None:
    """Joints, servo map, mass and limits of robot NAME (a built-in name or a robot file)."""
    data = model_summary(load_robot(name))
    if as_json:
        print_json(data)
        return
    click.echo(
        f"{data['title']} ({data['name']}): {data['servos']} servos, "
        f"{data['links']} links, {data['mass_kg']} kg"
    )
    rows = [
        [
            j["index"] if j["index"] is not None else "-",
            j["joint"],
            j["kind"],
            j["sign"] if j["sign"] is not None else "-",
            j["lower_deg"],
            j["upper_deg"],
            j["mirror"] or "-",
        ]
        for j in sorted(data["joints"], key=lambda j: (j["index"] is None, j["index"] or 0))
    ]
    print_table(["index", "joint", "kind", "sign", "lower°", "upper°", "mirror"], rows)
    for key, text in data["sources"].items():
        click.echo(f"  {key}: {text}")


@robot.command()
@click.argument("name")
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["urdf", "mjcf"]),
    default="urdf",
    show_default=True,
    help="Output format.",
)
@output_option("File to write.")
@click.option(
    "--joint-map",
    type=OUTPUT_FILE,
    default=None,
    help="Also write the joint map (TOML) here, for `--robot FILE` (urdf only).",
)
@handle_errors
def export(name: str, fmt: str, output: Path, joint_map: Path | None) -> None:
    """Write robot NAME as URDF (for ROS) or MJCF (for MuJoCo)."""
    model = load_robot(name)
    if fmt == "mjcf":
        try:
            mjcf: Any = importlib.import_module("rcb4hv.robot.mjcf")
        except ModuleNotFoundError as exc:
            if exc.name != "rcb4hv.robot.mjcf":
                raise
            raise RobotModelError(
                "MJCF export is not available in this build (rcb4hv.robot.mjcf is missing)"
            ) from None
        text = str(mjcf.to_mjcf(model))
    else:
        text = to_urdf(model)
    write_atomic(output, text)
    if joint_map is not None:
        rel = os.path.relpath(os.fspath(output), os.fspath(joint_map.parent))
        write_atomic(joint_map, to_joint_map(model, urdf=rel))
    click.echo(f"wrote {output} ({fmt}, {model.name}, {len(model.joints)} joints)")


def register(cli: click.Group) -> None:
    """Add ``robot`` to ``cli``."""
    cli.add_command(robot)
