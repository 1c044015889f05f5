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
    """The model as JSON-ready data: joints (servo index, sign, hard limits and advisory range
    in degrees), mass."""
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
                "advisory_deg": [round(math.degrees(a), 2) for a in j.advisory_range],
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


#: the kit families and example codes ``robot list`` shows (any code of the grammar works)
KIT_EXAMPLES: tuple[tuple[str, str, str], ...] = (
    ("humanoid", "kxr:L2L5A3", "biped: legs L2/L4/L5/L6 axes, arms A3-A7, head H1/H2, G, W2"),
    ("humanoid", "kxr:L2GH", "KXR-L2 with grippers and a 2-axis head"),
    ("humanoid", "kxr:L2W2L6A4H2", "6-axis legs, wheels behind the ankles"),
    ("humanoid", "kxr:L2GL6A7H2W", "7-axis arms, wide hips"),
    ("humanoid", "kxr:A6G", "upper body on short legs and a wheeled base"),
    ("L4D", "kxr:L4D", "four legs (4 axes), neck and jaw (dinosaur)"),
    ("L4N", "kxr:L4NH4", "four legs (2 axes), neck and hand"),
    ("L4R", "kxr:L4R", "four steered wheels"),
    ("L4T", "kxr:L4T", "four legs (2 axes), neck (turtle)"),
    ("L6", "kxr:L6", "six legs (3 axes)"),
    ("R4LL", "kxr:R4LL", "four legs (yaw, pitch) on wheels"),
)


@robot.command("list")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def list_cmd(as_json: bool) -> None:
    """The built-in robot models and the KXR kit families (``kxr:CODE``)."""
    rows = [load_builtin(n) for n in BUILTIN]
    kits = [(family, load_robot(code), note) for family, code, note in KIT_EXAMPLES]
    if as_json:
        print_json(
            [
                {
                    "name": m.name,
                    "title": m.title,
                    "servos": len(m.servos),
                    "mass_kg": round(m.mass, 4),
                    "family": None,
                }
                for m in rows
            ]
            + [
                {
                    "name": m.name,
                    "title": note,
                    "servos": len(m.servos),
                    "mass_kg": round(m.mass, 4),
                    "family": family,
                }
                for family, m, note in kits
            ]
        )
        return
    print_table(
        ["name", "servos", "mass kg", "title"],
        [[m.name, len(m.servos), round(m.mass, 3), m.title] for m in rows],
    )
    click.echo("\nKXR kits (any kit code: kxr:CODE, e.g. from a project title Hello_KXR-L6):")
    print_table(
        ["family", "name", "servos", "mass kg", "what"],
        [[f, m.name, len(m.servos), round(m.mass, 3), note] for f, m, note in kits],
    )


@robot.command()
@click.argument("name")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def show(name: str, as_json: bool) -> None:
    """Joints, servo map, mass and limits of robot NAME (a built-in name, a kit code such as
    kxr:L2W2L6A4H2, or a robot file)."""
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
            "{:g}..{:g}".format(*j["advisory_deg"]),
            j["mirror"] or "-",
        ]
        for j in sorted(data["joints"], key=lambda j: (j["index"] is None, j["index"] or 0))
    ]
    print_table(["index", "joint", "kind", "sign", "lower°", "upper°", "advisory°", "mirror"], rows)
    for key, text in data["sources"].items():
        click.echo(f"  {key}: {text}")


@robot.command()
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--robot", "robot_name", default=None, help="Pick a model: NAME, kxr:CODE or FILE.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def detect(file: Path, robot_name: str | None, as_json: bool) -> None:
    """The robot model project FILE drives (.h4p), and the evidence for it."""
    from rcb4hv.errors import AmbiguousRobotError
    from rcb4hv.hth4 import load_project
    from rcb4hv.hth4.robotpick import detect_project, servo_table
    from rcb4hv.robot.builtin import check_indices

    project = load_project(file)
    try:
        model, det = detect_project(project, robot_name)
        if servo_table(project):  # a named model must fit, as for every other command
            check_indices(model, servo_table(project))
    except AmbiguousRobotError as exc:
        if as_json:
            print_json({"model": None, "error": str(exc), "candidates": list(exc.candidates)})
        raise
    data: dict[str, Any] = (
        det.as_dict()
        if det is not None
        else {
            "model": model.name,
            "title": model.title,
            "project_title": project.project_title or "",
            "servos": [
                {"index": i, "name": n, "joint": j.joint, "sign": j.sign}
                for i, n in sorted(servo_table(project).items())
                for j in model.servos
                if j.index == i
            ],
            "notes": [
                f"chosen with --robot {robot_name}"
                if robot_name
                else "the built-in model matching the servos"
            ],
            "checks": [],
        }
    )
    data["model"], data["title"] = model.name, model.title
    if det is not None:
        data["notes"] = [*data["notes"], *_against_stock(model)]
    if as_json:
        print_json(data)
        return
    click.echo(f"{file.name}: {model.name} - {model.title}")
    click.echo(f"  project title: {data['project_title']!r}")
    rows = [
        [s["index"], s["name"], s["joint"] or "-", s["sign"] if s["sign"] is not None else "-"]
        for s in data["servos"]
    ]
    print_table(["index", "servo name", "joint", "sign"], rows)
    for note in data["notes"]:
        click.echo(f"  note: {note}")
    for c in data["checks"]:
        click.echo(f"  check: {c['check']}: {'ok' if c['ok'] else 'FAILED'} ({c['detail']})")


def _against_stock(model: RobotModel) -> list[str]:
    """How a model built from a project's servo names differs from the stock build its kit
    code names (``robot show`` of the same code), so that the printed code never hides it."""
    try:
        stock = load_robot(model.name)
    except RobotModelError:
        return []
    have, kit = {s.joint for s in model.servos}, {s.joint for s in stock.servos}
    if have == kit:
        return []
    parts = [
        f"{word} {', '.join(sorted(joints))}"
        for word, joints in (("add", have - kit), ("lack", kit - have))
        if joints
    ]
    return [
        f"{len(have)} servos where the stock {model.name} has {len(kit)}: the project's "
        f"servo names {' and '.join(parts)}"
    ]


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
    if joint_map is not None and fmt != "urdf":
        raise click.UsageError(
            "--joint-map names a URDF file (a `--robot FILE` reads URDF): export --format urdf"
        )
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
