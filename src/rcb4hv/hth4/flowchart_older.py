"""The older single-motion flowchart form: root ``ArrayOfAnyType``, no ``CanvasData``.

HeartToHeart4 versions before the ``CanvasData`` form (the KHR-3HV era; half of the motion
files python-khr3hv ships are in it) wrote a flowchart as one list::

    <ArrayOfAnyType xmlns:xsi=... xmlns:xsd=...>
      <anyType xsi:type="ActivityData"> Name, GUID, Location, Size, MotionFlag, PriorityList,
                                          BaseName, Description, Group, Path, ConnectedGuids,
                                          ConnectTypes, ProgramCode </anyType>
      ...
      <anyType xsi:type="LineData"> Name, StartPoint, EndPoint, GUID, LineType </anyType>
    </ArrayOfAnyType>

It reads into the same :class:`~rcb4hv.hth4.flowchart_model.Flowchart` model:

* each ``ActivityData`` becomes a :class:`FlowchartActivity` (no ``Text``, ``BackColorText``
  or ``Hint`` in this form: those stay None); ``PriorityList`` and ``Path`` (meaning not
  known) are kept as extras at their places;
* each ``LineData`` becomes a :class:`FlowchartLine` whose ``path`` is (StartPoint, EndPoint)
  and whose ``connect_mode`` holds ``LineType`` (``Straight``; ``True`` / ``False`` for the
  arrows out of a compare box, read as the ``ConnectMode`` of the ``CanvasData`` form, so a
  ``True`` arrow is the branch taken); its empty ``Name`` is kept as an extra;
* :attr:`Flowchart.item_types` records the ``xsi:type`` of each list item in file order, so the
  list is written back in the same interleaving; the canvas fields (``name``, ``size``,
  ``grid_size``, ``back_color_text``) do not exist in this form and are not written.

:func:`dump_older_flowchart` writes a chart read from this form back byte for byte.
:func:`to_older_form` turns a ``CanvasData`` chart into this form (boxes first, then arrows, as
the files of that era hold them; each arrow keeps its first and last point and its ``True`` /
``False`` branch mark).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import replace
from typing import Final

from rcb4hv.hth4._xml import (
    XSI_FIRST_LAYOUT,
    XSI_TYPE,
    ExtraElement,
    XmlLayout,
    XmlNode,
    XmlReader,
    parse_document,
    root_reader,
    serialize,
)
from rcb4hv.hth4._xmlbuild import Builder
from rcb4hv.hth4.flowchart_model import (
    Flowchart,
    FlowchartActivity,
    FlowchartLine,
    read_activity,
    read_point,
    write_activity,
    write_point,
)

__all__ = [
    "OLDER_ROOT",
    "dump_older_flowchart",
    "parse_older_flowchart",
    "read_older_flowchart",
    "to_older_form",
]

OLDER_ROOT: Final = "ArrayOfAnyType"
ACTIVITY: Final = "ActivityData"
LINE: Final = "LineData"
BRANCH_MARKS: Final = frozenset({"True", "False"})
"""The arrow modes that mark a compare box's branches; kept as the older form's ``LineType``."""

_NO_PRIORITY: Final = XmlNode(
    "PriorityList", children=(XmlNode("anyType", ((XSI_TYPE, "xsd:string"),), "00 00 00 00"),)
)
"""``PriorityList`` as the files of that era hold it for every box (meaning not known)."""


def _read_line(x: XmlReader) -> FlowchartLine:
    x.xsi_type(LINE)
    start, end = read_point(x.child("StartPoint")), read_point(x.child("EndPoint"))
    return FlowchartLine(
        guid=x.opt_str_of("GUID"), path=(start, end), connect_mode=x.str_of("LineType")
    )


def parse_older_flowchart(data: bytes | str) -> Flowchart:
    """Parse an ``ArrayOfAnyType`` flowchart (Hth4FormatError if it is not one)."""
    return read_older_flowchart(*parse_document(data, OLDER_ROOT, XSI_FIRST_LAYOUT))


def read_older_flowchart(root: ET.Element, layout: XmlLayout) -> Flowchart:
    """The chart of a parsed ``ArrayOfAnyType`` document."""
    r = root_reader(root)
    kinds: list[str] = []
    acts: list[FlowchartActivity] = []
    lines: list[FlowchartLine] = []
    for item in r.items("anyType"):
        kind = item.el.get(XSI_TYPE)
        if kind == ACTIVITY:
            acts.append(read_activity(item))
        elif kind == LINE:
            lines.append(_read_line(item))
        else:
            raise item.error(f'expected xsi:type="{ACTIVITY}" or "{LINE}", found {kind!r}')
        kinds.append(kind)
    extras: list[ExtraElement] = []
    r.close(extras)
    return Flowchart(
        name=None,
        lines=tuple(lines),
        activities=tuple(acts),
        back_color_text=None,
        extra=tuple(extras),
        layout=layout,
        item_types=tuple(kinds),
    )


def dump_older_flowchart(chart: Flowchart) -> bytes:
    """The ``ArrayOfAnyType`` file contents of ``chart`` (ValueError if it cannot be one)."""
    kinds = chart.item_types
    if kinds is None:
        raise ValueError("not an older-form chart (item_types is None); see to_older_form")
    if kinds.count(ACTIVITY) != len(chart.activities) or kinds.count(LINE) != len(chart.lines):
        raise ValueError("item_types does not match the chart's boxes and arrows")
    if len(kinds) != len(chart.activities) + len(chart.lines):
        raise ValueError(f"item_types holds a type other than {ACTIVITY} / {LINE}")
    b = Builder(OLDER_ROOT, "")
    acts, lines = iter(chart.activities), iter(chart.lines)
    for kind in kinds:
        x = b.item("anyType", kind)
        if kind == ACTIVITY:
            write_activity(x, next(acts))
            continue
        line = next(lines)
        if len(line.path) != 2:
            raise ValueError(
                f"arrow {line.guid}: the older form holds 2 points, not {len(line.path)}"
            )
        write_point(x.child("StartPoint"), line.path[0])
        write_point(x.child("EndPoint"), line.path[1])
        x.opt_leaf("GUID", line.guid)
        x.leaf("LineType", line.connect_mode)
    return serialize(b.to_node(chart.extra), chart.layout)


def to_older_form(chart: Flowchart, line_type: str = "Straight") -> Flowchart:
    """``chart`` as the older form: boxes then arrows, each box with the era's
    ``PriorityList``/``Path`` and no Text/BackColorText/Hint, each arrow from its first to its
    last point with ``LineType`` ``line_type`` (a compare box's ``True`` / ``False`` arrows keep
    that mark: it says which arrow branches), ``xsi`` declared before ``xsd`` as those files
    do. Extras of the ``CanvasData`` form are dropped."""
    if chart.item_types is not None:
        return chart
    acts = tuple(replace(a, text=None, back_color_text=None, hint=None) for a in chart.activities)
    for line in chart.lines:
        if not line.path:
            raise ValueError(f"arrow {line.guid}: no points to keep")
    lines = tuple(
        FlowchartLine(
            line.guid,
            (line.path[0], line.path[-1]),
            line.connect_mode if line.connect_mode in BRANCH_MARKS else line_type,
        )
        for line in chart.lines
    )
    extras: list[ExtraElement] = []
    for k in range(1, len(acts) + 1):
        extras.append(ExtraElement(f"anyType[{k}]", 5, _NO_PRIORITY))
        extras.append(ExtraElement(f"anyType[{k}]", 9, XmlNode("Path")))
    for k in range(len(acts) + 1, len(acts) + len(lines) + 1):
        extras.append(ExtraElement(f"anyType[{k}]", 0, XmlNode("Name")))
    return Flowchart(
        name=None,
        lines=lines,
        activities=acts,
        back_color_text=None,
        extra=tuple(extras),
        layout=replace(chart.layout, namespaces=XSI_FIRST_LAYOUT.namespaces),
        item_types=(ACTIVITY,) * len(acts) + (LINE,) * len(lines),
    )
