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
the same model (:mod:`rcb4hv.hth4.flowchart_model`; :attr:`Flowchart.item_types` is then
set). :func:`parse_motion_xml` chooses the reader from the document's root element.
"""

from __future__ import annotations

import os
from dataclasses import replace

from rcb4hv.files import read_bytes, write_atomic
from rcb4hv.hth4._xml import (
    XSI_FIRST_LAYOUT,
    ExtraElement,
    XmlReader,
    parse_document,
    root_reader,
    serialize,
)
from rcb4hv.hth4._xmlbuild import Builder
from rcb4hv.hth4.flowchart_model import (
    Flowchart,
    FlowchartLine,
    Size,
    read_activity,
    read_point,
    write_activity,
    write_point,
    write_size,
)
from rcb4hv.hth4.flowchart_older import OLDER_ROOT, dump_older_flowchart, read_older_flowchart

__all__ = [
    "ROOT",
    "dump_motion_xml",
    "load_motion_xml",
    "parse_motion_xml",
    "save_motion_xml",
]

ROOT = "CanvasData"


def load_motion_xml(path: str | os.PathLike[str]) -> Flowchart:
    """Read a single-motion flowchart file (``.xml``)."""
    return parse_motion_xml(read_bytes(path))


def parse_motion_xml(data: bytes | str) -> Flowchart:
    """Parse the text of a flowchart file: the form is the root element's (``CanvasData``,
    or the older ``ArrayOfAnyType``)."""
    root, layout = parse_document(data, (ROOT, OLDER_ROOT), XSI_FIRST_LAYOUT)
    if root.tag == OLDER_ROOT:
        return read_older_flowchart(root, layout)
    r = root_reader(root)
    size = r.child("Size")
    chart = Flowchart(
        name=r.opt_str_of("Name"),
        size=Size(size.int_of("Width"), size.int_of("Height")),
        grid_size=r.int_of("GridSize"),
        lines=tuple(read_canvas_line(x) for x in r.child("Lines").items("anyType", "LineData")),
        activities=tuple(
            read_activity(x) for x in r.child("Activities").items("anyType", "ActivityData")
        ),
        back_color_text=r.opt_str_of("BackColorText"),
        layout=layout,
    )
    extras: list[ExtraElement] = []
    r.close(extras)
    return replace(chart, extra=tuple(extras)) if extras else chart


def read_canvas_line(x: XmlReader) -> FlowchartLine:
    x.xsi_type("LineData")
    return FlowchartLine(
        guid=x.opt_str_of("GUID"),
        path=tuple(read_point(p) for p in x.child("Path").items("Point")),
        connect_mode=x.str_of("ConnectMode"),
    )


def dump_motion_xml(chart: Flowchart) -> bytes:
    """The ``.xml`` file contents for ``chart`` (in the form it was read in)."""
    if chart.item_types is not None:
        return dump_older_flowchart(chart)
    b = Builder(ROOT, "")
    b.opt_leaf("Name", chart.name)
    write_size(b.child("Size"), chart.size)
    b.int_leaf("GridSize", chart.grid_size)
    lines = b.child("Lines")
    for line in chart.lines:
        x = lines.item("anyType", "LineData")
        x.opt_leaf("GUID", line.guid)
        path = x.child("Path")
        for p in line.path:
            write_point(path.item("Point"), p)
        x.leaf("ConnectMode", line.connect_mode)
    acts = b.child("Activities")
    for a in chart.activities:
        write_activity(acts.item("anyType", "ActivityData"), a)
    b.opt_leaf("BackColorText", chart.back_color_text)
    return serialize(b.to_node(chart.extra), chart.layout)


def save_motion_xml(chart: Flowchart, path: str | os.PathLike[str]) -> None:
    """Write ``chart`` to ``path``."""
    write_atomic(path, dump_motion_xml(chart))
