"""XmlSerializer-style XML reading and writing shared by every HeartToHeart4 file type.

HeartToHeart4 is a .NET program that writes its files with ``System.Xml.Serialization.
XmlSerializer``. The output of that serializer is regular:

* declaration ``<?xml version="1.0"?>`` (no encoding attribute), UTF-8 without BOM,
  CRLF line ends, no newline after the closing root tag;
* the root element declares ``xmlns:xsd`` and ``xmlns:xsi`` (the order differs between file
  types: projects write ``xsd`` first, flowcharts and trims ``xsi`` first);
* two-space indentation, one element per line, no mixed content;
* an empty string or empty list is written as ``<Tag />``, a ``null`` reference is omitted;
* polymorphic members carry ``xsi:type`` (``<Key xsi:type="xsd:string">``).

This module reproduces that format byte for byte. :class:`XmlLayout` records the few
formatting choices that vary between files (namespace order, line end, BOM, declaration), so a
file read and written again keeps them.

Reading goes through :class:`XmlReader`, which remembers the element path (for error messages
such as ``Rcb4/MotionDataCollection/DictionaryEntry[3]/Value/Number: not an integer``) and
which children were consumed. Children the model does not know are kept as
:class:`ExtraElement` (parent path, position, raw :class:`XmlNode`) and written back at the
same place, so a foreign-but-valid file round trips. Comments and processing instructions
inside the document are not kept (xml.etree drops them).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation

from rcb4hv.errors import Hth4FormatError

__all__ = [
    "XSD",
    "XSI",
    "XSI_TYPE",
    "ExtraElement",
    "XmlLayout",
    "XmlNode",
    "XmlReader",
]

XSI = "http://www.w3.org/2001/XMLSchema-instance"
XSD = "http://www.w3.org/2001/XMLSchema"
XSI_TYPE = f"{{{XSI}}}type"

INT32_MIN = -(2**31)
INT32_MAX = 2**31 - 1


# ---------------------------------------------------------------------------------------------
# Raw nodes, extras and layout


@dataclass(frozen=True)
class XmlNode:
    """An XML element kept verbatim (tag and attribute names in ``{uri}local`` notation)."""

    tag: str
    attrib: tuple[tuple[str, str], ...] = ()
    text: str = ""
    children: tuple[XmlNode, ...] = ()

    @classmethod
    def from_element(cls, el: ET.Element, path: str) -> XmlNode:
        """Convert an ElementTree element; mixed content raises :class:`Hth4FormatError`."""
        kids = list(el)
        text = el.text or ""
        if kids and text.strip():
            raise Hth4FormatError(path, "mixed text and element content is not supported")
        children = []
        for i, kid in enumerate(kids, 1):
            if kid.tail and kid.tail.strip():
                raise Hth4FormatError(path, f"text after child element {i} is not supported")
            children.append(cls.from_element(kid, f"{path}/{_local(kid.tag)}"))
        return cls(
            tag=str(el.tag),
            attrib=tuple((str(k), str(v)) for k, v in el.attrib.items()),
            text="" if kids else text,
            children=tuple(children),
        )

    def to_xml(self) -> str:
        """This element alone as XmlSerializer-style text (LF line ends, no declaration)."""
        return "\n".join(_write_node(self, 0, {XSI: "xsi", XSD: "xsd"}, declare_all=True))


@dataclass(frozen=True)
class ExtraElement:
    """An element the model does not know, kept to be written back.

    ``parent`` is the path of its parent element below the root ("" = the root itself,
    ``Kri3``, ``MotionDataCollection/DictionaryEntry[3]/Value``); ``position`` its index among
    the parent's children in the file read.
    """

    parent: str
    position: int
    node: XmlNode


@dataclass(frozen=True)
class XmlLayout:
    """Formatting details of an XML file that carry no data but vary between files."""

    namespaces: tuple[tuple[str, str], ...] = (("xsd", XSD), ("xsi", XSI))
    newline: str = "\r\n"
    declaration: str = '<?xml version="1.0"?>'
    bom: bool = False
    final_newline: bool = False


PROJECT_LAYOUT = XmlLayout()
"""Layout of a HeartToHeart4 2.x project (``.h4p``): ``xsd`` declared before ``xsi``."""

XSI_FIRST_LAYOUT = XmlLayout(namespaces=(("xsi", XSI), ("xsd", XSD)))
"""Layout of flowcharts (``.xml``) and trims (``.h4t``): ``xsi`` declared before ``xsd``."""


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


# ---------------------------------------------------------------------------------------------
# Parsing


_DECL_RE = re.compile(r"<\?xml\s[^?]*\?>")
_ENCODING_RE = re.compile(r"""encoding\s*=\s*["']([^"']*)["']""")
_ROOT_RE = re.compile(r"<(?![?!])[^\s/>]+(\s[^>]*)?>")
_XMLNS_RE = re.compile(r"""xmlns:([\w.-]+)\s*=\s*["']([^"']*)["']""")


def _detect_layout(data: bytes, default: XmlLayout) -> XmlLayout:
    bom = data.startswith(b"\xef\xbb\xbf")
    text = data[3:] if bom else data
    try:
        head = text[:8192].decode("utf-8", errors="strict")
    except UnicodeDecodeError:
        head = text[:8192].decode("utf-8", errors="replace")
    newline = "\r\n" if "\r\n" in head else ("\n" if "\n" in head else default.newline)
    declaration = default.declaration
    m = _DECL_RE.match(head)
    if m is not None:
        enc = _ENCODING_RE.search(m.group(0))
        if enc is None or enc.group(1).lower().replace("_", "-") in ("utf-8", "utf8"):
            declaration = m.group(0)
    elif not head.lstrip().startswith("<?xml"):
        declaration = ""
    namespaces = default.namespaces
    body = head[m.end() :] if m is not None else head
    root = _ROOT_RE.search(re.sub(r"<!--.*?-->", "", body, flags=re.S))
    if root is not None:
        found = tuple((p, u) for p, u in _XMLNS_RE.findall(root.group(0)))
        namespaces = found
    final_newline = text.endswith(b"\n")
    return XmlLayout(
        namespaces=namespaces,
        newline=newline,
        declaration=declaration,
        bom=bom,
        final_newline=final_newline,
    )


def parse_document(
    data: bytes | str, root_tag: str | tuple[str, ...], default: XmlLayout
) -> tuple[ET.Element, XmlLayout]:
    """Parse XML text; check the root tag (one of ``root_tag`` when a tuple). Returns the root
    element and the layout."""
    raw = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    if isinstance(data, str):
        # A str carries no BOM bytes; an encoding declaration would contradict the str.
        raw = _DECL_RE.sub('<?xml version="1.0"?>', data, count=1).encode("utf-8")
    try:
        root = ET.fromstring(raw)
    except ET.ParseError as exc:
        raise Hth4FormatError("", f"not well-formed XML ({exc})") from None
    tags = (root_tag,) if isinstance(root_tag, str) else root_tag
    if root.tag not in tags:
        wanted = " or ".join(f"<{t}>" for t in tags)
        raise Hth4FormatError(_local(str(root.tag)), f"wrong root element: expected {wanted}")
    return root, _detect_layout(raw, default)


class XmlReader:
    """Cursor over one element that records the path and what was consumed."""

    def __init__(self, el: ET.Element, path: str, rel: str) -> None:
        self.el = el
        self.path = path  # full path for messages (root included)
        self.rel = rel  # path below the root, for extras
        self._kids = list(el)
        self._used: set[int] = set()
        self._attr_used: set[str] = set()
        self._subs: list[XmlReader] = []

    # -- children -------------------------------------------------------------------------

    def _sub(self, index: int, step: str) -> XmlReader:
        self._used.add(index)
        rel = f"{self.rel}/{step}" if self.rel else step
        sub = XmlReader(self._kids[index], f"{self.path}/{step}", rel)
        self._subs.append(sub)
        return sub

    def opt_child(self, tag: str) -> XmlReader | None:
        for i, kid in enumerate(self._kids):
            if kid.tag == tag and i not in self._used:
                return self._sub(i, tag)
        return None

    def child(self, tag: str) -> XmlReader:
        sub = self.opt_child(tag)
        if sub is None:
            raise Hth4FormatError(f"{self.path}/{tag}", "missing element")
        return sub

    def items(self, tag: str, xsi_type: str | None = None) -> list[XmlReader]:
        """All children named ``tag`` (with that ``xsi:type`` if given), paths ``tag[k]``."""
        out = []
        count = 0
        for i, kid in enumerate(self._kids):
            if kid.tag != tag:
                continue
            count += 1
            if i in self._used:
                continue
            if xsi_type is not None and kid.get(XSI_TYPE) != xsi_type:
                continue
            out.append(self._sub(i, f"{tag}[{count}]"))
        return out

    # -- attributes and text ----------------------------------------------------------------

    def xsi_type(self, expected: str) -> None:
        got = self.el.get(XSI_TYPE)
        if got != expected:
            raise Hth4FormatError(self.path, f'expected xsi:type="{expected}", found {got!r}')
        self._attr_used.add(XSI_TYPE)

    def text(self) -> str:
        if self._kids:
            raise Hth4FormatError(self.path, "expected text, found child elements")
        return self.el.text or ""

    def error(self, message: str) -> Hth4FormatError:
        return Hth4FormatError(self.path, message)

    # -- typed leaves ----------------------------------------------------------------------

    def str_of(self, tag: str) -> str:
        return self.child(tag).text()

    def opt_str_of(self, tag: str) -> str | None:
        sub = self.opt_child(tag)
        return None if sub is None else sub.text()

    def int_of(self, tag: str, lo: int = INT32_MIN, hi: int = INT32_MAX) -> int:
        return self.child(tag).as_int(lo, hi)

    def as_int(self, lo: int = INT32_MIN, hi: int = INT32_MAX) -> int:
        text = self.text().strip()
        if not re.fullmatch(r"[+-]?[0-9]+", text):
            raise self.error(f"not an integer: {text!r}")
        value = int(text)
        if not lo <= value <= hi:
            raise self.error(f"{value} out of range {lo}..{hi}")
        return value

    def decimal_of(self, tag: str) -> Decimal:
        sub = self.child(tag)
        text = sub.text().strip()
        if not re.fullmatch(r"[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)", text):
            raise sub.error(f"not a decimal number: {text!r}")
        try:
            return Decimal(text)
        except InvalidOperation:  # pragma: no cover - the regex already guards this
            raise sub.error(f"not a decimal number: {text!r}") from None

    def bytes_of(self, tag: str) -> bytes:
        """A ``byte[]`` / ``List<byte>`` written as ``<unsignedByte>`` children."""
        sub = self.child(tag)
        return bytes(item.as_int(0, 255) for item in sub.items("unsignedByte"))

    def hex_frames(self) -> tuple[bytes, ...]:
        """Children ``<anyType xsi:type="xsd:string">13 12 00 …</anyType>`` as bytes."""
        frames = []
        for item in self.items("anyType"):
            item.xsi_type("xsd:string")
            frames.append(parse_hex(item.text(), item.path))
        return tuple(frames)

    # -- closing ---------------------------------------------------------------------------

    def close(self, extras: list[ExtraElement]) -> None:
        """Check attributes/content of everything read; collect unread children as extras."""
        for name in self.el.attrib:
            if name not in self._attr_used:
                raise Hth4FormatError(self.path, f"unexpected attribute {name!r}")
        if self._used and (self.el.text or "").strip():
            raise Hth4FormatError(self.path, "mixed text and element content is not supported")
        for i, kid in enumerate(self._kids):
            if kid.tail and kid.tail.strip():
                raise Hth4FormatError(self.path, "text between child elements is not supported")
            if i not in self._used:
                node = XmlNode.from_element(kid, f"{self.path}/{_local(str(kid.tag))}")
                extras.append(ExtraElement(self.rel, i, node))
        for sub in self._subs:
            sub.close(extras)


def root_reader(root: ET.Element) -> XmlReader:
    return XmlReader(root, _local(str(root.tag)), "")


_HEX_RE = re.compile(r"[0-9A-Fa-f]{2}( [0-9A-Fa-f]{2})*")


def parse_hex(text: str, path: str) -> bytes:
    """``"13 12 00 FF"`` → bytes; anything else raises :class:`Hth4FormatError`."""
    if not _HEX_RE.fullmatch(text):
        shown = text if len(text) <= 40 else text[:37] + "..."
        raise Hth4FormatError(path, f"not a hex byte string: {shown!r}")
    return bytes.fromhex(text)


def _is_xml_char(c: str) -> bool:
    o = ord(c)
    return (
        o in (0x9, 0xA, 0xD)
        or 0x20 <= o <= 0xD7FF
        or 0xE000 <= o <= 0xFFFD
        or 0x10000 <= o <= 0x10FFFF
    )


def is_xml_text(text: str) -> bool:
    """True if every character may appear in an XML 1.0 document."""
    return all(_is_xml_char(c) for c in text)


def check_xml_text(text: str, path: str) -> str:
    if not isinstance(text, str):
        raise ValueError(f"{path}: expected a str, got {type(text).__name__}")
    if not is_xml_text(text):
        raise ValueError(f"{path}: text contains a character XML 1.0 cannot represent")
    return text


# ---------------------------------------------------------------------------------------------
# Serializing


def _escape_text(text: str) -> str:
    return (
        text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace("\r", "&#xD;")
    )


def _escape_attr(text: str) -> str:
    return _escape_text(text).replace('"', "&quot;").replace("\n", "&#xA;").replace("\t", "&#x9;")


def _uris(node: XmlNode) -> Iterator[str]:
    names = [node.tag, *(k for k, _ in node.attrib)]
    for name in names:
        if name.startswith("{"):
            yield name[1:].split("}", 1)[0]


def _write_node(
    node: XmlNode, depth: int, scope: dict[str, str], declare_all: bool = False
) -> list[str]:
    decls: list[tuple[str, str]] = []
    if declare_all:
        decls = [(p, u) for u, p in scope.items() if any(True for _ in _uris_deep(node, u))]
    for uri in _uris(node):
        if uri not in scope:
            scope = dict(scope)
            prefix = f"ns{len(scope)}"
            scope[uri] = prefix
            decls.append((prefix, uri))

    def qname(name: str) -> str:
        if name.startswith("{"):
            uri, local = name[1:].split("}", 1)
            return f"{scope[uri]}:{local}"
        return name

    for k, v in node.attrib:
        check_xml_text(v, qname(k))
    check_xml_text(node.text, qname(node.tag))
    indent = "  " * depth
    name = qname(node.tag)
    start = "<" + name
    start += "".join(f' xmlns:{p}="{_escape_attr(u)}"' for p, u in decls)
    start += "".join(f' {qname(k)}="{_escape_attr(v)}"' for k, v in node.attrib)
    if node.children:
        lines = [f"{indent}{start}>"]
        for child in node.children:
            lines.extend(_write_node(child, depth + 1, scope))
        lines.append(f"{indent}</{name}>")
        return lines
    if node.text:
        return [f"{indent}{start}>{_escape_text(node.text)}</{name}>"]
    return [f"{indent}{start} />"]


def _uris_deep(node: XmlNode, uri: str) -> Iterator[None]:
    if uri in set(_uris(node)):
        yield None
    for child in node.children:
        yield from _uris_deep(child, uri)


def serialize(root: XmlNode, layout: XmlLayout) -> bytes:
    """Write a document the way XmlSerializer does (see the module docstring)."""
    scope = {uri: prefix for prefix, uri in layout.namespaces}
    if len(scope) != len(layout.namespaces) or len(set(scope.values())) != len(scope):
        raise ValueError("XmlLayout.namespaces must map distinct prefixes to distinct URIs")
    ns_attrs = tuple((f"xmlns:{p}", u) for p, u in layout.namespaces)
    # The root's own declarations go first, as XmlSerializer writes them.
    lines = _write_node(XmlNode(root.tag, (), root.text, root.children), 0, scope)
    decl = "".join(f' {k}="{_escape_attr(v)}"' for k, v in ns_attrs)
    rest = "".join(f' {_qualify(k, scope)}="{_escape_attr(v)}"' for k, v in root.attrib)
    first = lines[0]
    name_end = 1 + len(_qualify(root.tag, scope))
    lines[0] = first[:name_end] + decl + rest + first[name_end:]
    out = layout.newline.join(([layout.declaration] if layout.declaration else []) + lines)
    if layout.final_newline:
        out += layout.newline
    data = out.encode("utf-8")
    return b"\xef\xbb\xbf" + data if layout.bom else data


def _qualify(name: str, scope: dict[str, str]) -> str:
    if name.startswith("{"):
        uri, local = name[1:].split("}", 1)
        if uri not in scope:
            raise ValueError(f"namespace {uri!r} used on the root is not declared in the layout")
        return f"{scope[uri]}:{local}"
    return name
