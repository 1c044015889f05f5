"""``rcb4hv project add-motion``: save keyframes as a new motion of a HeartToHeart4 project
(the Teach page of ``rcb4hv ui`` does the same), from the keyframes JSON it reads."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import click

from rcb4hv.cli._util import MOTION_SLOT, OUTPUT_FILE, handle_errors, output_option
from rcb4hv.errors import EditError
from rcb4hv.files import write_atomic
from rcb4hv.hth4 import dump_motion_xml, dump_project, parse_project
from rcb4hv.hth4.edit import bind_button
from rcb4hv.hth4.keyframes import (
    Keyframe,
    add_motion,
    flowchart_from_keyframes,
    free_slots,
    motion_from_keyframes,
)
from rcb4hv.protocol import SystemRegister


def register(cli: click.Group) -> None:
    group = cli.commands.get("project")
    if not isinstance(group, click.Group):
        raise RuntimeError("rcb4hv.cli.project_cmd must be registered before teach_cmd")
    group.add_command(add_motion_command)


def _ics_key(i: int, key: object) -> int:
    """An ICS number key of a keyframe's positions ("2" or 2)."""
    if isinstance(key, int) and not isinstance(key, bool):
        return key
    if isinstance(key, str) and key.strip().lstrip("-").isdigit():
        return int(key)
    raise EditError(f"keyframe {i}: servo key {key!r} is not an ICS number")


def parse_keyframes(data: Any) -> list[Keyframe]:
    """``{"keyframes": [{"time": 0.5, "positions": {"2": 7500, ...}, "name": "..."}]}``
    (or just the list). EditError naming the keyframe for anything else: a position that is
    not an integer (7500.7 is refused, not cut to 7500), a time that is not a finite number."""
    items = data.get("keyframes") if isinstance(data, dict) else data
    if not isinstance(items, list):
        raise EditError('keyframes JSON: expected {"keyframes": [...]} or a list')
    out = []
    for i, item in enumerate(items, 1):
        if not isinstance(item, dict) or "time" not in item or "positions" not in item:
            raise EditError(f"keyframe {i}: needs 'time' and 'positions'")
        raw = item["positions"]
        if not isinstance(raw, dict):
            raise EditError(f"keyframe {i}: 'positions' maps ICS numbers to positions")
        try:
            positions = {_ics_key(i, k): v for k, v in raw.items()}
            out.append(Keyframe(item["time"], positions, str(item.get("name", ""))))
        except EditError as exc:
            text = str(exc)
            if not text.startswith(f"keyframe {i}:"):
                text = f"keyframe {i}: {text}"
            raise EditError(text) from None
    return out


@click.command("add-motion")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.argument("keyframes", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--name", required=True, help="Motion name.")
@click.option(
    "--slot",
    type=MOTION_SLOT,
    default=None,
    help="Motion slot (default: the first free one).",
)
@click.option("--button", default="", help="Bind to remote buttons, e.g. TRIANGLE or UP+S1.")
@output_option("Where to write the new .h4p.")
@click.option(
    "--flowchart",
    type=OUTPUT_FILE,
    default=None,
    help="Also write the motion's HeartToHeart4 flowchart (.xml) here.",
)
@handle_errors
def add_motion_command(
    file: Path,
    keyframes: Path,
    name: str,
    slot: int | None,
    button: str,
    output: Path,
    flowchart: Path | None,
) -> None:
    """Save KEYFRAMES (JSON: time in seconds and ICS -> position per pose) as a new motion of
    project FILE, in a free slot, as HeartToHeart4 compiles a chain of Pos boxes."""
    from rcb4hv.cli.project_common import parse_buttons
    from rcb4hv.hth4 import load_project

    project = load_project(file)
    try:
        data = json.loads(keyframes.read_text(encoding="utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{keyframes}: not JSON keyframes: {exc}") from None
    frames = parse_keyframes(data)
    free = free_slots(project)
    if slot is None:
        if not free:
            raise ValueError(f"{file} has no free motion slot")
        slot = free[0]
    period = SystemRegister.from_word(project.system_register).frame_period_ms
    word = parse_buttons(button) if button else 0
    from rcb4hv.project.relocate import project_layout

    motion = motion_from_keyframes(
        frames, slot=slot, name=name, period_ms=period, button=0, layout=project_layout(project)
    )
    # bound as `project bind` binds: a word another motion holds is refused, not doubled
    added = add_motion(project, motion)
    if word:
        added = bind_button(added, slot, word)
    data = dump_project(added)
    if dump_project(parse_project(data)) != data:
        raise ValueError("the new project does not round-trip; nothing written")
    write_atomic(output, data)
    if flowchart is not None:
        write_atomic(flowchart, dump_motion_xml(flowchart_from_keyframes(frames, period)))
    click.echo(
        f"{output}: motion {slot} {name!r}, {len(frames)} keyframes, "
        f"{len(motion.rom_bytes())} bytes at {motion.address:05X}h"
    )
