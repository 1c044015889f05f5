"""What the ``rcb4hv project`` commands share: loading a project or image, the layout and
build options, button names, the simulation's exit codes and the slots an image holds."""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from rcb4hv.errors import Hth4FormatError
from rcb4hv.project.options import EMPTY_STARTUP, PRIORITY_NONE, BuildOptions
from rcb4hv.protocol import Button
from rcb4hv.rom.layout import HTH4_22, ROM_SIZE, MotionLayout

if TYPE_CHECKING:
    from rcb4hv.hth4 import Project

__all__ = [
    "IMAGE_LAYOUT_OPTION",
    "LAYOUT_OPTION",
    "STATUS_EXIT",
    "LoadedFile",
    "build_options",
    "current_build_options",
    "image_slots",
    "load_file",
    "load_image",
    "parse_buttons",
    "read_project_or_image",
    "read_rom_image",
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
IMAGE_LAYOUT_OPTION = click.option(
    "--layout",
    "layout_name",
    type=click.Choice(["2.2", "2.1", "2.0", "1.3"]),
    default=None,
    help="HeartToHeart4 layout the ROM image was built in [default: the one its main loop shows].",
)


def _project_hint(data: bytes) -> str:
    """``"; it is a HeartToHeart4 project"`` if ``data`` parses as one, else ``""``."""
    from rcb4hv.hth4 import parse_project

    try:
        parse_project(data)
    except Hth4FormatError:
        return ""
    return "; it is a HeartToHeart4 project"


def read_rom_image(path: Path, project_advice: str) -> bytes:
    """The bytes of the 256 KB ROM image file ``path``; ValueError naming the file if it is
    another size, with ``project_advice`` (what to do instead) when it is a project."""
    data = path.read_bytes()
    if len(data) != ROM_SIZE:
        hint = _project_hint(data)
        advice = f": {project_advice}" if hint else ""
        raise ValueError(f"{path}: not a 256 KB ROM image ({len(data)} bytes){hint}{advice}")
    return data


def read_project_or_image(path: Path) -> Project | bytes:
    """A HeartToHeart4 project, or the bytes of a ROM image, told apart by content as every
    command does (a 262144-byte file is an image; anything else is parsed as a project)."""
    from rcb4hv.hth4 import parse_project

    data = path.read_bytes()
    if len(data) == ROM_SIZE:
        return data
    try:
        return parse_project(data)
    except Hth4FormatError as exc:
        raise Hth4FormatError(
            str(path),
            f"not a HeartToHeart4 project ({exc}) nor a {ROM_SIZE}-byte ROM image "
            f"({len(data)} bytes)",
        ) from None


@dataclass(frozen=True, slots=True)
class LoadedFile:
    """A project or ROM image file as a simulation or upload needs it."""

    image: bytes
    layout: MotionLayout
    names: dict[int, str]
    """The motions' names by slot (a project's; an image has none)."""
    project: Project | None
    """The project (None for an image)."""

    @classmethod
    def of_project(cls, project: Project, layout_name: str | None = None) -> LoadedFile:
        """``project`` built in its layout (or moved to ``layout_name``), with the running
        command's build options."""
        from rcb4hv.project.relocate import project_image

        names = {m.slot: m.name or "" for m in project.used_motions}
        image, lay = project_image(project, layout_name, options=current_build_options())
        return cls(image, lay, names, project)

    def check_slots(self, slots: Iterable[int]) -> None:
        """EditError for a slot that holds no motion of the project, as ``project poses``
        (:func:`rcb4hv.hth4.edit.used_motion`); an image is not checked."""
        from rcb4hv.hth4.edit import used_motion

        if self.project is not None:
            for slot in slots:
                used_motion(self.project, slot)


def load_file(path: Path, layout_name: str | None = None) -> LoadedFile:
    """A HeartToHeart4 project (built in its layout, or moved to ``layout_name``) or a raw
    256 KB image file (:func:`read_project_or_image`)."""
    from rcb4hv.project.relocate import image_layout

    loaded = read_project_or_image(path)
    if isinstance(loaded, bytes):
        return LoadedFile(loaded, image_layout(loaded, layout_name, default=HTH4_22), {}, None)
    return LoadedFile.of_project(loaded, layout_name)


def load_image(
    path: Path, layout_name: str | None = None
) -> tuple[bytes, MotionLayout, dict[int, str]]:
    """(image, layout, names by slot) of a project or a raw 256 KB image (:func:`load_file`)."""
    f = load_file(path, layout_name)
    return f.image, f.layout, f.names


def image_slots(image: bytes, lay: MotionLayout = HTH4_22) -> list[int]:
    from rcb4hv.project.image import read_image

    return [m.slot for m in read_image(image, lay).motions]
