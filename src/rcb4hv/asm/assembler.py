"""Text -> bytes: the RCB-4 assembler (syntax in :mod:`rcb4hv.asm`).

Two passes: the first finds every label's address (instruction lengths never depend on a
label's value, because labels only appear in fixed-width ROM addresses and branch targets),
the second builds the commands and encodes them with :func:`rcb4hv.protocol.encode_command`.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Final

from rcb4hv.asm.errors import AsmError
from rcb4hv.asm.symbols import RAM_SCALARS, RAM_TABLES, SERVO_FIELDS
from rcb4hv.asm.syntax import POSITION_WORDS, SHIFT_WORDS
from rcb4hv.protocol import (
    ROM_SIZE,
    AcknowledgeCheck,
    Call,
    Com,
    Command,
    CommunicateDevice,
    Condition,
    Data,
    Destination,
    GetVersionInfo,
    Ics,
    Jump,
    Move,
    Not,
    Ram,
    Return,
    Rom,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
    Shift,
    Source,
    encode_command,
)
from rcb4hv.protocol.registry import BY_MNEMONIC

__all__ = ["AsmItem", "AssembledProgram", "assemble"]

ERASED: Final = 0xFF
"""Value of erased EEPROM bytes; gaps left by ``.org`` are filled with it."""


@dataclass(frozen=True, slots=True)
class AsmItem:
    """One assembled statement: its ROM address, bytes, command (None for data) and line."""

    address: int
    data: bytes
    command: Command | None
    line: int
    source: str


@dataclass(frozen=True)
class AssembledProgram:
    """The result of :func:`assemble`.

    ``data`` holds the bytes from ``origin`` on, gaps between ``.org`` regions filled with FF
    (erased EEPROM); ``items`` every statement that produced bytes, in address order.
    """

    origin: int
    data: bytes
    items: tuple[AsmItem, ...]
    labels: Mapping[str, int] = field(default_factory=dict)

    @property
    def end(self) -> int:
        """The address after the last byte."""
        return self.origin + len(self.data)

    @property
    def frames(self) -> list[bytes]:
        """The command frames, in order (``.byte`` / ``.fill`` data left out)."""
        return [item.data for item in self.items if item.command is not None]

    @property
    def commands(self) -> list[Command]:
        return [item.command for item in self.items if item.command is not None]

    def image(self, size: int = ROM_SIZE, fill: int = ERASED) -> bytes:
        """A ``size``-byte image with the program at its origin, the rest ``fill``."""
        if self.end > size:
            raise ValueError(f"program ends at {self.end:#x}, past the {size:#x}-byte image")
        out = bytearray([fill]) * size
        out[self.origin : self.end] = self.data
        return bytes(out)


# --------------------------------------------------------------------------- lexing

_TOKEN: Final = re.compile(
    r"\s*(?:(?P<num>\$[0-9A-Fa-f]+|0[xX][0-9A-Fa-f]+|0[bB][01]+|\d+)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)|(?P<punct>[\[\]().+\-]))"
)
_HEX_BYTE: Final = re.compile(r"[0-9A-Fa-f]{2}")
_NAME_INDEX: Final = re.compile(r"([A-Z_]*[A-Z])(\d+)")
_LABEL: Final = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*):")
_MNEMONIC: Final = re.compile(r"\s*([.A-Za-z][A-Za-z0-9_]*(?:\.[A-Za-z]+)*)")
_IF: Final = re.compile(r"\s+IF\s+", re.IGNORECASE)


class _Unresolved(Exception):
    """A label not known yet (first pass)."""


@dataclass(frozen=True, slots=True)
class _Text:
    """A piece of a source line and the 1-based column where it starts."""

    text: str
    column: int
    line: int

    def error(self, message: str, offset: int = 0) -> AsmError:
        return AsmError(message, self.line, self.column + offset)

    def strip(self) -> _Text:
        lead = len(self.text) - len(self.text.lstrip())
        return _Text(self.text.strip(), self.column + lead, self.line)

    def sub(self, start: int, end: int | None = None) -> _Text:
        return _Text(self.text[start:end], self.column + start, self.line).strip()


def _parse_number(token: str) -> int:
    if token.startswith("$"):
        return int(token[1:], 16)
    return int(token, 0) if token[:2].lower() in ("0x", "0b") else int(token, 10)


def _tokens(t: _Text) -> list[tuple[str, str, int]]:
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
    def __init__(self, t: _Text, context: str, labels: Labels) -> None:
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
            return _parse_number(text)
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


def _servo_field(t: _Text, name: str, col: int) -> int:
    entry = SERVO_FIELDS.get(name.upper())
    if entry is None:
        raise t.error(f"unknown servo-block field {name!r} (one of {', '.join(SERVO_FIELDS)})", col)
    return entry[0]


def _eval(t: _Text, context: str = "int", labels: Labels = None) -> int:
    t = t.strip()
    try:
        return _ExprParser(t, context, labels).parse()
    except _Unresolved:
        return 0  # first pass: the value does not change any length


def _check_range(t: _Text, what: str, value: int, lo: int, hi: int) -> int:
    if not lo <= value <= hi:
        raise t.error(f"{what} {value} out of range {lo}..{hi}")
    return value


# --------------------------------------------------------------------------- operands


def _split_operands(t: _Text) -> list[_Text]:
    """Split at commas outside brackets; an empty operand text gives no operands."""
    if not t.text.strip():
        return []
    parts: list[_Text] = []
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


def _bracketed(t: _Text, keyword: str) -> _Text | None:
    """The inside of ``KEYWORD[...]`` when ``t`` is exactly that, else None."""
    if t.text.upper().startswith(keyword + "[") and t.text.endswith("]"):
        inner = t.sub(len(keyword) + 1, len(t.text) - 1)
        if inner.text.count("[") == inner.text.count("]"):
            return inner
    return None


_ICS: Final = re.compile(r"ICS\s*\[([^\]]*)\]\s*(?:\.\s*([A-Za-z_0-9]+))?\s*(.*)", re.IGNORECASE)


def _memory_operand(t: _Text, labels: Labels) -> Ram | Ics | Rom | Com | None:
    if t.text.upper() == "COM":
        return Com()
    inner = _bracketed(t, "RAM")
    if inner is not None:
        addr = _eval(inner, "ram")
        try:
            return Ram(addr)
        except ValueError as exc:
            raise inner.error(str(exc)) from None
    inner = _bracketed(t, "ROM")
    if inner is not None:
        addr = _eval(inner, "rom", labels)
        try:
            return Rom(addr)
        except ValueError as exc:
            raise inner.error(str(exc)) from None
    m = _ICS.fullmatch(t.text)
    if m is not None:
        number = _check_range(t, "ICS number", _eval(t.sub(m.start(1), m.end(1))), 0, 35)
        offset = 0
        if m.group(2):
            offset = _servo_field(t, m.group(2), m.start(2))
        rest = m.group(3)
        if rest:
            if rest[0] not in "+-":
                raise t.error(f"unexpected {rest!r} after ICS[n]", m.start(3))
            offset += _eval(t.sub(m.start(3)))
        _check_range(t, "ICS offset", offset, 0, 255)
        return Ics(offset, number)
    return None


def _literal(t: _Text) -> bytes:
    """``#02 80`` (bytes as in the frame) or ``#0x8002`` / ``#7500:2`` (LE value, width)."""
    body = t.sub(1)
    words = body.text.split()
    if words and all(_HEX_BYTE.fullmatch(w) for w in words):
        return bytes(int(w, 16) for w in words)
    text, _, width_text = body.text.partition(":")
    value_t = _Text(text, body.column, body.line).strip()
    value = _eval(value_t)
    if width_text:
        width = _eval(_Text(width_text, body.column + len(text) + 1, body.line))
    elif value_t.text.lower().startswith(("0x", "$")):
        digits = len(value_t.text) - (1 if value_t.text.startswith("$") else 2)
        width = (digits + 1) // 2
    else:
        raise t.error(
            f"literal {t.text!r} needs a width: write bytes (#05 00), hex (#0x0005) "
            "or value:width (#5:2)"
        )
    _check_range(t, "literal width", width, 1, 121)
    if not 0 <= value < 1 << (8 * width):
        raise t.error(f"literal value {value} does not fit {width} byte(s)")
    return value.to_bytes(width, "little")


def _source(t: _Text, labels: Labels) -> Source:
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


def _destination(t: _Text, labels: Labels) -> Destination:
    op = _memory_operand(t, labels)
    if op is None:
        raise t.error(
            f"bad destination operand {t.text!r}: expected RAM[..], ICS[n].., ROM[..] or COM"
        )
    return op


def _condition(t: _Text) -> Condition:
    text = t.text.strip().upper().replace(" ", "")
    if text.startswith("COND="):
        value = _eval(t.sub(t.text.index("=") + 1))
        _check_range(t, "condition byte", value, 0, 15)
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


def _pairs(parts: list[_Text], value: Callable[[_Text], int]) -> list[tuple[int, int]]:
    out: list[tuple[int, int]] = []
    for p in parts:
        ics_text, eq, _ = p.text.partition("=")
        if not eq:
            raise p.error(f"expected ICS=value, not {p.text!r}")
        ics = _check_range(p, "ICS number", _eval(_Text(ics_text, p.column, p.line)), 0, 35)
        if any(k == ics for k, _ in out):
            raise p.error(f"ICS {ics} given twice")
        out.append((ics, value(p.sub(len(ics_text) + 1))))
    return out


def _position(t: _Text) -> int:
    word = POSITION_WORDS.get(t.text.upper())
    return word if word is not None else _eval(t)


# --------------------------------------------------------------------------- statements


def _want(parts: list[_Text], lo: int, hi: int, usage: str, where: _Text) -> None:
    if not lo <= len(parts) <= hi:
        raise where.error(f"expected {usage}")


def _build(mnemonic: str, flags: set[str], ops: _Text, labels: Labels, where: _Text) -> Command:
    """One command from a mnemonic (upper case, without flags) and its operand text."""
    allowed: set[str] = set()
    cmd: Command
    spec = BY_MNEMONIC.get(SHIFT_WORDS.get(mnemonic, mnemonic))
    cls = spec.cls if spec is not None else None
    if cls is Jump or cls is Call:
        target_t, *cond = _IF.split(ops.text, maxsplit=1)
        target = _Text(target_t, ops.column, ops.line).strip()
        if not target.text:
            raise where.error(f"expected {mnemonic} TARGET [IF CONDITION]")
        condition = Condition()
        if cond:
            condition = _condition(ops.sub(len(ops.text) - len(cond[0])))
        address = _check_range(target, "branch target", _eval(target, "rom", labels), 0, 0xFFFFFF)
        cmd = cls(address, condition)
        _no_flags(flags, allowed, where)
        return cmd
    parts = _split_operands(ops)
    if spec is not None and (spec.symbol is not None or cls is Move):
        allowed = set() if cls is Move else {"NW"}
        _want(parts, 2, 3, f"{mnemonic} DEST, SOURCE[, SIZE]", where)
        dst = _destination(parts[0], labels)
        src = _source(parts[1], labels)
        size = _eval(parts[2]) if len(parts) == 3 else None
        if size is None and not isinstance(src, Data):
            raise where.error(f"{mnemonic} from {parts[1].text} needs a size: add ', SIZE'")
        _no_flags(flags, allowed, where)
        if cls is Move:
            return Move(dst, src, size)
        result: Command = spec.cls(dst, src, size, "NW" in flags)
        return result
    if cls is Not or cls is Shift:
        allowed = {"NW"}
        _no_flags(flags, allowed, where)
        if cls is Not:
            _want(parts, 2, 2, "NOT DEST, SIZE", where)
            dst = _destination(parts[0], labels)
            return Not(dst, _eval(parts[1]), "NW" in flags)
        _want(
            parts,
            3,
            3,
            f"{mnemonic} DEST, {'COUNT' if mnemonic == 'SHIFT' else 'BITS'}, SIZE",
            where,
        )
        dst = _destination(parts[0], labels)
        bits, size = _eval(parts[1]), _eval(parts[2])
        if mnemonic == "SHR":
            _check_range(parts[1], "right shift", bits, 0, 127)
            return Shift.right(dst, bits, size, "NW" in flags)
        if mnemonic == "SHL":
            _check_range(parts[1], "left shift", bits, 1, 128)
            return Shift.left(dst, bits, size, "NW" in flags)
        return Shift(dst, size, "NW" in flags, _check_range(parts[1], "count", bits, 0, 255))
    if cls is Return:
        _want(parts, 0, 0, "RETURN without operands", where)
        cmd = Return()
    elif cls is GetVersionInfo:
        _want(parts, 0, 0, "VERSION without operands", where)
        cmd = GetVersionInfo()
    elif cls is AcknowledgeCheck:
        allowed = {"LONG"}
        _want(parts, 0, 0, "ACKCHECK without operands", where)
        cmd = AcknowledgeCheck("LONG" in flags)
    elif cls is CommunicateDevice:
        _want(parts, 4, 4, "ICSCOMM ICS, COUNT, RAM[TX], RAM[RX]", where)
        ics, count = _eval(parts[0]), _eval(parts[1])
        tx, rx = (_destination(p, labels) for p in parts[2:])
        if not isinstance(tx, Ram) or not isinstance(rx, Ram):
            raise where.error("ICSCOMM buffers must be RAM[..] operands")
        cmd = CommunicateDevice(ics, count, tx.address, rx.address)
    elif cls is RunSingleServo:
        allowed = {"KEEP"}
        _want(parts, 3, 3, "SERVO ICS, SPEED, POSITION", where)
        cmd = RunSingleServo(
            _eval(parts[0]), _eval(parts[1]), _position(parts[2]), "KEEP" not in flags
        )
    elif cls is RunConstFrameServo:
        allowed = {"KEEP"}
        if not parts:
            raise where.error("expected SERVOS SPEED[, ICS=POSITION ...]")
        cmd = RunConstFrameServo(_eval(parts[0]), _pairs(parts[1:], _position), "KEEP" not in flags)
    elif cls is RunSeriesServo:
        allowed = {"KEEP"}
        moves = []
        for ics, packed in _pairs(parts, lambda t: _pack_series(t)):
            moves.append((ics, packed >> 16, packed & 0xFFFF))
        cmd = RunSeriesServo(moves, "KEEP" not in flags)
    elif cls is SetSpeed or cls is SetStretch:
        cmd = cls(_pairs(parts, _eval))
    else:
        raise where.error(f"unknown mnemonic {mnemonic!r}")
    _no_flags(flags, allowed, where)
    return cmd


def _pack_series(t: _Text) -> int:
    pos_t, at, _ = t.text.partition("@")
    if not at:
        raise t.error(f"expected POSITION@SPEED, not {t.text!r}")
    position = _position(_Text(pos_t, t.column, t.line).strip())
    speed = _eval(t.sub(len(pos_t) + 1))
    _check_range(t, "speed", speed, 0, 255)
    _check_range(t, "position", position, 0, 0xFFFF)
    return speed << 16 | position


def _no_flags(flags: set[str], allowed: set[str], where: _Text) -> None:
    bad = flags - allowed
    if bad:
        raise where.error(f"flag .{sorted(bad)[0]} is not allowed here")


def _byte_tokens(t: _Text) -> bytes:
    out = bytearray()
    pos = 0
    for m in re.finditer(r"[^\s,]+", t.text):
        word = m.group()
        pos = m.start()
        if _HEX_BYTE.fullmatch(word):
            out.append(int(word, 16))
        else:
            try:
                value = _parse_number(word) if word[:2].lower() == "0x" or word[0] == "$" else -1
            except ValueError:
                value = -1
            if not 0 <= value <= 0xFF:
                raise t.error(f"bad byte {word!r}: write two hex digits (0D) or 0x0D", pos)
            out.append(value)
    return bytes(out)


@dataclass
class _Line:
    number: int
    text: str
    label: str | None
    label_col: int
    mnemonic: _Text | None
    operands: _Text


def _split_line(number: int, raw: str) -> _Line:
    text = raw.split(";", 1)[0].rstrip()
    label: str | None = None
    label_col = 1
    rest_start = 0
    m = _LABEL.match(text)
    if m is not None:
        label, label_col, rest_start = m.group(1), m.start(1) + 1, m.end()
    m2 = _MNEMONIC.match(text, rest_start)
    if m2 is None:
        if text[rest_start:].strip():
            bad = len(text) - len(text[rest_start:].lstrip())
            raise AsmError(f"expected a mnemonic, found {text[bad : bad + 12]!r}", number, bad + 1)
        return _Line(number, raw, label, label_col, None, _Text("", len(text) + 1, number))
    mnemonic = _Text(m2.group(1), m2.start(1) + 1, number)
    operands = _Text(text[m2.end() :], m2.end() + 1, number).strip()
    if operands.text and not text[m2.end()].isspace():
        raise AsmError(f"unexpected {text[m2.end()]!r} after the mnemonic", number, m2.end() + 1)
    return _Line(number, raw, label, label_col, mnemonic, operands)


def _statement(line: _Line, labels: Labels) -> tuple[str, bytes, Command | None]:
    """('org', address bytes, None) | ('data', bytes, None) | ('cmd', frame, command)."""
    assert line.mnemonic is not None
    word = line.mnemonic.text.upper()
    ops = line.operands
    if word.startswith("."):
        if word == ".ORG":
            address = _check_range(ops, ".org address", _eval(ops), 0, ROM_SIZE - 1)
            return "org", address.to_bytes(3, "little"), None
        if word in (".BYTE", ".DATA"):
            data = _byte_tokens(ops)
            if not data:
                raise line.mnemonic.error(f"{word.lower()} needs at least one byte")
            return "data", data, None
        if word == ".FILL":
            parts = _split_operands(ops)
            _want(parts, 2, 2, ".fill COUNT, BYTE", line.mnemonic)
            count = _check_range(parts[0], "count", _eval(parts[0]), 1, ROM_SIZE)
            value = _byte_tokens(parts[1])
            if len(value) != 1:
                raise parts[1].error(".fill takes one byte value")
            return "data", value * count, None
        raise line.mnemonic.error(f"unknown directive {line.mnemonic.text!r}")
    name, *flag_list = word.split(".")
    try:
        cmd = _build(name, set(flag_list), ops, labels, line.mnemonic)
        frame = encode_command(cmd)
    except AsmError:
        raise
    except ValueError as exc:
        raise line.mnemonic.error(str(exc)) from None
    return "cmd", frame, cmd


def assemble(text: str, origin: int | None = None) -> AssembledProgram:
    """Assemble ``text``; ``origin`` is the ROM address of the first byte (default: the first
    ``.org``, else 0). Raise :class:`AsmError` naming the line and column of the first error."""
    if origin is not None and not 0 <= origin < ROM_SIZE:
        raise ValueError(f"origin {origin:#x} outside ROM 0..{ROM_SIZE - 1:#x}")
    lines = [_split_line(i, raw) for i, raw in enumerate(text.splitlines(), 1)]
    labels: dict[str, int] = {}
    # pass 1: addresses of labels
    start, _ = _run(lines, origin, None, labels)
    # pass 2: build and encode
    start, items = _run(lines, origin, labels, None)
    data = bytearray()
    for item in items:
        gap = item.address - (start + len(data))
        data += bytes([ERASED]) * gap
        data += item.data
    return AssembledProgram(start, bytes(data), tuple(items), dict(labels))


def _run(
    lines: list[_Line], origin: int | None, labels: Labels, collect: dict[str, int] | None
) -> tuple[int, list[AsmItem]]:
    pc = origin if origin is not None else 0
    start = pc
    emitted = False
    items: list[AsmItem] = []
    label_lines: dict[str, int] = {}
    pending: list[str] = []  # labels defined before the first byte: they follow a first .org
    for line in lines:
        if line.label is not None and collect is not None:
            if line.label in collect:
                raise AsmError(
                    f"duplicate label {line.label!r} (first defined on line "
                    f"{label_lines[line.label]})",
                    line.number,
                    line.label_col,
                )
            collect[line.label] = pc
            label_lines[line.label] = line.number
            if not emitted:
                pending.append(line.label)
        if line.mnemonic is None:
            continue
        kind, data, cmd = _statement(line, labels)
        if kind == "org":
            address = int.from_bytes(data, "little")
            if not emitted:
                if origin is not None and address != origin:
                    raise line.mnemonic.error(
                        f".org ${address:06X} conflicts with the origin ${origin:06X} given"
                    )
                start = pc = address
                if collect is not None:
                    collect.update(dict.fromkeys(pending, address))
            elif address < pc:
                raise line.mnemonic.error(
                    f".org ${address:06X} is below the current address ${pc:06X}"
                )
            pc = address
            if line.label is not None and collect is not None:
                collect[line.label] = address  # `name: .org X` names X
            continue
        if pc + len(data) > ROM_SIZE:
            raise line.mnemonic.error(f"code runs past the end of ROM (${ROM_SIZE:06X})")
        items.append(AsmItem(pc, data, cmd, line.number, line.text))
        pc += len(data)
        emitted = True
    return start, items
