"""``rcb4hv robot fk`` and ``rcb4hv robot ik``: a link's position for joint angles, and the
joint angles that put a hand or foot at a target (:mod:`rcb4hv.robot.ik`)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import click

from rcb4hv.cli._util import FINITE, handle_errors, print_json
from rcb4hv.errors import RobotModelError
from rcb4hv.robot.builtin import load_robot
from rcb4hv.robot.ik import Orient, solve
from rcb4hv.robot.kinematics import from_xyz_rpy, link_pose, position
from rcb4hv.robot.model import RobotModel
from rcb4hv.robot.wholebody import point_in_start_frame, solve_balanced


def read_angles(model: RobotModel, path: Path) -> dict[str, float]:
    """Joint angles (radians by joint name) from a JSON file: ``{"angles": {...}}`` (what
    ``robot ik --json`` prints) or the mapping itself; the model's home pose fills the rest."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise RobotModelError(f"{path}: not JSON ({exc})") from None
    if isinstance(data, dict) and isinstance(data.get("angles"), dict):
        data = data["angles"]
    if not isinstance(data, dict):
        raise RobotModelError(f"{path}: expected a JSON object of joint angles")
    names = {j.name for j in model.joints}
    out = dict(model.home)
    for name, value in data.items():
        if name not in names:
            raise RobotModelError(f"{path}: {model.name} has no joint {name!r}")
        if not isinstance(value, int | float) or not math.isfinite(value):
            raise RobotModelError(f"{path}: joint {name!r}: {value!r} is not an angle")
        out[name] = float(value)
    return out


_ANGLES_FILE = click.Path(exists=True, dir_okay=False, path_type=Path)


def _rounded(v: tuple[float, float, float]) -> list[float]:
    return [round(x, 6) for x in v]


@click.command("fk")
@click.argument("name")
@click.option("--link", required=True, help="The link, e.g. l_foot, r_forearm.")
@click.option(
    "--angles",
    "angles_file",
    type=_ANGLES_FILE,
    help="JSON joint angles (rad), e.g. what `robot ik --json` wrote; default: home pose.",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def fk(name: str, link: str, angles_file: Path | None, as_json: bool) -> None:
    """Position of LINK's origin in metres, in the torso (root link) frame."""
    model = load_robot(name)
    angles = dict(model.home) if angles_file is None else read_angles(model, angles_file)
    pos = _rounded(position(link_pose(model, link, angles)))
    if as_json:
        print_json({"pos": pos})
    else:
        click.echo(f"{link}: x {pos[0]:+.4f}  y {pos[1]:+.4f}  z {pos[2]:+.4f} m")


@click.command("ik")
@click.argument("name")
@click.option("--link", required=True, help="The hand or foot link to move, e.g. l_foot.")
@click.option("--pos", nargs=3, type=FINITE, required=True, help="Target X Y Z (m, torso frame).")
@click.option(
    "--rpy",
    nargs=3,
    type=FINITE,
    default=None,
    help="Target orientation: roll pitch yaw in degrees (torso frame); default: keep it.",
)
@click.option(
    "--orient",
    type=click.Choice(["auto", "full", "normal", "none"]),
    default="auto",
    show_default=True,
    help="Which orientation to hold: as the chain allows, all axes, the link's z, none.",
)
@click.option(
    "--angles",
    "angles_file",
    type=_ANGLES_FILE,
    help="JSON joint angles to start from (default: home pose).",
)
@click.option(
    "--balance",
    is_flag=True,
    help="Keep the other feet in place and the centre of mass over them (the body shifts).",
)
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def ik(
    name: str,
    link: str,
    pos: tuple[float, float, float],
    rpy: tuple[float, float, float] | None,
    orient: Orient,
    angles_file: Path | None,
    balance: bool,
    as_json: bool,
) -> None:
    """Joint angles that put LINK's origin at --pos; an unreachable target gives the nearest
    pose and a warning on stderr."""
    model = load_robot(name)
    seed = dict(model.home) if angles_file is None else read_angles(model, angles_file)
    target = pos if rpy is None else from_xyz_rpy(pos, tuple(math.radians(a) for a in rpy))  # type: ignore[arg-type]
    if balance:
        if rpy is not None:
            raise click.UsageError("--balance takes a position target (--pos), not --rpy")
        result = solve_balanced(model, link, pos, seed, orient=orient)
    else:
        result = solve(model, link, target, seed, orient=orient)
    if balance:  # the body moved: the link where the target is, in the start pose's frame
        got = _rounded(point_in_start_frame(model, link, seed, result.angles))
    else:
        got = _rounded(position(link_pose(model, link, result.angles)))
    if not result.reached:
        click.echo(f"warning: {link}: {result.message}", err=True)
    if as_json:
        print_json(
            {
                "angles": {k: round(v, 6) for k, v in sorted(result.angles.items())},
                "pos": got,
                "reached": result.reached,
                "error_m": round(result.position_error, 6),
            }
        )
        return
    for k, v in sorted(result.angles.items()):
        click.echo(f"{k:20s} {math.degrees(v):+8.2f}°")
    click.echo(f"{link}: x {got[0]:+.4f}  y {got[1]:+.4f}  z {got[2]:+.4f} m ({result.message})")


def register(cli: click.Group) -> None:
    group = cli.commands["robot"]
    assert isinstance(group, click.Group)
    group.add_command(fk)
    group.add_command(ik)
