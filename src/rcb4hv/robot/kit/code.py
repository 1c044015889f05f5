"""Kondo KXR kit codes: ``Hello_KXR-L2W2L6A4H2`` -> family and options.

The grammar (KXR-KITS.md §1.1, from kxreus's ``kxr-document.txt`` and its eusview catalogue):
``KXR`` + body (``L2`` biped, ``L4D``/``L4N``/``L4R``/``L4T`` four legs, ``L6`` six legs,
``R4LL`` wheel-legged) + options: ``L5``/``L6``/``L2`` axes per leg (biped), ``A3``-``A7`` axes
per arm, ``H``/``H2`` head axes (``H4``: the L4N's four-axis neck), ``G`` grippers, ``W2`` a
wheel on each foot, ``T1`` a waist axis, trailing ``N``/``W`` narrow/wide hips, ``M`` the
magnet-modular frame, ``2`` the L4R's two arms (``L4R2A3G``). A code without a body
(``kxra6g``) is an upper body on short legs. Case does not matter.

One grammar (:data:`_OPTIONS`), read two ways:

* a project title wraps the code (``Hello_`` before, ``(V1.0)`` after) and Kondo's titles are
  loose (``Hello_KXR-L4T(V1.1)-l4th``, ``Hello_kxrl4tm``): read leniently, the code ends at the
  first character no option reads and a later option overrides an earlier one;
* a code the user types (``--robot kxr:CODE``, ``robot show kxr:CODE``) is read strictly
  (``strict=True``): every character is part of the code, each option is given at most once
  with a value the family takes, or :class:`~rcb4hv.errors.RobotModelError` says which part
  is wrong (``kxr:L2L9A3`` is no L2L5A3).
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal, overload

from rcb4hv.errors import RobotModelError

__all__ = ["FAMILIES", "Family", "KitCode", "parse_kit_code"]

Family = Literal["humanoid", "L4D", "L4N", "L4R", "L4T", "L6", "R4LL"]
FAMILIES: tuple[Family, ...] = ("humanoid", "L4D", "L4N", "L4R", "L4T", "L6", "R4LL")
Width = Literal["standard", "narrow", "wide"]

_TITLE = re.compile(r"KXR[-_ ]?([A-Z0-9]+)")
_NAME = re.compile(r"KXR[-_: ]?(.*)", re.S)  # a typed code: nothing before KXR
_BODY = re.compile(r"(R4LL|L4[DNRT]|L2|L6)")
_BODIES = "L2, L4D, L4N, L4R, L4T, L6 or R4LL"


@dataclass(frozen=True)
class _Option:
    """One option of the grammar: ``letter`` + digits (``""``: none), what it sets."""

    key: str  # the KitCode field it sets (``frame``, ``pair``: none); given at most once
    letter: str
    loose: str  # what a title's reading takes (a regex; wider than the valid values)
    takes: Mapping[Family, tuple[str, ...]]  # per family, the digits it may carry
    says: str


_HEADS = ("", "1", "2")  # H alone: 2 axes (yaw, pitch)
_OPTIONS: tuple[_Option, ...] = (
    _Option("wheels", "W", "W2", {"humanoid": ("2",)}, "a wheel on each foot"),
    _Option("legs", "L", "L[2456]", {"humanoid": ("2", "4", "5", "6")}, "axes per leg"),
    _Option("arms", "A", "A[1-9]", {"humanoid": ("3", "4", "5", "6", "7"), "L4R": ("3",)},
            "axes per arm"),
    _Option("head", "H", "H[0-9]?", {"humanoid": _HEADS, "L4T": _HEADS, "L4R": _HEADS,
                                     "L4N": (*_HEADS, "3", "4")}, "head axes, H alone 2"),
    _Option("gripper", "G", "G", {"humanoid": ("",), "L4R": ("",)}, "grippers"),
    _Option("waist", "T", "T1", {"humanoid": ("1",)}, "a waist axis"),
    _Option("width", "N", "N", {"humanoid": ("",)}, "narrow hips"),
    _Option("width", "W", "W", {"humanoid": ("",)}, "wide hips"),
    _Option("frame", "M", "M", {"humanoid": ("",), "L4T": ("",)}, "the magnet-modular frame"),
    _Option("pair", "", "2", {"L4R": ("2",)}, "two arms in front"),
)  # fmt: skip
_LOOSE = re.compile("|".join(f"(?P<o{i}>{o.loose})" for i, o in enumerate(_OPTIONS)) + "|[0-9]")
_TOKEN = re.compile(r"[A-Z][0-9]*|[0-9]+")


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
    width: Width = "standard"
    unknown: tuple[str, ...] = field(default=())

    @property
    def name(self) -> str:
        """The model name for this code: ``kxr:`` + the code (``kxr:L2W2L6A4H2``)."""
        return "kxr:" + self.code


def _set(values: dict[str, Any], option: _Option, digits: str) -> None:
    """Record what ``option`` with ``digits`` says (KitCode field -> value)."""
    if option.key in ("legs", "arms"):
        values[option.key] = int(digits)
    elif option.key == "head":
        values["head"] = int(digits) if digits else 2
    elif option.key == "width":
        values["width"] = "narrow" if option.letter == "N" else "wide"
    elif option.key in ("wheels", "gripper", "waist"):
        values[option.key] = True
    # frame (the magnet-modular frame) and pair (the L4R2's arms): the same joints


def _forms(options: list[_Option], family: Family) -> str:
    """What ``options`` (one letter) take for ``family``: ``L2, L4, L5 or L6 (axes per leg)``."""
    out = []
    for o in options:
        forms = [o.letter + d for d in o.takes[family]]
        text = ", ".join(forms[:-1]) + " or " + forms[-1] if len(forms) > 1 else forms[0]
        out.append(f"{text} ({o.says})")
    return " or ".join(out)


def _taken(family: Family) -> str:
    forms = sorted({o.letter or o.loose for o in _OPTIONS if family in o.takes})
    return f"it takes {', '.join(forms)}" if forms else "it takes no options"


def _strict(raw: str, family: Family, rest: str) -> dict[str, Any]:
    """The options of ``rest`` (after the body of ``raw``), every character read, or
    :class:`RobotModelError` naming the part that is wrong."""
    what = "an upper body on short legs" if family == "humanoid" and raw == rest else (
        "a humanoid" if family == "humanoid" else f"a KXR-{family}"
    )  # fmt: skip
    values: dict[str, Any] = {}
    given: dict[str, str] = {}
    for tok in _TOKEN.findall(rest):
        letter = tok[0] if tok[0].isalpha() else ""
        digits = tok[len(letter) :]
        named = [o for o in _OPTIONS if o.letter == letter and (letter or o.loose == digits)]
        mine = [o for o in named if family in o.takes]
        if not named:
            raise RobotModelError(f"{tok}: not a kit option ({what}: {_taken(family)})")
        if not mine:
            raise RobotModelError(f"{tok}: {what} takes no {named[0].says} ({_taken(family)})")
        option = next((o for o in mine if digits in o.takes[family]), None)
        if option is None:
            raise RobotModelError(f"{tok}: {what} takes {_forms(mine, family)}")
        if option.key in given:
            raise RobotModelError(f"{tok}: {option.key} given twice ({given[option.key]}, {tok})")
        given[option.key] = tok
        _set(values, option, digits)
    return values


@overload
def parse_kit_code(text: str | None, *, strict: Literal[False] = False) -> KitCode | None: ...
@overload
def parse_kit_code(text: str | None, *, strict: Literal[True]) -> KitCode: ...
@overload
def parse_kit_code(text: str | None, *, strict: bool) -> KitCode | None: ...
def parse_kit_code(text: str | None, *, strict: bool = False) -> KitCode | None:
    """The kit code in a project title or a ``kxr:CODE`` name, or None when there is none.

    ``strict``: ``text`` is a code as a user types it (``kxr:L2W2L6A4H2``): all of it is the
    code, or :class:`~rcb4hv.errors.RobotModelError` says which part is wrong (never None)."""
    up = unicodedata.normalize("NFKC", text or "").upper()
    if up.startswith("KXR:"):
        up = "KXR-" + up[4:]
    if strict:
        whole = _NAME.fullmatch(up.strip())
        raw = whole.group(1) if whole else ""
        bad = re.search(r"[^A-Z0-9]", raw)
        if whole is None or not raw or bad is not None:
            where = f"{raw[bad.start() :]!r} after {raw[: bad.start()] or 'KXR'}" if bad else ""
            raise RobotModelError(
                f"{text}: not a KXR kit code ({where + ': ' if where else ''}expected kxr: + "
                f"the body {_BODIES} + options, letters and digits only, e.g. kxr:L2W2L6A4H2)"
            )
    else:
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
        if strict:
            raise RobotModelError(
                f"{text}: not a KXR kit code (it starts with the body {_BODIES}, or with the "
                "arms of an upper body on short legs, A6G)"
            )
        return None
    unknown: list[str] = []
    if strict:
        try:
            values = _strict(raw, family, rest)
        except RobotModelError as exc:
            raise RobotModelError(f"{text}: not a valid KXR-{raw} kit code: {exc}") from None
    else:
        values = {}
        pos = 0
        while pos < len(rest):
            t = _LOOSE.match(rest, pos)
            if t is None:
                unknown.append(rest[pos:])
                break
            pos = t.end()
            if t.lastgroup is None:
                unknown.append(t.group(0))  # a stray digit
            else:
                _set(values, _OPTIONS[int(t.lastgroup[1:])], t.group(0)[1:])
    if family == "humanoid" and body is None:
        values.setdefault("legs", 2)  # an upper body on the short (2-axis) legs
    return replace(KitCode(family, raw, unknown=tuple(unknown)), **values)
