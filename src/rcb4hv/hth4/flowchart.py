"""Single-motion flowcharts (``.xml``, root ``CanvasData``) exported by HeartToHeart4.

A flowchart is the editor's picture of one motion: boxes (``Activities``, each an
``ActivityData``) connected by arrows (``Lines``, each a ``LineData``). Inferred meanings:

* ``CanvasData``: ``Name`` (``canvas``), canvas ``Size``, ``GridSize``, ``BackColorText``.
* ``LineData``: ``GUID``; ``Path`` of ``Point`` (X, Y) from start to end; ``ConnectMode``
  (``Normal``; other values not seen).
* ``ActivityData``: ``Name`` (``Pos1``, ``ServoParam2`` … = ``BaseName`` + a counter);
  ``GUID``; ``Location``, ``Size``; ``Text`` (label shown); ``BackColorText``;
  ``MotionFlag`` (``Start`` for the entry box, ``None`` otherwise, other values not seen);
  ``BaseName`` (box kind: ``Pos``, ``ServoParam``, …); ``Description`` (kind description);
  ``Group`` (``Position``, ``Set``, …); ``ConnectedGuids`` (comma-separated GUIDs of the
  lines touching the box) with ``ConnectTypes`` (comma-separated, ``BeginConnect`` /
  ``EndConnect`` per GUID); ``ProgramCode``: the command frames the box compiles to, hex
  strings as in projects; ``Hint`` (tool-tip text).

Boxes are stored in editor order, not execution order; follow the lines to get the order.
Round trip is byte-identical for XmlSerializer output (see :mod:`rcb4hv.hth4.project`).

Older HeartToHeart4 versions wrote the same boxes and arrows as one ``ArrayOfAnyType`` list
with no ``CanvasData``; :mod:`rcb4hv.hth4.flowchart_older` reads and writes that form into
this model (:attr:`Flowchart.item_types` is then set).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace
from pathlib import Path

from rcb4hv.hth4._files import write_atomic
from rcb4hv.hth4._xml import (
    XSI_FIRST_LAYOUT,
    Builder,
    ExtraElement,
    Hth4FormatError,
    XmlLayout,
    _Reader,
    parse_document,
    root_reader,
    serialize,
)
from rcb4hv.hth4.model import Point

__all__ = [
    "Flowchart",
    "FlowchartActivity",
    "FlowchartLine",
    "Size",
    "dump_motion_xml",
    "load_motion_xml",
    "parse_motion_xml",
    "save_motion_xml",
]

ROOT = "CanvasData"


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


def load_motion_xml(path: str | os.PathLike[str]) -> Flowchart:
    """Read a single-motion flowchart file (``.xml``)."""
    return parse_motion_xml(Path(path).read_bytes())


def parse_motion_xml(data: bytes | str) -> Flowchart:
    """Parse the text of a flowchart file (either form)."""
    try:
        root, layout = parse_document(data, ROOT, XSI_FIRST_LAYOUT)
    except Hth4FormatError as exc:
        from rcb4hv.hth4.flowchart_older import OLDER_ROOT, parse_older_flowchart

        if exc.path != OLDER_ROOT:
            raise
        return parse_older_flowchart(data)
    r = root_reader(root)
    size = r.child("Size")
    chart = Flowchart(
        name=r.opt_str_of("Name"),
        size=Size(size.int_of("Width"), size.int_of("Height")),
        grid_size=r.int_of("GridSize"),
        lines=tuple(_read_line(x) for x in r.child("Lines").items("anyType", "LineData")),
        activities=tuple(
            _read_activity(x) for x in r.child("Activities").items("anyType", "ActivityData")
        ),
        back_color_text=r.opt_str_of("BackColorText"),
        layout=layout,
    )
    extras: list[ExtraElement] = []
    r.close(extras)
    return replace(chart, extra=tuple(extras)) if extras else chart


def _point(p: _Reader) -> Point:
    return Point(p.int_of("X"), p.int_of("Y"))


def _read_line(x: _Reader) -> FlowchartLine:
    x.xsi_type("LineData")
    return FlowchartLine(
        guid=x.opt_str_of("GUID"),
        path=tuple(_point(p) for p in x.child("Path").items("Point")),
        connect_mode=x.str_of("ConnectMode"),
    )


def _read_activity(x: _Reader) -> FlowchartActivity:
    x.xsi_type("ActivityData")
    loc = x.child("Location")
    size = x.child("Size")
    return FlowchartActivity(
        name=x.opt_str_of("Name"),
        guid=x.opt_str_of("GUID"),
        location=_point(loc),
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


def dump_motion_xml(chart: Flowchart) -> bytes:
    """The ``.xml`` file contents for ``chart`` (in the form it was read in)."""
    if chart.item_types is not None:
        from rcb4hv.hth4.flowchart_older import dump_older_flowchart

        return dump_older_flowchart(chart)
    b = Builder(ROOT, "")
    b.opt_leaf("Name", chart.name)
    _size(b.child("Size"), chart.size)
    b.int_leaf("GridSize", chart.grid_size)
    lines = b.child("Lines")
    for line in chart.lines:
        x = lines.item("anyType", "LineData")
        x.opt_leaf("GUID", line.guid)
        path = x.child("Path")
        for p in line.path:
            _pt(path.item("Point"), p)
        x.leaf("ConnectMode", line.connect_mode)
    acts = b.child("Activities")
    for a in chart.activities:
        write_activity(acts.item("anyType", "ActivityData"), a)
    b.opt_leaf("BackColorText", chart.back_color_text)
    return serialize(b.to_node(chart.extra), chart.layout)


def write_activity(x: Builder, a: FlowchartActivity) -> None:
    """The children of an ``ActivityData`` item (absent optional fields are not written)."""
    x.opt_leaf("Name", a.name)
    x.opt_leaf("GUID", a.guid)
    _pt(x.child("Location"), a.location)
    _size(x.child("Size"), a.size)
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


def save_motion_xml(chart: Flowchart, path: str | os.PathLike[str]) -> None:
    """Write ``chart`` to ``path``."""
    write_atomic(path, dump_motion_xml(chart))


def _pt(b: Builder, p: Point) -> None:
    b.int_leaf("X", p.x)
    b.int_leaf("Y", p.y)


def _size(b: Builder, s: Size) -> None:
    b.int_leaf("Width", s.width)
    b.int_leaf("Height", s.height)
