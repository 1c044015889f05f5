"""A motion program drawn as SVG: one box per block, top to bottom, branches as arrows.

Each box carries ``data-block`` (its index) so a click selects it; the selected block and the
block the single-stepped program is at are highlighted. Plain jumps and branches within the
program are drawn as arrows on the right (red: conditional, grey: always), calls to other
motions as a note in the box.
"""

from __future__ import annotations

import html
import json
from collections.abc import Sequence

from rcb4hv.hth4.blocks import Block
from rcb4hv.ui.flowsvg import side_arrow, svg_start

__all__ = ["block_text", "program_svg"]

BOX_W, BOX_H, GAP = 340, 30, 12
LABEL_MAX = 50
_SKIP = ("positions", "values", "moves", "to", "if")


def block_text(block: Block) -> str:
    """One line about ``block``: its kind and its short fields."""
    f = block.fields
    parts = [block.kind]
    if block.kind == "pose":
        positions = f.get("positions")
        count = len(positions) if isinstance(positions, dict) else 0
        parts.append(f"{f.get('frames')} frames, {count} servos")
    for k, v in f.items():
        if k not in _SKIP and not (block.kind == "pose" and k == "frames"):
            parts.append(f"{k}={json.dumps(v, ensure_ascii=False)}")
    to = f.get("to")
    if isinstance(to, dict):
        parts.append("-> " + ", ".join(f"{k} {v}" for k, v in to.items()))
    if "if" in f:
        parts.append(f"if {f['if']}")
    text = " ".join(parts)
    return text if len(text) <= LABEL_MAX else text[: LABEL_MAX - 1] + "…"


def program_svg(
    blocks: Sequence[Block], selected: int | None = None, current: int | None = None
) -> str:
    """The blocks as boxes with their branch arrows; ``selected`` / ``current`` highlighted."""
    labels = {b.label: i for i, b in enumerate(blocks) if b.label is not None}
    height = len(blocks) * (BOX_H + GAP) + GAP
    parts = svg_start(BOX_W + 220, height, "program-svg", "parr")

    def y(i: int) -> int:
        return GAP + i * (BOX_H + GAP)

    for i, b in enumerate(blocks):
        to = b.fields.get("to")
        j = labels.get(to) if isinstance(to, str) else to if isinstance(to, int) else None
        if j is None or not 0 <= j < len(blocks):
            continue
        bend = BOX_W + 20 + 12 * (i % 12)
        conditional = b.fields.get("if", "always") != "always"
        color = "#c62828" if conditional else "#616161"
        y1, y2 = y(i) + BOX_H // 2, y(j) + BOX_H // 2
        attrs = f'data-from="{i}" data-to="{j}"'
        parts.append(side_arrow(BOX_W, y1, y2, bend, color, "parr", attrs))
    for i, b in enumerate(blocks):
        fill = "#e3f2fd" if b.kind == "pose" else "#f5f5f5"
        if b.kind in ("jump", "call", "return", "end") or "to" in b.fields:
            fill = "#fff3e0"
        if i == selected:
            fill = "#90caf9"
        stroke = "#2e7d32" if i == current else "#777"
        width = 3 if i == current else 1
        label = f"{b.label}: " if b.label else ""
        parts.append(
            f'<g data-block="{i}" style="cursor:pointer">'
            f'<rect x="0" y="{y(i)}" width="{BOX_W}" height="{BOX_H}" rx="4" fill="{fill}" '
            f'stroke="{stroke}" stroke-width="{width}"/>'
            f'<text x="6" y="{y(i) + 19}">{i:3d} {html.escape(label + block_text(b))}</text></g>'
        )
    parts.append("</svg>")
    return "".join(parts)
