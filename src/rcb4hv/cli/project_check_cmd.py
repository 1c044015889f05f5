"""``rcb4hv project check`` (the lint) and the settings lines of ``project info`` and ``project
image``. Registered into the ``project`` group by :mod:`rcb4hv.cli.project_cmd`."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, TypeAlias, cast

import click

from rcb4hv.cli._util import handle_errors, print_json, print_table
from rcb4hv.hth4 import Project

if TYPE_CHECKING:
    from rcb4hv.project.check import Finding
    from rcb4hv.project.image import ImageContents
    from rcb4hv.rom.layout import MotionLayout

__all__ = ["image_settings_lines", "register", "settings_lines"]


Slot: TypeAlias = Callable[[int], tuple[int, str | None] | None]
"""(slot, what it holds: a name, "" for a motion without one, None for none) of the motion
slot starting at an address, None if no slot starts there."""


def _target_text(slot_at: Slot, address: int, stub: int) -> str:
    """``13B80h (slot 39, NAME)``, ``none`` for a negative address, the layout's start-up
    ``stub`` (a RETURN: HeartToHeart4's "no motion"), or what is wrong."""
    if address < 0:
        return "none"
    if address == stub:
        return f"{address:05X}h (the start-up stub, a RETURN: no motion)"
    found = slot_at(address)
    if found is None:
        return f"{address:05X}h (not the start of a motion slot)"
    slot, label = found
    if label is None:
        return f"{address:05X}h (slot {slot} holds no motion)"
    return f"{address:05X}h (slot {slot}{', ' if label else ''}{label})"


def _settings_lines(
    slot_at: Slot,
    stub: int,
    startup: int,
    priority: Iterable[tuple[int, str, str, int, int]],
    low_power: tuple[int, int] | None = None,
) -> list[str]:
    """The startup (and low-power: address, AD0 value) lines and a line a priority check
    (index, port, compare type, value, address)."""
    lines = [f"startup motion: {_target_text(slot_at, startup, stub)}"]
    if low_power is not None:
        address, value = low_power
        at = f" at AD0 <= {value}" if address >= 0 else ""
        lines.append(f"low-power motion: {_target_text(slot_at, address, stub)}{at}")
    for i, port, compare, value, address in priority:
        lines.append(
            f"priority check {i}: {port} {compare} {value} -> "
            f"{_target_text(slot_at, address, stub)}"
        )
    return lines


def settings_lines(project: Project) -> list[str]:
    """The startup, low-power and priority settings, "none" where they name no motion."""

    def slot_at(address: int) -> tuple[int, str | None] | None:
        m = project.motion_at(address)
        if m is None:
            return None
        return m.slot, None if m.is_empty else m.name or "unnamed"

    from rcb4hv.project.relocate import project_layout

    return _settings_lines(
        slot_at,
        project_layout(project).startup_stub,
        project.startup_motion_address,
        [
            (i, pm.port, pm.compare_type, pm.value, pm.address)
            for i, pm in project.active_priority_motions
        ],
        (project.low_power_motion_address, project.low_power_value),
    )


def image_settings_lines(image: ImageContents, layout: MotionLayout) -> list[str]:
    """The startup and priority settings of a ROM image (of ``layout``), as
    :func:`settings_lines` gives a project's (an image holds a low-power motion as a priority
    check)."""
    held = {m.slot: "" for m in image.motions} | {
        u.slot: "does not decode" for u in image.undecoded
    }

    def slot_at(address: int) -> tuple[int, str | None] | None:
        n = layout.motion_at(address)
        if n is None or layout.address(n) != address:
            return None
        return n, held.get(n)

    checks = [
        (i, str(p["port"]), str(p["compare_type"]), cast(int, p["value"]), cast(int, p["address"]))
        for i, p in image.priority.items()
    ]
    return _settings_lines(slot_at, layout.startup_stub, image.startup_motion_address, checks)


def _short(text: str, width: int) -> str:
    return text if len(text) <= width else text[: width - 3] + "..."


def _physics_findings(project: Project, robot: str | None) -> list[Finding]:
    from rcb4hv.cli.project_common import LoadedFile
    from rcb4hv.cli.project_physics import physics_robot
    from rcb4hv.project.physics_sim import physics_findings
    from rcb4hv.project.run import run_motions

    loaded = LoadedFile.of_project(project)
    image, lay, names = loaded.image, loaded.layout, loaded.names
    model = physics_robot(project, image, robot)
    run = run_motions(image, sorted(names), names=names, motion_layout=lay, robot=model)
    return physics_findings(run.motions)


@click.command("check")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@click.option(
    "--physics",
    is_flag=True,
    help="Also play every motion on the robot in MuJoCo (needs rcb4hv[sim]) and warn of "
    "falls and joints at their torque limit.",
)
@click.option(
    "--balance",
    is_flag=True,
    help="Also warn of poses that cannot stand still (centre of mass outside the support) "
    "and of servos a pose loads beyond their stall torque (static, no physics needed).",
)
@click.option(
    "--robot",
    metavar="NAME|FILE",
    help="Robot for the joint limits, --physics and --balance [default: detected].",
)
@handle_errors
def check(file: Path, as_json: bool, physics: bool, balance: bool, robot: str | None) -> None:
    """Lint FILE (.h4p) before it goes on a robot.

    Reports targets (startup, priority, low-power, buttons, JUMP/CALL) in empty slots or
    outside motions, positions outside 3500-11500, 12h values outside 1-127, speeds of 0,
    motions without a final RETURN, ICS numbers missing from the servo table, unreachable
    code and buttons bound twice; with a robot model (--robot, or detected), joint angles
    beyond a joint's hard (mechanical) limits or outside its advisory range (warnings).
    With --physics each motion is also played on the robot in MuJoCo (from standing, as
    ``project simulate --physics``): "motion N makes the robot fall at t s" and "joint X
    saturates" are warnings. With --balance every pose is checked statically: "pose cannot
    stand still" (its centre of mass outside its support) and "joint X needs N% of its
    stall torque" are warnings. Exit status 0 when clean or only
    warnings, 1 on errors.
    """
    from rcb4hv.errors import NoRobotModelError
    from rcb4hv.hth4 import load_project
    from rcb4hv.hth4.robotpick import project_model
    from rcb4hv.project.check import check_project

    project = load_project(file)
    try:  # joint limits need the robot: --robot, or detected from the servo table
        model = project_model(project, robot)
    except NoRobotModelError:
        model = None
    findings = check_project(project, model)
    if physics:
        findings += _physics_findings(project, robot)
    if balance:
        from rcb4hv.project.posebalance import balance_findings

        findings += balance_findings(project, project_model(project, robot))
    errors = sum(f.severity == "error" for f in findings)
    warnings = len(findings) - errors
    if as_json:
        doc: dict[str, object] = {
            "file": str(file),
            "errors": errors,
            "warnings": warnings,
            "findings": [f.to_dict() for f in findings],
        }
        if physics:  # what the falls and saturations were found on
            from rcb4hv.physics import engine_version

            doc["physics"] = {"engine": engine_version()}
        print_json(doc)
    else:
        if findings:
            print_table(
                ("severity", "slot", "name", "address", "instruction", "reason"),
                [
                    [
                        f.severity,
                        "-" if f.slot is None else f.slot,
                        f.name,
                        "-" if f.address is None else f"{f.address:05X}",
                        _short(f.instruction, 48),
                        f"{f.reason} [{f.code}]",
                    ]
                    for f in findings
                ],
            )
        click.echo(f"{file.name}: {errors} errors, {warnings} warnings")
    sys.exit(1 if errors else 0)


def register(project: click.Group) -> None:
    """Add ``check`` to the ``project`` group."""
    project.add_command(check)
