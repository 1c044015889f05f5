"""Link files (``.h4l``) and any other XmlSerializer document, kept as a generic tree.

No ``.h4l`` file was available to study (the fixture project's ``LinkFileList`` is empty), so
its schema is unknown. It is XmlSerializer output like the other HeartToHeart4 files, so this
module reads it into an :class:`XmlDocument` — the root :class:`~rcb4hv.hth4._xml.XmlNode`
plus the :class:`~rcb4hv.hth4._xml.XmlLayout` — and writes it back in the same layout. For
XmlSerializer output the round trip is byte-identical; no field is interpreted.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

from rcb4hv.errors import Hth4FormatError
from rcb4hv.files import read_bytes, write_atomic
from rcb4hv.hth4._xml import (
    PROJECT_LAYOUT,
    XmlLayout,
    XmlNode,
    parse_document,
    serialize,
)

__all__ = [
    "XmlDocument",
    "dump_link",
    "dump_xml_document",
    "load_link",
    "parse_link",
    "parse_xml_document",
    "save_link",
]


@dataclass(frozen=True)
class XmlDocument:
    """A whole XML document: its root element and its formatting."""

    root: XmlNode
    layout: XmlLayout = field(default=PROJECT_LAYOUT)


def parse_xml_document(data: bytes | str, root_tag: str | None = None) -> XmlDocument:
    """Parse any XmlSerializer document; ``root_tag`` (if given) must match the root."""
    if root_tag is None:
        # Peek at the root name by parsing once; parse_document then checks nothing new.
        import xml.etree.ElementTree as ET

        raw = data.encode("utf-8") if isinstance(data, str) else data
        try:
            root_tag = str(ET.fromstring(raw).tag)
        except ET.ParseError as exc:
            raise Hth4FormatError("", f"not well-formed XML ({exc})") from None
    root, layout = parse_document(data, root_tag, PROJECT_LAYOUT)
    return XmlDocument(XmlNode.from_element(root, root_tag), layout)


def dump_xml_document(doc: XmlDocument) -> bytes:
    """Write a document in its layout."""
    return serialize(doc.root, doc.layout)


def load_link(path: str | os.PathLike[str]) -> XmlDocument:
    """Read a ``.h4l`` file as a generic XML document (see the module docstring)."""
    return parse_link(read_bytes(path))


def parse_link(data: bytes | str) -> XmlDocument:
    """Parse the text of a ``.h4l`` file as a generic XML document."""
    return parse_xml_document(data)


def dump_link(doc: XmlDocument) -> bytes:
    """The ``.h4l`` file contents for ``doc``."""
    return dump_xml_document(doc)


def save_link(doc: XmlDocument, path: str | os.PathLike[str]) -> None:
    """Write ``doc`` to ``path``."""
    write_atomic(path, dump_link(doc))
