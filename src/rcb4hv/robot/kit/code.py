"""Kondo KXR kit codes: ``Hello_KXR-L2W2L6A4H2`` -> family and options.

The grammar (KXR-KITS.md §1.1, from kxreus's ``kxr-document.txt`` and its eusview catalogue):
``KXR`` + body (``L2`` biped, ``L4D``/``L4N``/``L4R``/``L4T`` four legs, ``L6`` six legs,
``R4LL`` wheel-legged) + options: ``L5``/``L6``/``L2`` axes per leg (biped), ``A3``-``A7`` axes
per arm, ``H``/``H2`` head axes (``H4``: the L4N's four-axis neck), ``G`` grippers, ``W2`` a
wheel on each foot, ``T1`` a waist axis, trailing ``N``/``W`` narrow/wide hips, ``M`` the
magnet-modular frame. A code without a body (``kxra6g``) is an upper body on short legs.
Case does not matter; a project title wraps the code (``Hello_`` before, ``(V1.0)`` after).
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass, field
from typing import Literal

__all__ = ["FAMILIES", "Family", "KitCode", "parse_kit_code"]

Family = Literal["humanoid", "L4D", "L4N", "L4R", "L4T", "L6", "R4LL"]
FAMILIES: tuple[Family, ...] = ("humanoid", "L4D", "L4N", "L4R", "L4T", "L6", "R4LL")

_TITLE = re.compile(r"KXR[-_ ]?([A-Z0-9]+)")
_BODY = re.compile(r"(R4LL|L4[DNRT]|L2|L6)")
_OPTION = re.compile(r"W2|L[2456]|A[1-9]|H[0-9]?|G|T1|N|W|M|[0-9]")


@dataclass(frozen=True)
class KitCode:
    """A parsed kit code. ``None`` means the code does not say (the servo names decide)."""

    family: Family
    code: str
    legs: int | None = None
    arms: int | None = None
    head: int | None = None
    gripper: bool = False
    wheels: bool = False
    waist: bool = False
    width: Literal["standard", "narrow", "wide"] = "standard"
    unknown: tuple[str, ...] = field(default=())

    @property
    def name(self) -> str:
        """The model name for this code: ``kxr:`` + the code (``kxr:L2W2L6A4H2``)."""
        return "kxr:" + self.code


def parse_kit_code(text: str | None) -> KitCode | None:
    """The kit code in a project title or a ``kxr:CODE`` name, or None when there is none."""
    if not text:
        return None
    up = unicodedata.normalize("NFKC", text).upper()
    if up.startswith("KXR:"):
        up = "KXR-" + up[4:]
    m = _TITLE.search(up)
    if m is None:
        return None
    raw = m.group(1)
    body = _BODY.match(raw)
    family: Family = "humanoid"
    rest = raw
    if body is not None:
        tag = body.group(1)
        family = "humanoid" if tag == "L2" else "L6" if tag == "L6" else tag  # type: ignore[assignment]
        rest = raw[body.end() :]
    elif not raw.startswith("A"):
        return None
    legs = arms = head = None
    gripper = wheels = waist = False
    width: Literal["standard", "narrow", "wide"] = "standard"
    unknown: list[str] = []
    pos = 0
    while pos < len(rest):
        t = _OPTION.match(rest, pos)
        if t is None:
            unknown.append(rest[pos:])
            break
        tok = t.group(0)
        pos = t.end()
        if tok == "W2":
            wheels = True
        elif tok[0] == "L":
            legs = int(tok[1])
        elif tok[0] == "A":
            arms = int(tok[1])
        elif tok[0] == "H":
            head = int(tok[1:]) if len(tok) > 1 else 2
        elif tok == "G":
            gripper = True
        elif tok == "T1":
            waist = True
        elif tok == "N":
            width = "narrow"
        elif tok == "W":
            width = "wide"
        elif tok == "M":
            pass  # the magnet-modular frame: same joints
        else:
            unknown.append(tok)
    if family == "humanoid" and body is None:
        legs = 2 if legs is None else legs  # an upper body on the short (2-axis) legs
    return KitCode(
        family=family,
        code=raw,
        legs=legs,
        arms=arms,
        head=head,
        gripper=gripper,
        wheels=wheels,
        waist=waist,
        width=width,
        unknown=tuple(unknown),
    )
