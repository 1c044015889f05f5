"""``rcb4hv project``: HeartToHeart4 projects -> ROM image, simulation, upload, inspection."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from rcb4hv.cli import (
    _output,
    edit_cmd,
    project_check_cmd,
    project_motion_cmd,
    project_new_cmd,
    project_pose_cmd,
    project_sim_cmd,
)
from rcb4hv.cli._util import (
    Connection,
    handle_errors,
    output_option,
    pass_connection,
    print_json,
    print_table,
)
from rcb4hv.cli.project_common import (
    IMAGE_LAYOUT_OPTION,
    LAYOUT_OPTION,
    build_options,
    current_build_options,
    load_image,
    read_rom_image,
)
from rcb4hv.files import write_atomic

if TYPE_CHECKING:
    from rcb4hv.project.image import ImageContents


def _button_text(buttons: int, compare: str = "Equals") -> str:
    from rcb4hv.project.image import button_names

    names = button_names(buttons)
    return names if compare == "Equals" else f"{compare} {names}"


def _image_entry(
    c: ImageContents, slot: int, address: int, frames: int = 0, size: int = 0
) -> dict[str, Any]:
    """The entry of ``project image`` for the motion slot at ``address``."""
    return {
        "slot": slot,
        "address": f"{address:05X}",
        "frames": frames,
        "bytes": size,
        "buttons": [
            _button_text(b.buttons, b.compare_type) for b in c.bindings if b.target == address
        ],
        "startup": c.startup_motion_address == address,
        "priority": [i for i, p in c.priority.items() if p["address"] == address],
    }


@click.group()
def project() -> None:
    """HeartToHeart4 projects (.h4p): build, inspect, check, simulate and upload ROM images."""


@project.command("build")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@output_option("Where to write the 256 KB image.")
@build_options
@LAYOUT_OPTION
@handle_errors
def build(file: Path, output: Path, layout_name: str | None) -> None:
    """Build the 256 KB ROM image of FILE in its HeartToHeart4 layout (or --layout)."""
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.relocate import project_image

    p = load_project(file)
    image, lay = project_image(p, layout_name, options=current_build_options())
    write_atomic(output, image)
    click.echo(
        f"wrote {len(image)} bytes ({len(p.used_motions)} motions, HeartToHeart4 "
        f"{lay.version} layout) to {output}"
    )


@project.command("info")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@handle_errors
def info(file: Path, as_json: bool) -> None:
    """Motions (slot, address, name, frames, button) and servos of FILE (.h4p)."""
    from rcb4hv.hth4 import load_project

    p = load_project(file)
    startup = p.startup_motion_address
    prio = {pm.address: i for i, pm in p.active_priority_motions}
    motions: list[dict[str, Any]] = []
    for m in p.used_motions:
        motions.append(
            {
                "slot": m.slot,
                "address": f"{m.address:05X}",
                "name": m.name or "",
                "frames": len(m.frames),
                "bytes": m.code_size,
                "button": m.button_data,
                "button_names": _button_text(m.button_data, m.compare_type)
                if m.button_data
                else "",
                "compare_type": m.compare_type,
                "startup": m.address == startup,
                "priority": prio.get(m.address),
            }
        )
    servos: list[dict[str, Any]] = []
    for s in p.servos:
        if not s.in_use:
            continue
        servos.append(
            {
                "ics": s.ics_number,
                "id": s.id,
                "name": s.name or "",
                "port": s.port,
                "trim": s.trim,
                "home": s.home_position,
                "mixing1": [s.mixing1_address, s.mixing1_rate],
                "mixing2": [s.mixing2_address, s.mixing2_rate],
            }
        )
    settings = {
        "title": p.project_title,
        "system_register": f"{p.system_register:04X}",
        "startup_motion": None if startup < 0 else f"{startup:05X}",
        "priority_motions": [
            {
                "check": i,
                "name": pm.name,
                "port": pm.port,
                "compare_type": pm.compare_type,
                "value": pm.value,
                "address": None if pm.address < 0 else f"{pm.address:05X}",
            }
            for i, pm in p.active_priority_motions
        ],
        "low_power_motion": None
        if p.low_power_motion_address < 0
        else f"{p.low_power_motion_address:05X}",
        "low_power_value": p.low_power_value,
    }
    if as_json:
        print_json({"settings": settings, "motions": motions, "servos": servos})
        return
    click.echo(
        f"{file.name}: {settings['title'] or '(no title)'}, system register "
        f"{settings['system_register']}h, {len(motions)} motions, "
        f"{len(servos)} servos"
    )
    for line in project_check_cmd.settings_lines(p):
        click.echo(line)
    click.echo("")
    rows = []
    for mi in motions:
        notes = []
        if mi["startup"]:
            notes.append("startup")
        if mi["priority"] is not None:
            notes.append(f"priority {mi['priority']}")
        rows.append(
            [
                mi["slot"],
                mi["address"],
                mi["name"],
                mi["frames"],
                mi["bytes"],
                mi["button_names"],
                ", ".join(notes),
            ]
        )
    print_table(("slot", "address", "name", "frames", "bytes", "button", "note"), rows)
    click.echo("")
    print_table(
        ("ICS", "ID", "name", "port", "trim", "home", "mixing1", "mixing2"),
        [
            [
                s["ics"],
                s["id"],
                s["name"],
                s["port"],
                s["trim"],
                s["home"],
                "-" if s["mixing1"][0] == 0xFFFF else f"{s['mixing1'][0]:04X} x{s['mixing1'][1]}",
                "-" if s["mixing2"][0] == 0xFFFF else f"{s['mixing2'][0]:04X} x{s['mixing2'][1]}",
            ]
            for s in servos
        ],
    )


@project.command("image")
@click.argument("image", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
@IMAGE_LAYOUT_OPTION
@handle_errors
def image_cmd(image: Path, as_json: bool, layout_name: str | None) -> None:
    """The motions and settings a HeartToHeart4 ROM IMAGE holds."""
    from rcb4hv.project.image import read_image
    from rcb4hv.project.relocate import image_layout

    data = read_rom_image(
        image, "use `rcb4hv project info` to read it, `rcb4hv project build` for its image"
    )
    lay = image_layout(data, layout_name)
    c = read_image(data, lay)
    motions = [_image_entry(c, m.slot, m.address, len(m.frames), m.size) for m in c.motions]
    if as_json:
        print_json(
            {
                "title": c.title,
                "layout": lay.version,
                "system_register": f"{c.system_register:04X}",
                "startup_motion": None
                if c.startup_motion_address < 0
                else f"{c.startup_motion_address:05X}",
                "ad_references": list(c.description.ad_references),
                "servos": {str(k): v for k, v in c.servos.items()},
                "priority_motions": {str(k): v for k, v in c.priority.items()},
                "motions": motions,
                "undecoded_slots": [
                    {
                        "slot": u.slot,
                        "address": f"{u.address:05X}",
                        "at": f"{u.at:05X}",
                        "reason": u.reason,
                        "note": u.note,
                    }
                    for u in c.undecoded
                ],
            }
        )
        return
    bad = {u.slot: u for u in c.undecoded}
    click.echo(
        f"{image.name}: {c.title or '(no title)'}, HeartToHeart4 {lay.version} layout, system "
        f"register {c.system_register:04X}h, {len(motions)} motions, "
        f"{len(c.servos)} servos"
        + (", 1 slot that does not decode" if len(bad) == 1 else "")
        + (f", {len(bad)} slots that do not decode" if len(bad) > 1 else "")
    )
    for line in project_check_cmd.image_settings_lines(c, lay):
        click.echo(line)
    click.echo("")
    used = {m.slot for m in c.motions}  # a slot with garbage from its first byte is no motion
    motions += [_image_entry(c, u.slot, u.address) for u in bad.values() if u.slot not in used]
    rows = []
    for m in sorted(motions, key=lambda m: int(m["slot"])):
        notes = (["startup"] if m["startup"] else []) + [f"priority {i}" for i in m["priority"]]
        if m["slot"] in bad:
            notes.append(bad[m["slot"]].note)
        row = [m["slot"], m["address"], m["frames"], m["bytes"], ", ".join(m["buttons"])]
        rows.append([*row, ", ".join(notes)])
    print_table(("slot", "address", "frames", "bytes", "button", "note"), rows)


@project.command("upload")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@pass_connection
@click.option(
    "--only-changed",
    is_flag=True,
    help="Read the board's ROM first; write only the 128-byte pages that differ.",
)
@click.option(
    "--verify/--no-verify",
    default=True,
    show_default=True,
    help="Read every written chunk back and compare.",
)
@click.option(
    "--restart/--no-restart",
    default=True,
    show_default=True,
    help="Restart the ROM program from 000000h afterwards.",
)
@_output.PROGRESS_OPTION
@build_options
@handle_errors
def upload(
    conn: Connection,
    file: Path,
    only_changed: bool,
    verify: bool,
    restart: bool,
    progress: bool | None,
) -> None:
    """Write the ROM image of FILE (.h4p or a 256 KB image) to the board at --port."""
    from rcb4hv.project.upload import upload_image

    image, _, _ = load_image(file)
    with conn.open() as robot:
        try:
            if only_changed:
                with _output.progress(len(image), "read", progress) as rbar:
                    current = robot.read_rom(0, len(image), progress=rbar)
                from rcb4hv.project.upload import changed_pages

                n = len(changed_pages(current, image))
                with _output.progress(n * 128, "write", progress) as bar:
                    res = upload_image(
                        robot,
                        image,
                        only_changed=True,
                        verify=verify,
                        restart=restart,
                        progress=bar,
                        known=current,
                    )
            else:
                with _output.progress(len(image), "write", progress) as bar:
                    res = upload_image(robot, image, verify=verify, restart=restart, progress=bar)
        except KeyboardInterrupt:
            click.echo(
                "interrupted: the board's ROM is partly written and its program is stopped; "
                f"`rcb4hv project upload {file} --only-changed` (with the same --port) "
                "writes the rest",
                err=True,
            )
            sys.exit(130)
    checked = " and verified" if verify else ""
    click.echo(
        f"wrote{checked} {res.pages_written} of {res.pages_total} pages ({res.bytes_written} bytes)"
    )


def register(cli: click.Group) -> None:
    """Add the ``project`` group to ``cli``."""
    project_check_cmd.register(project)
    project_sim_cmd.register(project)
    edit_cmd.register(project)
    project_pose_cmd.register(project)
    project_motion_cmd.register(project)
    project_new_cmd.register(project)
    cli.add_command(project)
