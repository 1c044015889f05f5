"""The flowchart model shared by both file forms of a single-motion flowchart: boxes
(:class:`FlowchartActivity`), arrows (:class:`FlowchartLine`) and the chart
(:class:`Flowchart`), with the readers and writers of the parts both forms hold alike (points,
sizes, ``ActivityData``).

:mod:`rcb4hv.hth4.flowchart` reads and writes the ``CanvasData`` form and chooses the form
from the root element; :mod:`rcb4hv.hth4.flowchart_older` does the ``ArrayOfAnyType`` form.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rcb4hv.hth4._xml import XSI_FIRST_LAYOUT, ExtraElement, XmlLayout, XmlReader
from rcb4hv.hth4._xmlbuild import Builder
from rcb4hv.hth4.model import Point

__all__ = [
    "Flowchart",
    "FlowchartActivity",
    "FlowchartLine",
    "Size",
    "read_activity",
    "read_point",
    "write_activity",
    "write_point",
    "write_size",
]


@dataclass(frozen=True)
class Size:
    """A ``System.Drawing.Size``."""

    width: int = 0
    height: int = 0


_ORIGIN = Point()


@dataclass(frozen=True)
class FlowchartLine:
    """A ``LineData`` arrow."""

    guid: str | None
    path: tuple[Point, ...] = ()
    connect_mode: str = "Normal"


@dataclass(frozen=True)
class FlowchartActivity:
    """An ``ActivityData`` box and the frames it compiles to."""

    name: str | None
    guid: str | None
    location: Point = _ORIGIN
    size: Size = Size()
    text: str | None = ""
    back_color_text: str | None = "WhiteSmoke"
    motion_flag: str = "None"
    base_name: str | None = ""
    description: str | None = ""
    group: str | None = ""
    connected_guids: str | None = ""
    connect_types: str | None = ""
    program_code: tuple[bytes, ...] = ()
    hint: str | None = ""

    @property
    def connections(self) -> tuple[tuple[str, str], ...]:
        """(line GUID, connect type) pairs from ``ConnectedGuids``/``ConnectTypes``."""
        guids = [g for g in (self.connected_guids or "").split(",") if g]
        types = [t for t in (self.connect_types or "").split(",") if t]
        return tuple(zip(guids, types, strict=False))


@dataclass(frozen=True)
class Flowchart:
    """A ``CanvasData`` document (one motion's flowchart)."""

    name: str | None = "canvas"
    size: Size = Size(640, 480)
    grid_size: int = 8
    lines: tuple[FlowchartLine, ...] = ()
    activities: tuple[FlowchartActivity, ...] = ()
    back_color_text: str | None = "buttonface"
    extra: tuple[ExtraElement, ...] = ()
    layout: XmlLayout = field(default=XSI_FIRST_LAYOUT)
    item_types: tuple[str, ...] | None = None
    """None for the ``CanvasData`` form; for the older ``ArrayOfAnyType`` form the ``xsi:type``
    of each list item in file order (``ActivityData`` / ``LineData``)."""

    def activity(self, name: str) -> FlowchartActivity:
        """The box called ``name``; KeyError if none."""
        for a in self.activities:
            if a.name == name:
                return a
        raise KeyError(name)

    @property
    def start(self) -> FlowchartActivity | None:
        """The box whose ``MotionFlag`` is ``Start``, if any."""
        for a in self.activities:
            if a.motion_flag == "Start":
                return a
        return None


def read_point(p: XmlReader) -> Point:
    return Point(p.int_of("X"), p.int_of("Y"))


def read_activity(x: XmlReader) -> FlowchartActivity:
    x.xsi_type("ActivityData")
    loc = x.child("Location")
    size = x.child("Size")
    return FlowchartActivity(
        name=x.opt_str_of("Name"),
        guid=x.opt_str_of("GUID"),
        location=read_point(loc),
        size=Size(size.int_of("Width"), size.int_of("Height")),
        text=x.opt_str_of("Text"),
        back_color_text=x.opt_str_of("BackColorText"),
        motion_flag=x.str_of("MotionFlag"),
        base_name=x.opt_str_of("BaseName"),
        description=x.opt_str_of("Description"),
        group=x.opt_str_of("Group"),
        connected_guids=x.opt_str_of("ConnectedGuids"),
        connect_types=x.opt_str_of("ConnectTypes"),
        program_code=x.child("ProgramCode").hex_frames(),
        hint=x.opt_str_of("Hint"),
    )


def write_activity(x: Builder, a: FlowchartActivity) -> None:
    """The children of an ``ActivityData`` item (absent optional fields are not written)."""
    x.opt_leaf("Name", a.name)
    x.opt_leaf("GUID", a.guid)
    write_point(x.child("Location"), a.location)
    write_size(x.child("Size"), a.size)
    x.opt_leaf("Text", a.text)
    x.opt_leaf("BackColorText", a.back_color_text)
    x.leaf("MotionFlag", a.motion_flag)
    x.opt_leaf("BaseName", a.base_name)
    x.opt_leaf("Description", a.description)
    x.opt_leaf("Group", a.group)
    x.opt_leaf("ConnectedGuids", a.connected_guids)
    x.opt_leaf("ConnectTypes", a.connect_types)
    x.child("ProgramCode").hex_frames(a.program_code)
    x.opt_leaf("Hint", a.hint)


def write_point(b: Builder, p: Point) -> None:
    b.int_leaf("X", p.x)
    b.int_leaf("Y", p.y)


def write_size(b: Builder, s: Size) -> None:
    b.int_leaf("Width", s.width)
    b.int_leaf("Height", s.height)
