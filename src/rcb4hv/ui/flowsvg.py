"""Flowcharts drawn as SVG: a motion's control flow from its frames, and a HeartToHeart4
``CanvasData`` flowchart from its boxes and lines."""

from __future__ import annotations

import html
from collections.abc import Mapping, Sequence

from rcb4hv.asm import format_command
from rcb4hv.errors import ProtocolError
from rcb4hv.hth4 import Flowchart
from rcb4hv.protocol import ALWAYS, Call, Jump, Return, RunConstFrameServo, decode_command

__all__ = ["canvas_svg", "motion_graph", "motion_svg", "side_arrow", "svg_start"]

BOX_W, BOX_H, GAP = 300, 30, 16
LABEL_MAX = 44


def svg_start(width: int, height: int, testid: str, marker: str) -> list[str]:
    """The opening of a flowchart SVG: the element and an arrow-head marker named ``marker``."""
    return [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'font-family="monospace" font-size="11" data-testid="{testid}">',
        f'<defs><marker id="{marker}" markerWidth="8" markerHeight="8" refX="7" refY="4" '
        'orient="auto"><path d="M0,0 L8,4 L0,8 z" fill="#555"/></marker></defs>',
    ]


def side_arrow(x: int, y1: int, y2: int, bend: int, color: str, marker: str, attrs: str) -> str:
    """A branch drawn on the right of the boxes: from (x, y1) out to ``bend`` and back to
    (x, y2), with the arrow head ``marker`` and extra attributes ``attrs``."""
    return (
        f'<path d="M{x},{y1} C{bend},{y1} {bend},{y2} {x},{y2}" fill="none" '
        f'stroke="{color}" marker-end="url(#{marker})" {attrs}/>'
    )


def _short(text: str) -> str:
    return text if len(text) <= LABEL_MAX else text[: LABEL_MAX - 1] + "…"


def motion_graph(
    frames: Sequence[bytes], origin: int
) -> tuple[list[tuple[int, str]], list[tuple[int, int, str]]]:
    """Nodes ``(address, label)`` and edges ``(from index, to index or -1, kind)`` of a motion.

    kind: ``next`` (falls through), ``jump`` (taken branch), ``call`` (to a subroutine; the
    callee is outside the motion when the index is -1) and ``end`` for RETURN.
    """
    nodes: list[tuple[int, str]] = []
    cmds = []
    a = origin
    for f in frames:
        try:
            cmd = decode_command(f[: f[0]] if f else f)
            text = format_command(cmd)
            if isinstance(cmd, RunConstFrameServo):
                text = f"POSE {len(cmd.positions)} servos, {cmd.speed} frames"
        except (ProtocolError, ValueError, IndexError):
            cmd, text = None, f"DATA {f[:6].hex(' ')}"
        nodes.append((a, _short(text)))
        cmds.append(cmd)
        a += len(f)
    index = {addr: i for i, (addr, _) in enumerate(nodes)}
    edges: list[tuple[int, int, str]] = []
    for i, cmd in enumerate(cmds):
        last = i == len(nodes) - 1
        if isinstance(cmd, Return):
            edges.append((i, -1, "end"))
            continue
        if isinstance(cmd, (Jump, Call)):
            kind = "jump" if isinstance(cmd, Jump) else "call"
            edges.append((i, index.get(cmd.address, -1), kind))
            if isinstance(cmd, Jump) and cmd.condition == ALWAYS:
                continue
        if not last:
            edges.append((i, i + 1, "next"))
    return nodes, edges


def motion_svg(
    frames: Sequence[bytes],
    origin: int,
    poses: Mapping[int, int] | None = None,
    selected: int | None = None,
) -> str:
    """The motion's control flow: one box per frame, top to bottom, branches on the right.

    ``poses`` (box index -> pose number) makes those boxes selectable: each gets
    ``data-pose``; the box of pose ``selected`` is highlighted."""
    poses = poses or {}
    nodes, edges = motion_graph(frames, origin)
    height = len(nodes) * (BOX_H + GAP) + GAP
    parts = svg_start(BOX_W + 200, height, "flowchart-svg", "arr")

    def y(i: int) -> int:
        return GAP + i * (BOX_H + GAP)

    for n, (i, j, kind) in enumerate(edges):
        if kind == "next":
            parts.append(
                f'<line x1="{BOX_W // 2}" y1="{y(i) + BOX_H}" x2="{BOX_W // 2}" y2="{y(j)}" '
                'stroke="#555" marker-end="url(#arr)"/>'
            )
        elif j >= 0:
            bend = BOX_W + 20 + 14 * (n % 8)
            color = "#c62828" if kind == "jump" else "#1565c0"
            y1, y2 = y(i) + BOX_H // 2, y(j) + BOX_H // 2
            parts.append(side_arrow(BOX_W, y1, y2, bend, color, "arr", f'class="edge-{kind}"'))
    for i, (addr, label) in enumerate(nodes):
        fill = "#fff3e0" if label.startswith(("JUMP", "CALL", "RETURN")) else "#f5f5f5"
        pose = poses.get(i)
        group = ""
        if pose is not None:
            fill = "#bbdefb" if pose == selected else "#e3f2fd"
            group = f' data-pose="{pose}" style="cursor:pointer" class="pose"'
        parts.append(
            f"<g{group}>"
            f'<rect x="0" y="{y(i)}" width="{BOX_W}" height="{BOX_H}" rx="4" fill="{fill}" '
            'stroke="#777" class="node"/>'
            f'<text x="6" y="{y(i) + 19}">{addr:05X} {html.escape(label)}</text></g>'
        )
    parts.append("</svg>")
    return "".join(parts)


def canvas_svg(chart: Flowchart) -> str:
    """A HeartToHeart4 flowchart as the editor draws it: its boxes and line paths."""
    w, h = chart.size.width or 640, chart.size.height or 480
    parts = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-size="11" '
        'data-testid="canvas-svg">'
    ]
    for line in chart.lines:
        pts = " ".join(f"{p.x},{p.y}" for p in line.path)
        parts.append(f'<polyline points="{pts}" fill="none" stroke="#555"/>')
    for a in chart.activities:
        stroke = "#2e7d32" if a.motion_flag == "Start" else "#777"
        parts.append(
            f'<rect x="{a.location.x}" y="{a.location.y}" width="{a.size.width}" '
            f'height="{a.size.height}" fill="#f5f5f5" stroke="{stroke}" class="node"/>'
            f'<text x="{a.location.x + 4}" y="{a.location.y + 16}">'
            f"{html.escape(a.text or a.name or '')}</text>"
        )
    parts.append("</svg>")
    return "".join(parts)
