"""Motion lists (``.csv``): HeartToHeart4's export of a project's motion table.

Shift-JIS (cp932) text, CRLF line ends (also after the last row), every cell in double
quotes. The header has seven columns — 番号 (key), 名前 (name), ボタン番号 (button word),
ボタン記号 (button symbols), 比較 (comparison), 日付 (date), 使用率 (usage) — while every row has
an eighth, unnamed cell: the ROM address. Cell formats (inferred from the fixture):

* ``"M001"``; the name (an empty slot shows ``名称未設定`` here, although the project stores
  ``M018`` etc. as its ``Name``);
* ``"B:514"`` (decimal button word) and ``"↓+S1"`` (symbols of the set bits, in bit order:
  ↑ ↓ → ← △ × ○ □ S1 S2 S3 S4, see :func:`button_label`);
* ``"="`` for ``CompareType`` ``Equals`` (symbols for other comparisons not seen);
* ``"2023/09/22 14:06:20"`` (the project's ``Date`` without fraction and time zone);
* ``"592 (28.9 %)"``: bytes used in the 2048-byte slot (the frames, including the final
  ``FF``) and the percentage with one decimal;
* ``"2944 (00B80)"``: ROM address in decimal and as five hex digits.

Cells are parsed into typed fields; writing formats them back in the same way, so the round
trip is byte-identical. Extra cells after the eighth are kept as text.
"""

from __future__ import annotations

import csv
import io
import os
import re
from dataclasses import dataclass
from decimal import ROUND_HALF_UP, Decimal

from rcb4hv.errors import Hth4FormatError
from rcb4hv.files import read_bytes, write_atomic
from rcb4hv.hth4.model import MOTION_SLOT_SIZE, Motion
from rcb4hv.protocol.memory import Button

__all__ = [
    "BUTTON_SYMBOLS",
    "DEFAULT_HEADER",
    "MotionList",
    "MotionListEntry",
    "button_label",
    "dump_motion_list",
    "load_motion_list",
    "parse_motion_list",
    "save_motion_list",
]

ENCODING = "cp932"

DEFAULT_HEADER = ("番号", "名前", "ボタン番号", "ボタン記号", "比較", "日付", "使用率")

BUTTON_SYMBOLS: tuple[tuple[int, str], ...] = (
    (Button.UP, "↑"),
    (Button.DOWN, "↓"),
    (Button.RIGHT, "→"),
    (Button.LEFT, "←"),
    (Button.TRIANGLE, "△"),
    (Button.CROSS, "×"),
    (Button.CIRCLE, "○"),
    (Button.SQUARE, "□"),
    (Button.S1, "S1"),
    (Button.S2, "S2"),
    (Button.S3, "S3"),
    (Button.S4, "S4"),
)
"""Remote button bits (spec 10.1) and the symbols HeartToHeart4 shows for them."""

UNNAMED = "名称未設定"


def button_label(value: int) -> str:
    """Symbols of the buttons in ``value`` joined by ``+`` (``514`` → ``"↓+S1"``)."""
    return "+".join(sym for bit, sym in BUTTON_SYMBOLS if value & bit)


@dataclass(frozen=True)
class MotionListEntry:
    """One row of a motion list."""

    key: str
    name: str
    button_data: int
    button_label: str
    compare: str
    date: str
    used_bytes: int
    used_percent: Decimal
    address: int
    extra_cells: tuple[str, ...] = ()

    @classmethod
    def from_motion(cls, motion: Motion) -> MotionListEntry:
        """The row HeartToHeart4 writes for a project motion."""
        used = len(motion.rom_bytes())
        pct = (Decimal(used) * 100 / MOTION_SLOT_SIZE).quantize(
            Decimal("0.1"), rounding=ROUND_HALF_UP
        )
        date = motion.date[:19].replace("-", "/").replace("T", " ")
        return cls(
            key=motion.key,
            name=UNNAMED if motion.is_empty else (motion.name or ""),
            button_data=motion.button_data,
            button_label=button_label(motion.button_data),
            compare="=" if motion.compare_type == "Equals" else motion.compare_type,
            date=date,
            used_bytes=used,
            used_percent=pct,
            address=motion.address,
        )

    def cells(self) -> list[str]:
        if not self.used_percent.is_finite():
            raise ValueError(f"{self.key}: used_percent must be finite")
        if self.address < 0 or self.used_bytes < 0 or self.button_data < 0:
            raise ValueError(f"{self.key}: negative address, size or button word")
        return [
            self.key,
            self.name,
            f"B:{self.button_data}",
            self.button_label,
            self.compare,
            self.date,
            f"{self.used_bytes} ({format(self.used_percent, 'f')} %)",
            f"{self.address} ({self.address:05X})",
            *self.extra_cells,
        ]


@dataclass(frozen=True)
class MotionList:
    """A ``.csv`` motion list."""

    entries: tuple[MotionListEntry, ...] = ()
    header: tuple[str, ...] = DEFAULT_HEADER


_USAGE_RE = re.compile(r"([0-9]+) \(([0-9]+\.[0-9]+) %\)")
_ADDR_RE = re.compile(r"([0-9]+) \(([0-9A-Fa-f]+)\)")
_BUTTON_RE = re.compile(r"B:([0-9]+)")


def load_motion_list(path: str | os.PathLike[str]) -> MotionList:
    """Read a ``.csv`` motion list (Shift-JIS)."""
    return parse_motion_list(read_bytes(path))


def parse_motion_list(data: bytes | str) -> MotionList:
    """Parse a motion list: bytes are decoded as cp932, a str is taken as already decoded."""
    if isinstance(data, (bytes, bytearray)):
        try:
            text = bytes(data).decode(ENCODING)
        except UnicodeDecodeError as exc:
            raise Hth4FormatError(f"byte {exc.start}", "not Shift-JIS (cp932) text") from None
    else:
        text = data
    try:
        rows = list(csv.reader(io.StringIO(text, newline=""), strict=True))
    except csv.Error as exc:
        raise Hth4FormatError("", f"not a CSV file ({exc})") from None
    if not rows:
        raise Hth4FormatError("line 1", "empty file: expected the header row")
    header = tuple(rows[0])
    if not header or header[0] != DEFAULT_HEADER[0]:
        raise Hth4FormatError("line 1", f"not a motion-list header: {header[:3]!r}")
    entries = []
    for n, row in enumerate(rows[1:], 2):
        entries.append(_parse_row(row, n))
    return MotionList(entries=tuple(entries), header=header)


def _parse_row(row: list[str], line: int) -> MotionListEntry:
    if len(row) < 8:
        raise Hth4FormatError(f"line {line}", f"expected 8 cells, found {len(row)}")

    def bad(col: int, what: str) -> Hth4FormatError:
        return Hth4FormatError(f"line {line}, column {col}", f"{what}: {row[col - 1]!r}")

    m_button = _BUTTON_RE.fullmatch(row[2])
    if m_button is None:
        raise bad(3, "not a button word like 'B:0'")
    m_usage = _USAGE_RE.fullmatch(row[6])
    if m_usage is None:
        raise bad(7, "not a usage like '592 (28.9 %)'")
    m_addr = _ADDR_RE.fullmatch(row[7])
    if m_addr is None or int(m_addr.group(1)) != int(m_addr.group(2), 16):
        raise bad(8, "not an address like '2944 (00B80)'")
    entry = MotionListEntry(
        key=row[0],
        name=row[1],
        button_data=int(m_button.group(1)),
        button_label=row[3],
        compare=row[4],
        date=row[5],
        used_bytes=int(m_usage.group(1)),
        used_percent=Decimal(m_usage.group(2)),
        address=int(m_addr.group(1)),
        extra_cells=tuple(row[8:]),
    )
    return entry


def dump_motion_list(motion_list: MotionList) -> bytes:
    """The ``.csv`` file contents (cp932, CRLF, every cell quoted)."""
    buf = io.StringIO(newline="")
    writer = csv.writer(buf, quoting=csv.QUOTE_ALL, lineterminator="\r\n")
    writer.writerow(motion_list.header)
    for entry in motion_list.entries:
        writer.writerow(entry.cells())
    try:
        return buf.getvalue().encode(ENCODING)
    except UnicodeEncodeError as exc:
        bad = exc.object[exc.start : exc.end]
        raise ValueError(f"text not representable in Shift-JIS (cp932): {bad!r}") from None


def save_motion_list(motion_list: MotionList, path: str | os.PathLike[str]) -> None:
    """Write ``motion_list`` to ``path``."""
    write_atomic(path, dump_motion_list(motion_list))
