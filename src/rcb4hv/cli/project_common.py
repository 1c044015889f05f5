"""What the ``rcb4hv project`` commands share: loading a project or image, the layout and
build options, button names, the simulation's exit codes and the slots an image holds."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click

from rcb4hv.project.options import EMPTY_STARTUP, PRIORITY_NONE, BuildOptions
from rcb4hv.protocol import Button
from rcb4hv.rom.layout import HTH4_22, MotionLayout

__all__ = [
    "LAYOUT_OPTION",
    "STATUS_EXIT",
    "build_options",
    "current_build_options",
    "image_slots",
    "load_image",
    "parse_buttons",
]

F = TypeVar("F", bound=Callable[..., Any])
_META_KEY = "rcb4hv.build_options"


def _store(ctx: click.Context, param: click.Parameter, value: str) -> str:
    opts = ctx.meta.get(_META_KEY, {})
    opts[param.name] = value
    ctx.meta[_META_KEY] = opts
    return value


def build_options(func: F) -> F:
    """Add ``--priority-none`` and ``--empty-startup`` (read with :func:`current_build_options`)."""
    func = click.option(
        "--empty-startup",
        "empty_startup",
        type=click.Choice(EMPTY_STARTUP),
        default="call",
        show_default=True,
        expose_value=False,
        callback=_store,
        help="A startup address where no motion starts: CALL it as stored, or write 'none'.",
    )(func)
    return click.option(
        "--priority-none",
        "priority_none",
        type=click.Choice(PRIORITY_NONE),
        default="stub",
        show_default=True,
        expose_value=False,
        callback=_store,
        help="A priority check with Address -1: CALL the RETURN stub, or leave the check unused.",
    )(func)


def current_build_options() -> BuildOptions:
    """The build options given to the running command (defaults outside a command)."""
    ctx = click.get_current_context(silent=True)
    values = {} if ctx is None else ctx.meta.get(_META_KEY, {})
    return BuildOptions(**values)


STATUS_EXIT = {"error": 1, "timeout": 2, "stalled": 2}


def parse_buttons(text: str) -> int:
    value = 0
    for part in text.replace("|", "+").replace(",", "+").split("+"):
        name = part.strip().upper()
        if not name:
            continue
        try:
            value |= int(Button[name])
        except KeyError:
            names = ", ".join(b.name for b in Button if b.name and b is not Button.NONE)
            raise click.BadParameter(f"unknown button {part!r} (one of {names})") from None
    if not value:
        raise click.BadParameter("no button named")
    return value


LAYOUT_OPTION = click.option(
    "--layout",
    "layout_name",
    type=click.Choice(["2.2", "2.1", "2.0", "1.3"]),
    default=None,
    help="HeartToHeart4 layout [default: the one the motions' stored addresses (or the "
    "image's main loop) show; a project is moved to the layout given].",
)


def load_image(
    path: Path, layout_name: str | None = None
) -> tuple[bytes, MotionLayout, dict[int, str]]:
    """(image, layout, names by slot) of a .h4p project or a raw 256 KB image file."""
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.relocate import image_layout, project_image

    if path.suffix.lower() == ".h4p":
        project = load_project(path)
        names = {m.slot: m.name or "" for m in project.used_motions}
        image, lay = project_image(project, layout_name, options=current_build_options())
        return image, lay, names
    data = path.read_bytes()
    from rcb4hv.rom import layout

    if len(data) != layout.ROM_SIZE:
        raise ValueError(f"{path}: not a .h4p project nor a {layout.ROM_SIZE}-byte ROM image")
    return data, image_layout(data, layout_name, default=HTH4_22), {}


def image_slots(image: bytes, lay: MotionLayout = HTH4_22) -> list[int]:
    from rcb4hv.project.image import read_image

    return [m.slot for m in read_image(image, lay).motions]
