"""Building a HeartToHeart4 document: :class:`Builder` makes the element tree a file type's
writer fills in (with the same relative paths as :class:`~rcb4hv.hth4._xml.XmlReader`, so an
error names the element), and :func:`~rcb4hv.hth4._xml.serialize` writes it in the
XmlSerializer format (:mod:`rcb4hv.hth4._xml`)."""

from __future__ import annotations

from collections.abc import Iterable
from decimal import Decimal

from rcb4hv.hth4._xml import (
    INT32_MAX,
    INT32_MIN,
    XSI_TYPE,
    ExtraElement,
    XmlNode,
    check_xml_text,
)

__all__ = ["Builder", "format_hex", "format_int"]


def format_hex(frame: bytes) -> str:
    if not frame:
        raise ValueError("a frame must not be empty")
    return " ".join(f"{b:02X}" for b in frame)


class Builder:
    """An element being written, with the same relative path scheme as :class:`XmlReader`."""

    def __init__(self, tag: str, rel: str, attrib: tuple[tuple[str, str], ...] = ()) -> None:
        self.tag = tag
        self.rel = rel
        self.attrib = attrib
        self.text = ""
        self.children: list[Builder | XmlNode] = []
        self._counts: dict[str, int] = {}

    def _add(self, tag: str, step: str, attrib: tuple[tuple[str, str], ...]) -> Builder:
        rel = f"{self.rel}/{step}" if self.rel else step
        sub = Builder(tag, rel, attrib)
        self.children.append(sub)
        return sub

    def child(self, tag: str, xsi_type: str | None = None) -> Builder:
        attrib = ((XSI_TYPE, xsi_type),) if xsi_type is not None else ()
        return self._add(tag, tag, attrib)

    def item(self, tag: str, xsi_type: str | None = None) -> Builder:
        n = self._counts.get(tag, 0) + 1
        self._counts[tag] = n
        attrib = ((XSI_TYPE, xsi_type),) if xsi_type is not None else ()
        return self._add(tag, f"{tag}[{n}]", attrib)

    def leaf(self, tag: str, text: str, xsi_type: str | None = None) -> Builder:
        sub = self.child(tag, xsi_type)
        sub.text = check_xml_text(text, f"{self.rel}/{tag}")
        return sub

    def opt_leaf(self, tag: str, text: str | None) -> None:
        if text is not None:
            self.leaf(tag, text)

    def int_leaf(self, tag: str, value: int, lo: int = INT32_MIN, hi: int = INT32_MAX) -> None:
        self.leaf(tag, format_int(value, lo, hi, f"{self.rel}/{tag}"))

    def decimal_leaf(self, tag: str, value: Decimal) -> None:
        if not value.is_finite():
            raise ValueError(f"{self.rel}/{tag}: {value} is not a finite decimal")
        self.leaf(tag, format(value, "f"))

    def bytes_leaf(self, tag: str, data: bytes) -> None:
        sub = self.child(tag)
        for b in data:
            sub.item("unsignedByte").text = str(b)

    def hex_frames(self, frames: Iterable[bytes]) -> None:
        for frame in frames:
            self.item("anyType", "xsd:string").text = format_hex(frame)

    def raw(self, nodes: Iterable[XmlNode]) -> None:
        self.children.extend(nodes)

    # -- finishing -------------------------------------------------------------------------

    def _index(self, table: dict[str, Builder]) -> None:
        table.setdefault(self.rel, self)
        for c in self.children:
            if isinstance(c, Builder):
                c._index(table)

    def to_node(self, extras: Iterable[ExtraElement] = ()) -> XmlNode:
        """Freeze into an :class:`XmlNode`, inserting ``extras`` at their recorded places."""
        table: dict[str, Builder] = {}
        self._index(table)
        for extra in sorted(extras, key=lambda e: e.position):
            parent = extra.parent
            while parent not in table:
                parent = parent.rsplit("/", 1)[0] if "/" in parent else ""
            target = table[parent]
            pos = min(extra.position, len(target.children))
            target.children.insert(pos, extra.node)
        return self._freeze()

    def _freeze(self) -> XmlNode:
        return XmlNode(
            tag=self.tag,
            attrib=self.attrib,
            text=self.text,
            children=tuple(c._freeze() if isinstance(c, Builder) else c for c in self.children),
        )


def format_int(value: int, lo: int, hi: int, path: str) -> str:
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"{path}: expected an int, got {type(value).__name__}")
    if not lo <= value <= hi:
        raise ValueError(f"{path}: {value} out of range {lo}..{hi}")
    return str(value)
