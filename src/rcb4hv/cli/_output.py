"""The CLI's progress bar and plot helpers (one of each, shared by every command)."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import click

__all__ = ["PROGRESS_OPTION", "plot_to", "progress"]

PROGRESS_OPTION = click.option(
    "--progress/--no-progress",
    default=None,
    help="Draw a progress bar on stderr [default: when stderr is a terminal].",
)
"""``--progress/--no-progress`` (kwarg ``progress``: True, False or None) for :func:`progress`."""


@contextmanager
def progress(total: int, desc: str, enabled: bool | None) -> Iterator[Callable[[int, int], None]]:
    """A tqdm byte counter on stderr; yields ``update(done, total)`` (the client's progress
    callback). A changed ``total`` resizes the bar (an upload learns its size as it goes).
    ``enabled`` None: only when stderr is a terminal (a log or a pipe gets no bar)."""
    from tqdm import tqdm

    disable = None if enabled is None else not enabled  # tqdm: None = not on a non-TTY
    with tqdm(
        total=total, desc=desc, unit="B", unit_scale=True, disable=disable, file=sys.stderr
    ) as bar:

        def update(done: int, new_total: int) -> None:
            if new_total != bar.total:
                bar.total = new_total
                bar.refresh()
            bar.update(done - bar.n)

        yield update


@contextmanager
def plot_to(path: Path, figsize: tuple[float, float], dpi: int = 100) -> Iterator[Any]:
    """A matplotlib figure (headless Agg backend) whose axes the block draws on; on leaving,
    the figure is laid out and written to ``path`` (parent folders created) at ``dpi``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=figsize, dpi=dpi)
    try:
        yield ax
        fig.tight_layout()
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)
