"""The assembler's text layer: tokens, constant expressions, operands, conditions and literal
bytes of one statement (the statements are built in :mod:`rcb4hv.asm.assembler`)."""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Final

from rcb4hv.asm.symbols import RAM_SCALARS, RAM_TABLES, SERVO_FIELDS
from rcb4hv.asm.syntax import POSITION_WORDS
from rcb4hv.errors import AsmError
from rcb4hv.protocol import (
    Com,
    Condition,
    Data,
    Destination,
    Ics,
    Ram,
    Rom,
    Source,
)

# --------------------------------------------------------------------------- lexing

_TOKEN: Final = re.compile(
    r"\s*(?:(?P<num>\$[0-9A-Fa-f]+|0[xX][0-9A-Fa-f]+|0[bB][01]+|\d+)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)|(?P<punct>[\[\]().+\-]))"
)
HEX_BYTE: Final = re.compile(r"[0-9A-Fa-f]{2}")
_NAME_INDEX: Final = re.compile(r"([A-Z_]*[A-Z])(\d+)")
LABEL: Final = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*):")
MNEMONIC: Final = re.compile(r"\s*([.A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z]+)*)")
IF_WORD: Final = re.compile(r"\s+IF\s+", re.IGNORECASE)


class _Unresolved(Exception):
    """A label not known yet (first pass)."""


@dataclass(frozen=True, slots=True)
class Text:
    """A piece of a source line and the 1-based column where it starts."""

    text: str
    column: int
    line: int

    def error(self, message: str, offset: int = 0) -> AsmError:
        return AsmError(message, self.line, self.column + offset)

    def strip(self) -> Text:
        lead = len(self.text) - len(self.text.lstrip())
        return Text(self.text.strip(), self.column + lead, self.line)

    def sub(self, start: int, end: int | None = None) -> Text:
        return Text(self.text[start:end], self.column + start, self.line).strip()


def parse_number(token: str) -> int:
    if token.startswith("$"):
        return int(token[1:], 16)
    return int(token, 0) if token[:2].lower() in ("0x", "0b") else int(token, 10)


def _tokens(t: Text) -> list[tuple[str, str, int]]:
    out: list[tuple[str, str, int]] = []
    pos = 0
    text = t.text
    while pos < len(text):
        if not text[pos:].strip():
            break
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            bad = text[pos:].lstrip()
            raise t.error(f"unexpected {bad[:1]!r}", len(text) - len(bad))
        kind = m.lastgroup
        assert kind is not None
        out.append((kind, m.group(kind), m.start(kind)))
        pos = m.end()
    return out


# Contexts: "int" (plain numbers), "ram" (RAM symbols), "rom" (labels).
Labels = Mapping[str, int] | None


class _ExprParser:
    def __init__(self, t: Text, context: str, labels: Labels) -> None:
        self.t = t
        self.toks = _tokens(t)
        self.i = 0
        self.context = context
        self.labels = labels

    def peek(self) -> tuple[str, str, int] | None:
        return self.toks[self.i] if self.i < len(self.toks) else None

    def take(self, text: str | None = None) -> tuple[str, str, int]:
        tok = self.peek()
        if tok is None:
            raise self.t.error(
                f"expected {text!r} at the end" if text else "incomplete expression",
                len(self.t.text),
            )
        if text is not None and tok[1] != text:
            raise self.t.error(f"expected {text!r}, found {tok[1]!r}", tok[2])
        self.i += 1
        return tok

    def parse(self) -> int:
        if not self.toks:
            raise self.t.error("missing value")
        value = self.expr()
        tok = self.peek()
        if tok is not None:
            raise self.t.error(f"unexpected {tok[1]!r}", tok[2])
        return value

    def expr(self) -> int:
        sign = 1
        tok = self.peek()
        if tok is not None and tok[1] in "+-" and tok[0] == "punct":
            self.i += 1
            sign = -1 if tok[1] == "-" else 1
        value = sign * self.term()
        while (tok := self.peek()) is not None and tok[1] in ("+", "-"):
            self.i += 1
            rhs = self.term()
            value = value + rhs if tok[1] == "+" else value - rhs
        return value

    def term(self) -> int:
        kind, text, col = self.take()
        if kind == "num":
            return parse_number(text)
        if text == "(":
            value = self.expr()
            self.take(")")
            return value
        if kind != "name":
            raise self.t.error(f"unexpected {text!r}", col)
        index: int | None = None
        tok = self.peek()
        if tok is not None and tok[1] == "[":
            self.i += 1
            index = self.expr()
            self.take("]")
        fld: tuple[str, int] | None = None
        tok = self.peek()
        if tok is not None and tok[1] == ".":
            self.i += 1
            _, fname, fcol = self.take()
            fld = (fname, fcol)
        return self.resolve(text, col, index, fld)

    def resolve(self, name: str, col: int, index: int | None, fld: tuple[str, int] | None) -> int:
        if self.context == "rom":
            if index is not None or fld is not None:
                raise self.t.error(f"{name!r}: a label takes no index or field", col)
            if self.labels is None:
                raise _Unresolved(name)
            if name not in self.labels:
                raise self.t.error(f"undefined label {name!r}", col)
            return self.labels[name]
        if self.context != "ram":
            raise self.t.error(f"a number is needed here, not {name!r}", col)
        upper = name.upper()
        if index is None and upper not in RAM_SCALARS:
            m = _NAME_INDEX.fullmatch(upper)
            if m and m.group(1) in RAM_TABLES:
                upper, index = m.group(1), int(m.group(2))
        if index is None:
            if upper not in RAM_SCALARS:
                raise self.t.error(f"unknown RAM symbol {name!r}", col)
            address = RAM_SCALARS[upper][0]
        else:
            table = RAM_TABLES.get(upper)
            if table is None:
                raise self.t.error(f"unknown RAM table {name!r}", col)
            try:
                address = table.address(index)
            except ValueError as exc:
                raise self.t.error(str(exc), col) from None
        if fld is not None:
            if upper != "SERVO":
                raise self.t.error(f"only SERVO[n] has fields, not {name!r}", fld[1])
            address += _servo_field(self.t, fld[0], fld[1])
        return address


def _servo_field(t: Text, name: str, col: int) -> int:
    entry = SERVO_FIELDS.get(name.upper())
    if entry is None:
        raise t.error(f"unknown servo-block field {name!r} (one of {', '.join(SERVO_FIELDS)})", col)
    return entry[0]


def evaluate(t: Text, context: str = "int", labels: Labels = None) -> int:
    t = t.strip()
    try:
        return _ExprParser(t, context, labels).parse()
    except _Unresolved:
        return 0  # first pass: the value does not change any length


def check_operand_range(t: Text, what: str, value: int, lo: int, hi: int) -> int:
    if not lo <= value <= hi:
        raise t.error(f"{what} {value} out of range {lo}..{hi}")
    return value


# --------------------------------------------------------------------------- operands


def split_operands(t: Text) -> list[Text]:
    """Split at commas outside brackets; an empty operand text gives no operands."""
    if not t.text.strip():
        return []
    parts: list[Text] = []
    depth = 0
    start = 0
    for i, ch in enumerate(t.text):
        if ch in "[(":
            depth += 1
        elif ch in "])":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(t.sub(start, i))
            start = i + 1
    parts.append(t.sub(start))
    for p in parts:
        if not p.text:
            raise p.error("empty operand")
    return parts


def _bracketed(t: Text, keyword: str) -> Text | None:
    """The inside of ``KEYWORD[...]`` when ``t`` is exactly that, else None."""
    if t.text.upper().startswith(keyword + "[") and t.text.endswith("]"):
        inner = t.sub(len(keyword) + 1, len(t.text) - 1)
        if inner.text.count("[") == inner.text.count("]"):
            return inner
    return None


_ICS: Final = re.compile(r"ICS\s*\[([^\]]*)\]\s*(?:\.\s*([A-Za-z_0-9]+))?\s*(.*)", re.IGNORECASE)


def _memory_operand(t: Text, labels: Labels) -> Ram | Ics | Rom | Com | None:
    if t.text.upper() == "COM":
        return Com()
    inner = _bracketed(t, "RAM")
    if inner is not None:
        addr = evaluate(inner, "ram")
        try:
            return Ram(addr)
        except ValueError as exc:
            raise inner.error(str(exc)) from None
    inner = _bracketed(t, "ROM")
    if inner is not None:
        addr = evaluate(inner, "rom", labels)
        try:
            return Rom(addr)
        except ValueError as exc:
            raise inner.error(str(exc)) from None
    m = _ICS.fullmatch(t.text)
    if m is not None:
        number = check_operand_range(t, "ICS number", evaluate(t.sub(m.start(1), m.end(1))), 0, 35)
        offset = 0
        if m.group(2):
            offset = _servo_field(t, m.group(2), m.start(2))
        rest = m.group(3)
        if rest:
            if rest[0] not in "+-":
                raise t.error(f"unexpected {rest!r} after ICS[n]", m.start(3))
            offset += evaluate(t.sub(m.start(3)))
        check_operand_range(t, "ICS offset", offset, 0, 255)
        return Ics(offset, number)
    return None


def _literal(t: Text) -> bytes:
    """``#02 80`` (bytes as in the frame) or ``#0x8002`` / ``#7500:2`` (LE value, width)."""
    body = t.sub(1)
    words = body.text.split()
    if words and all(HEX_BYTE.fullmatch(w) for w in words):
        return bytes(int(w, 16) for w in words)
    text, _, width_text = body.text.partition(":")
    value_t = Text(text, body.column, body.line).strip()
    value = evaluate(value_t)
    if width_text:
        width = evaluate(Text(width_text, body.column + len(text) + 1, body.line))
    elif value_t.text.lower().startswith(("0x", "$")):
        digits = len(value_t.text) - (1 if value_t.text.startswith("$") else 2)
        width = (digits + 1) // 2
    else:
        raise t.error(
            f"literal {t.text!r} needs a width: write bytes (#05 00), hex (#0x0005) "
            "or value:width (#5:2)"
        )
    check_operand_range(t, "literal width", width, 1, 121)
    if not 0 <= value < 1 << (8 * width):
        raise t.error(f"literal value {value} does not fit {width} byte(s)")
    return value.to_bytes(width, "little")


def read_source(t: Text, labels: Labels) -> Source:
    if t.text.startswith("#"):
        data = _literal(t)
        try:
            return Data(data)
        except ValueError as exc:
            raise t.error(str(exc)) from None
    op = _memory_operand(t, labels)
    if op is None or isinstance(op, Com):
        raise t.error(f"bad source operand {t.text!r}: expected RAM[..], ICS[n].., ROM[..] or #..")
    return op


def read_destination(t: Text, labels: Labels) -> Destination:
    op = _memory_operand(t, labels)
    if op is None:
        raise t.error(
            f"bad destination operand {t.text!r}: expected RAM[..], ICS[n].., ROM[..] or COM"
        )
    return op


def read_condition(t: Text) -> Condition:
    text = t.text.strip().upper().replace(" ", "")
    if text.startswith("COND="):
        value = evaluate(t.sub(t.text.index("=") + 1))
        check_operand_range(t, "condition byte", value, 0, 15)
        return Condition.from_byte(value)
    cz = z = cc = c = False
    if text != "ALWAYS":
        for part in text.split("&"):
            if part in ("Z", "NZ") and not cz:
                cz, z = True, part == "Z"
            elif part in ("C", "NC") and not cc:
                cc, c = True, part == "C"
            else:
                raise t.error(f"bad condition {t.text!r}: use Z, NZ, C, NC, Z&C, ... or COND=n")
    return Condition(cz, z, cc, c)


def read_pairs(parts: list[Text], value: Callable[[Text], int]) -> list[tuple[int, int]]:
    out: list[tuple[int, int]] = []
    for p in parts:
        ics_text, eq, _ = p.text.partition("=")
        if not eq:
            raise p.error(f"expected ICS=value, not {p.text!r}")
        ics = check_operand_range(
            p, "ICS number", evaluate(Text(ics_text, p.column, p.line)), 0, 35
        )
        if any(k == ics for k, _ in out):
            raise p.error(f"ICS {ics} given twice")
        out.append((ics, value(p.sub(len(ics_text) + 1))))
    return out


def read_position(t: Text) -> int:
    word = POSITION_WORDS.get(t.text.upper())
    return word if word is not None else evaluate(t)


# --------------------------------------------------------------------------- statements


def want_operands(parts: list[Text], lo: int, hi: int, usage: str, where: Text) -> None:
    if not lo <= len(parts) <= hi:
        raise where.error(f"expected {usage}")
