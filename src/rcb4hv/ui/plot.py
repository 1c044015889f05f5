"""A live angle plot (ECharts) of selected servos over the last seconds."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

from nicegui import ui

__all__ = ["LEGEND_LEFT", "angle_chart", "set_series"]

LEGEND_LEFT = 70
"""Where the legend starts (px): right of the y axis's name, which is centred over the axis
at the plot's left edge (40 px)."""


def angle_chart(seconds: float = 10.0, *, x_name: str = "s") -> ui.echart:
    """An empty line chart: x in seconds (relative to now, or from the start)."""
    return ui.echart(
        {
            "animation": False,
            # one scrolling line of legend right of the y axis's "deg" (a wrapped legend
            # ran over the axis name and the plot on a narrow page)
            "legend": {"type": "scroll", "top": 0, "left": LEGEND_LEFT, "right": 10},
            "grid": {"left": 40, "right": 10, "top": 40, "bottom": 25},
            "tooltip": {"trigger": "axis"},
            "xAxis": {"type": "value", "name": x_name, "min": -seconds, "max": 0},
            # the y axis (and its name) at the left edge, not where x is 0 (the right edge)
            "yAxis": {"type": "value", "name": "deg", "axisLine": {"onZero": False}},
            "series": [],
        }
    ).classes("w-full h-64")


def set_series(
    chart: ui.echart,
    series: Mapping[int, Sequence[tuple[float, float]]],
    *,
    x_range: tuple[float, float] | None = None,
) -> None:
    """Replace the chart's lines: ``{ics: [(x, degrees), ...]}``."""
    chart.options["series"] = [
        {
            "name": f"ICS {k}",
            "type": "line",
            "showSymbol": False,
            "data": [list(p) for p in pts if not math.isnan(p[1])],
        }
        for k, pts in sorted(series.items())
    ]
    if x_range is not None:
        chart.options["xAxis"]["min"], chart.options["xAxis"]["max"] = x_range
    chart.update()


def spread(series: Mapping[int, Iterable[tuple[float, float]]]) -> float:
    """Largest max-min of any line (how much the plot moves)."""
    best = 0.0
    for pts in series.values():
        ys = [y for _, y in pts if not math.isnan(y)]
        if ys:
            best = max(best, max(ys) - min(ys))
    return best


def chart_data(chart: ui.echart) -> list[Any]:
    return list(chart.options.get("series", []))
