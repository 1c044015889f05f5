"""Trim files (``.h4t``, root ``ArrayOfDictionaryEntry``).

A trim file is the servo part of a project's ``ServoConfigParams`` without the editor data:
one ``DictionaryEntry`` per ICS slot, keyed by the servo's display name, whose
``PositionData`` value holds ``Name``, ``ID`` (servo ID), ``DeviceNumber`` (ICS number),
``Trim`` (signed offset) and ``Position`` (home position). Round trip is byte-identical for
XmlSerializer output.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, replace

from rcb4hv.errors import Hth4FormatError
from rcb4hv.files import read_bytes, write_atomic
from rcb4hv.hth4._xml import (
    XSI_FIRST_LAYOUT,
    ExtraElement,
    XmlLayout,
    parse_document,
    root_reader,
    serialize,
)
from rcb4hv.hth4._xmlbuild import Builder

__all__ = ["TrimEntry", "TrimFile", "dump_trim", "load_trim", "parse_trim", "save_trim"]

ROOT = "ArrayOfDictionaryEntry"


@dataclass(frozen=True)
class TrimEntry:
    """Trim and home position of one ICS slot."""

    key: str
    name: str | None
    id: int
    device_number: int
    trim: int = 0
    position: int = 7500

    @property
    def ics_number(self) -> int:
        return self.device_number


@dataclass(frozen=True)
class TrimFile:
    """A ``.h4t`` file."""

    entries: tuple[TrimEntry, ...] = ()
    extra: tuple[ExtraElement, ...] = ()
    layout: XmlLayout = field(default=XSI_FIRST_LAYOUT)

    @property
    def by_ics(self) -> dict[int, TrimEntry]:
        return {e.device_number: e for e in self.entries}


def load_trim(path: str | os.PathLike[str]) -> TrimFile:
    """Read a ``.h4t`` file."""
    return parse_trim(read_bytes(path))


def parse_trim(data: bytes | str) -> TrimFile:
    """Parse the text of a ``.h4t`` file."""
    root, layout = parse_document(data, ROOT, XSI_FIRST_LAYOUT)
    r = root_reader(root)
    entries = []
    for e in r.items("DictionaryEntry"):
        key = e.child("Key")
        key.xsi_type("xsd:string")
        v = e.opt_child("Value")
        if v is None:
            raise Hth4FormatError(f"{e.path}/Value", "missing element")
        v.xsi_type("PositionData")
        entries.append(
            TrimEntry(
                key=key.text(),
                name=v.opt_str_of("Name"),
                id=v.int_of("ID"),
                device_number=v.int_of("DeviceNumber"),
                trim=v.int_of("Trim"),
                position=v.int_of("Position"),
            )
        )
    extras: list[ExtraElement] = []
    r.close(extras)
    trim = TrimFile(entries=tuple(entries), layout=layout)
    return replace(trim, extra=tuple(extras)) if extras else trim


def dump_trim(trim: TrimFile) -> bytes:
    """The ``.h4t`` file contents for ``trim``."""
    b = Builder(ROOT, "")
    for t in trim.entries:
        e = b.item("DictionaryEntry")
        e.leaf("Key", t.key, "xsd:string")
        v = e.child("Value", "PositionData")
        v.opt_leaf("Name", t.name)
        v.int_leaf("ID", t.id)
        v.int_leaf("DeviceNumber", t.device_number)
        v.int_leaf("Trim", t.trim)
        v.int_leaf("Position", t.position)
    return serialize(b.to_node(trim.extra), trim.layout)


def save_trim(trim: TrimFile, path: str | os.PathLike[str]) -> None:
    """Write ``trim`` to ``path``."""
    write_atomic(path, dump_trim(trim))
