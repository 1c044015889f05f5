"""Text -> bytes: the RCB-4 assembler (syntax in :mod:`rcb4hv.asm`).

Two passes: the first finds every label's address (instruction lengths never depend on a
label's value, because labels only appear in fixed-width ROM addresses and branch targets),
the second builds the commands and encodes them with :func:`rcb4hv.protocol.encode_command`.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Final

from rcb4hv.asm.parse import (
    HEX_BYTE,
    IF_WORD,
    LABEL,
    MNEMONIC,
    Labels,
    Text,
    check_operand_range,
    evaluate,
    parse_number,
    read_condition,
    read_destination,
    read_pairs,
    read_position,
    read_source,
    split_operands,
    want_operands,
)
from rcb4hv.asm.syntax import SHIFT_WORDS
from rcb4hv.errors import AsmError
from rcb4hv.protocol import (
    ROM_SIZE,
    AcknowledgeCheck,
    Call,
    Command,
    CommunicateDevice,
    Condition,
    Data,
    GetVersionInfo,
    Jump,
    Move,
    Not,
    Ram,
    Return,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
    Shift,
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


# statements (tokens, expressions and operands: rcb4hv.asm.parse)


def _build(mnemonic: str, flags: set[str], ops: Text, labels: Labels, where: Text) -> Command:
    """One command from a mnemonic (upper case, without flags) and its operand text."""
    allowed: set[str] = set()
    cmd: Command
    spec = BY_MNEMONIC.get(SHIFT_WORDS.get(mnemonic, mnemonic))
    cls = spec.cls if spec is not None else None
    if cls is Jump or cls is Call:
        target_t, *cond = IF_WORD.split(ops.text, maxsplit=1)
        target = Text(target_t, ops.column, ops.line).strip()
        if not target.text:
            raise where.error(f"expected {mnemonic} TARGET [IF CONDITION]")
        condition = Condition()
        if cond:
            condition = read_condition(ops.sub(len(ops.text) - len(cond[0])))
        address = check_operand_range(
            target, "branch target", evaluate(target, "rom", labels), 0, 0xFFFFFF
        )
        cmd = cls(address, condition)
        _no_flags(flags, allowed, where)
        return cmd
    parts = split_operands(ops)
    if spec is not None and (spec.symbol is not None or cls is Move):
        allowed = set() if cls is Move else {"NW"}
        want_operands(parts, 2, 3, f"{mnemonic} DEST, SOURCE[, SIZE]", where)
        dst = read_destination(parts[0], labels)
        src = read_source(parts[1], labels)
        size = evaluate(parts[2]) if len(parts) == 3 else None
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
            want_operands(parts, 2, 2, "NOT DEST, SIZE", where)
            dst = read_destination(parts[0], labels)
            return Not(dst, evaluate(parts[1]), "NW" in flags)
        want_operands(
            parts,
            3,
            3,
            f"{mnemonic} DEST, {'COUNT' if mnemonic == 'SHIFT' else 'BITS'}, SIZE",
            where,
        )
        dst = read_destination(parts[0], labels)
        bits, size = evaluate(parts[1]), evaluate(parts[2])
        if mnemonic == "SHR":
            check_operand_range(parts[1], "right shift", bits, 0, 127)
            return Shift.right(dst, bits, size, "NW" in flags)
        if mnemonic == "SHL":
            check_operand_range(parts[1], "left shift", bits, 1, 128)
            return Shift.left(dst, bits, size, "NW" in flags)
        return Shift(dst, size, "NW" in flags, check_operand_range(parts[1], "count", bits, 0, 255))
    if cls is Return:
        want_operands(parts, 0, 0, "RETURN without operands", where)
        cmd = Return()
    elif cls is GetVersionInfo:
        want_operands(parts, 0, 0, "VERSION without operands", where)
        cmd = GetVersionInfo()
    elif cls is AcknowledgeCheck:
        allowed = {"LONG"}
        want_operands(parts, 0, 0, "ACKCHECK without operands", where)
        cmd = AcknowledgeCheck("LONG" in flags)
    elif cls is CommunicateDevice:
        want_operands(parts, 4, 4, "ICSCOMM ICS, COUNT, RAM[TX], RAM[RX]", where)
        ics, count = evaluate(parts[0]), evaluate(parts[1])
        tx, rx = (read_destination(p, labels) for p in parts[2:])
        if not isinstance(tx, Ram) or not isinstance(rx, Ram):
            raise where.error("ICSCOMM buffers must be RAM[..] operands")
        cmd = CommunicateDevice(ics, count, tx.address, rx.address)
    elif cls is RunSingleServo:
        allowed = {"KEEP"}
        want_operands(parts, 3, 3, "SERVO ICS, SPEED, POSITION", where)
        cmd = RunSingleServo(
            evaluate(parts[0]), evaluate(parts[1]), read_position(parts[2]), "KEEP" not in flags
        )
    elif cls is RunConstFrameServo:
        allowed = {"KEEP"}
        if not parts:
            raise where.error("expected SERVOS SPEED[, ICS=POSITION ...]")
        cmd = RunConstFrameServo(
            evaluate(parts[0]), read_pairs(parts[1:], read_position), "KEEP" not in flags
        )
    elif cls is RunSeriesServo:
        allowed = {"KEEP"}
        moves = []
        for ics, packed in read_pairs(parts, lambda t: _pack_series(t)):
            moves.append((ics, packed >> 16, packed & 0xFFFF))
        cmd = RunSeriesServo(moves, "KEEP" not in flags)
    elif cls is SetSpeed or cls is SetStretch:
        cmd = cls(read_pairs(parts, evaluate))
    else:
        raise where.error(f"unknown mnemonic {mnemonic!r}")
    _no_flags(flags, allowed, where)
    return cmd


def _pack_series(t: Text) -> int:
    pos_t, at, _ = t.text.partition("@")
    if not at:
        raise t.error(f"expected POSITION@SPEED, not {t.text!r}")
    position = read_position(Text(pos_t, t.column, t.line).strip())
    speed = evaluate(t.sub(len(pos_t) + 1))
    check_operand_range(t, "speed", speed, 0, 255)
    check_operand_range(t, "position", position, 0, 0xFFFF)
    return speed << 16 | position


def _no_flags(flags: set[str], allowed: set[str], where: Text) -> None:
    bad = flags - allowed
    if bad:
        raise where.error(f"flag .{sorted(bad)[0]} is not allowed here")


def _byte_tokens(t: Text) -> bytes:
    out = bytearray()
    pos = 0
    for m in re.finditer(r"[^\s,]+", t.text):
        word = m.group()
        pos = m.start()
        if HEX_BYTE.fullmatch(word):
            out.append(int(word, 16))
        else:
            try:
                value = parse_number(word) if word[:2].lower() == "0x" or word[0] == "$" else -1
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
    mnemonic: Text | None
    operands: Text


def _split_line(number: int, raw: str) -> _Line:
    text = raw.split(";", 1)[0].rstrip()
    label: str | None = None
    label_col = 1
    rest_start = 0
    m = LABEL.match(text)
    if m is not None:
        label, label_col, rest_start = m.group(1), m.start(1) + 1, m.end()
    m2 = MNEMONIC.match(text, rest_start)
    if m2 is None:
        if text[rest_start:].strip():
            bad = len(text) - len(text[rest_start:].lstrip())
            raise AsmError(f"expected a mnemonic, found {text[bad : bad + 12]!r}", number, bad + 1)
        return _Line(number, raw, label, label_col, None, Text("", len(text) + 1, number))
    mnemonic = Text(m2.group(1), m2.start(1) + 1, number)
    operands = Text(text[m2.end() :], m2.end() + 1, number).strip()
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
            address = check_operand_range(ops, ".org address", evaluate(ops), 0, ROM_SIZE - 1)
            return "org", address.to_bytes(3, "little"), None
        if word in (".BYTE", ".DATA"):
            data = _byte_tokens(ops)
            if not data:
                raise line.mnemonic.error(f"{word.lower()} needs at least one byte")
            return "data", data, None
        if word == ".FILL":
            parts = split_operands(ops)
            want_operands(parts, 2, 2, ".fill COUNT, BYTE", line.mnemonic)
            count = check_operand_range(parts[0], "count", evaluate(parts[0]), 1, ROM_SIZE)
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
