"""Bytes -> text: the RCB-4 disassembler (syntax in :mod:`rcb4hv.asm`).

A linear sweep: at each address the SIZE byte proposes a frame, which
:func:`rcb4hv.protocol.decode_command` either accepts (an instruction) or rejects (one raw
byte, shown with ``.byte``). Whatever the input, assembling the output gives the same bytes.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Final

from rcb4hv.asm.symbols import field_text, ram_text
from rcb4hv.asm.syntax import SHIFT_LEFT, SHIFT_RIGHT, condition_text, position_text, rom_text
from rcb4hv.errors import ChecksumError, ProtocolError
from rcb4hv.protocol import (
    ADDR,
    ROM_SIZE,
    AcknowledgeCheck,
    Button,
    Call,
    Command,
    CommunicateDevice,
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
    SystemRegister,
    checksum,
    decode_command,
    encode_command,
    frame_at,
)
from rcb4hv.protocol.datacmds import BinaryOp
from rcb4hv.protocol.registry import spec_of

__all__ = [
    "Listing",
    "SweepItem",
    "branch_targets",
    "disassemble",
    "disassemble_frames",
    "format_command",
    "operand_text",
    "sweep",
]

COMMENT_COLUMN: Final = 40
BYTES_PER_LINE: Final = 16
RUN_MIN: Final = 16
"""Runs of at least this many equal bytes become ``.fill`` (or are skipped if erased)."""

_DATA_COMMANDS: Final = (Move, BinaryOp)


def operand_text(op: Destination | Source, symbols: bool = True) -> str:
    """``RAM[BUTTONS]``, ``ICS[5].MEASURED``, ``ROM[$000B80]``, ``COM`` or ``#02 80``."""
    if isinstance(op, Ram):
        return f"RAM[{ram_text(op.address, symbols)}]"
    if isinstance(op, Ics):
        if symbols:
            return f"ICS[{op.ics}]{field_text(op.offset)}"
        return f"ICS[{op.ics}]" + (f"+{op.offset}" if op.offset else "")
    if isinstance(op, Rom):
        return f"ROM[{rom_text(op.address)}]"
    if isinstance(op, Data):
        return "#" + op.data.hex(" ").upper()
    return "COM"


def _flags(*pairs: tuple[bool, str]) -> str:
    return "".join(f".{name}" for on, name in pairs if on)


def format_command(
    cmd: Command,
    *,
    label_for: Callable[[int], str | None] | None = None,
    symbols: bool = True,
) -> str:
    """One command as assembler text (``label_for`` names branch targets it knows)."""

    def op(o: Destination | Source) -> str:
        return operand_text(o, symbols)

    name = spec_of(type(cmd)).mnemonic
    if isinstance(cmd, _DATA_COMMANDS):
        nw = not isinstance(cmd, Move) and cmd.no_write
        size = "" if isinstance(cmd.src, Data) else f", {cmd.nbytes}"
        return f"{name}{_flags((nw, 'NW'))} {op(cmd.dst)}, {op(cmd.src)}{size}"
    if isinstance(cmd, Shift):
        bits = cmd.right_bits
        name = SHIFT_RIGHT if bits >= 0 else SHIFT_LEFT
        return f"{name}{_flags((cmd.no_write, 'NW'))} {op(cmd.dst)}, {abs(bits)}, {cmd.size}"
    if isinstance(cmd, Not):
        return f"{name}{_flags((cmd.no_write, 'NW'))} {op(cmd.dst)}, {cmd.size}"
    if isinstance(cmd, (Jump, Call)):
        label = label_for(cmd.address) if label_for is not None else None
        target = label if label is not None else rom_text(cmd.address)
        cond = condition_text(cmd.condition)
        when = "" if cond == "ALWAYS" else f" IF {cond}"
        return f"{name} {target}{when}"
    if isinstance(cmd, Return):
        return name
    if isinstance(cmd, CommunicateDevice):
        tx, rx = ram_text(cmd.tx_address, symbols), ram_text(cmd.rx_address, symbols)
        return f"{name} {cmd.ics}, {cmd.tx_count}, RAM[{tx}], RAM[{rx}]"
    keep = ""
    if isinstance(cmd, (RunSingleServo, RunConstFrameServo, RunSeriesServo)):
        keep = _flags((not cmd.set_update_flag, "KEEP"))
    if isinstance(cmd, RunSingleServo):
        return f"{name}{keep} {cmd.ics}, {cmd.speed}, {position_text(cmd.position)}"
    if isinstance(cmd, RunConstFrameServo):
        pairs = "".join(f", {k}={position_text(p)}" for k, p in cmd.positions)
        return f"{name}{keep} {cmd.speed}{pairs}"
    if isinstance(cmd, RunSeriesServo):
        moves = ", ".join(f"{k}={position_text(p)}@{s}" for k, s, p in cmd.moves)
        return f"{name}{keep}" + (f" {moves}" if moves else "")
    if isinstance(cmd, (SetSpeed, SetStretch)):
        values = ", ".join(f"{k}={v}" for k, v in cmd.values)
        return name + (f" {values}" if values else "")
    if isinstance(cmd, GetVersionInfo):
        return name
    assert isinstance(cmd, AcknowledgeCheck)
    return name + _flags((cmd.long_form, "LONG"))


def _hint(cmd: Command) -> str:
    """A short note for the comment: buttons compared, system-register bits written."""
    if isinstance(cmd, _DATA_COMMANDS):
        dst, src = cmd.dst, cmd.src
        if isinstance(dst, Ram) and isinstance(src, Data) and len(src.data) == 2:
            if dst.address == ADDR.BUTTONS:
                buttons = Button.from_ram(src.data)
                names = "|".join(b.name for b in Button if b and b in buttons and b.name)
                return f"buttons {names or 'none'}"
            if dst.address == ADDR.SYSTEM and isinstance(cmd, Move):
                reg = SystemRegister.from_bytes(src.data)
                bits = [
                    name
                    for name, on in (
                        ("ICS_F", reg.ics_output),
                        ("ROM_F", reg.rom_run),
                        ("MSG_F", reg.message),
                        ("VEC_F", reg.vector_jump),
                        ("LED", reg.led),
                    )
                    if on
                ]
                return f"system {' '.join(bits) or '-'}, {reg.frame_period_ms} ms"
    return ""


# --------------------------------------------------------------------------- sweep


@dataclass(frozen=True, slots=True)
class SweepItem:
    address: int
    data: bytes
    command: Command | None
    note: str = ""
    """Why the bytes here are not an instruction, when they nearly are (a bad checksum)."""


def _bad_sum_note(data: bytes, i: int) -> str:
    """A note when the frame its SIZE byte spans at ``data[i]`` would be a command but for its
    checksum (a damaged frame, not data), else ""."""
    size = data[i]
    frame = data[i : i + size]
    if size < 3 or len(frame) < size:
        return ""
    fixed = frame[:-1] + bytes((checksum(frame[:-1]),))
    try:
        decode_command(fixed)
    except ProtocolError:
        return ""
    return (
        f"{size}-byte frame with a bad checksum {frame[-1]:02X} (the sum is "
        f"{fixed[-1]:02X}): kept as bytes"
    )


def sweep(data: bytes, origin: int) -> list[SweepItem]:
    items: list[SweepItem] = []
    i, n = 0, len(data)
    while i < n:
        note = ""
        try:
            frame = frame_at(data, i)
            cmd: Command | None = decode_command(frame)
        except ChecksumError:
            cmd, note = None, _bad_sum_note(data, i)
        except ProtocolError:
            cmd = None
        if cmd is not None and encode_command(cmd) == frame:
            items.append(SweepItem(origin + i, frame, cmd))
            i += len(frame)
            continue
        items.append(SweepItem(origin + i, data[i : i + 1], None, note))
        i += 1
    return items


def branch_targets(items: Iterable[SweepItem]) -> set[int]:
    return {it.command.address for it in items if isinstance(it.command, (Jump, Call))}


# --------------------------------------------------------------------------- rendering


class Listing:
    """Accumulates output lines and tracks the address the text has reached."""

    def __init__(self, comments: bool, symbols: bool, labels: Mapping[int, str]) -> None:
        self.lines: list[str] = []
        self.comments = comments
        self.symbols = symbols
        self.labels = labels
        self.pc: int | None = None
        self.placed: set[int] = set()

    def comment(self, text: str) -> None:
        if self.comments:
            self.lines.append(f"; {text}" if text else ";")

    def blank(self) -> None:
        if self.lines and self.lines[-1]:
            self.lines.append("")

    def _line(self, text: str, note: str) -> None:
        if self.comments and note:
            text = f"    {text}".ljust(COMMENT_COLUMN - 1) + f" ; {note}"
        else:
            text = f"    {text}"
        self.lines.append(text)

    def _at(self, address: int) -> None:
        if self.pc != address:
            self.lines.append(f"    .org {rom_text(address)}")
            self.pc = address
        label = self.labels.get(address)
        if label is not None and address not in self.placed:
            self.lines.append(f"{label}:")
            self.placed.add(address)

    def instruction(self, item: SweepItem) -> None:
        assert item.command is not None
        self._at(item.address)
        text = format_command(item.command, label_for=self.labels.get, symbols=self.symbols)
        hint = _hint(item.command)
        self._line(text, f"{item.address:06X}" + (f"  {hint}" if hint else ""))
        self.pc = item.address + len(item.data)

    def raw(
        self,
        address: int,
        data: bytes,
        note: str = "",
        *,
        skip_erased: bool = False,
        per_line: int = BYTES_PER_LINE,
        runs: bool = True,
    ) -> None:
        """``data`` at ``address`` as ``.byte`` lines; long runs as ``.fill`` (or skipped)."""
        run_min = RUN_MIN if runs else len(data) + 1
        i = 0
        while i < len(data):
            j = i + 1
            while j < len(data) and data[j] == data[i] and address + j not in self.labels:
                j += 1
            if j - i >= run_min:
                run_at = address + i
                if run_at in self.labels:
                    self._at(run_at)
                if skip_erased and data[i] == 0xFF:
                    self.comment(f"{run_at:06X}: {j - i} erased bytes (FF)")
                else:
                    self._at(run_at)
                    self._line(f".fill {j - i}, {data[i]:02X}", f"{run_at:06X}")
                    self.pc = run_at + (j - i)
                i = j
                continue
            # a line of bytes up to the next long run, label or BYTES_PER_LINE
            end = i + 1
            while end < len(data) and end - i < per_line:
                if address + end in self.labels:
                    break
                k = end
                while k < len(data) and data[k] == data[end]:
                    k += 1
                if k - end >= run_min:
                    break
                end += 1
            self._at(address + i)
            chunk = data[i:end]
            self._line(
                ".byte " + chunk.hex(" ").upper(), note or f"{address + i:06X}  {_ascii(chunk)}"
            )
            self.pc = address + end
            i = end

    def items(self, items: list[SweepItem], skip_erased: bool = False) -> None:
        k = 0
        while k < len(items):
            item = items[k]
            if item.command is not None:
                self.instruction(item)
                k += 1
                continue
            start = k
            while k < len(items) and items[k].command is None:
                if k > start and items[k].address in self.labels:
                    break
                k += 1
            data = b"".join(it.data for it in items[start:k])
            for it in items[start:k]:
                if it.note:
                    self.comment(f"{it.address:06X}: {it.note}")
            address = item.address
            if start > 0 and isinstance(items[start - 1].command, Return) and data[0] == 0xFF:
                self.raw(address, data[:1], f"{address:06X}  end-of-motion marker")
                address, data = address + 1, data[1:]
            if data:
                self.raw(address, data, skip_erased=skip_erased)

    def text(self) -> str:
        while self.lines and not self.lines[-1]:
            self.lines.pop()
        return "\n".join(self.lines) + "\n"


def _ascii(data: bytes) -> str:
    return "".join(chr(b) if 0x20 <= b < 0x7F else "." for b in data)


def _auto_labels(items: list[SweepItem]) -> dict[int, str]:
    starts = {it.address for it in items}
    return {a: f"L_{a:06X}" for a in sorted(branch_targets(items) & starts)}


def _check_origin(origin: int, length: int) -> None:
    if not 0 <= origin < ROM_SIZE:
        raise ValueError(f"origin {origin:#x} outside ROM 0..{ROM_SIZE - 1:#x}")
    if origin + length > ROM_SIZE:
        raise ValueError(f"{length} bytes at {origin:#x} run past the end of ROM")


def disassemble(
    data: bytes | bytearray,
    origin: int = 0,
    *,
    labels: bool = True,
    comments: bool = True,
    symbols: bool = True,
) -> str:
    """Assembler text for ``data`` placed at ROM ``origin``; it assembles back to ``data``.

    ``labels``: name branch targets inside ``data`` (``L_000C15``) instead of writing their
    address; ``comments``: addresses and notes after ``;``; ``symbols``: RAM symbols
    (``RAM[BUTTONS]``) instead of numbers (``RAM[0x0350]``).
    """
    data = bytes(data)
    _check_origin(origin, len(data))
    items = sweep(data, origin)
    listing = Listing(comments, symbols, _auto_labels(items) if labels else {})
    listing.lines.append(f"    .org {rom_text(origin)}")
    listing.pc = origin
    listing.items(items)
    return listing.text()


def disassemble_frames(
    frames: Iterable[bytes | bytearray],
    origin: int = 0,
    *,
    labels: bool = True,
    comments: bool = True,
    symbols: bool = True,
) -> str:
    """:func:`disassemble` of ``frames`` laid end to end (e.g. a HeartToHeart4 motion)."""
    return disassemble(
        b"".join(bytes(f) for f in frames),
        origin,
        labels=labels,
        comments=comments,
        symbols=symbols,
    )
