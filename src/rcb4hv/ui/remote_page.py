"""Remote page: the KRC pad (press and hold sets a button in the button word, release clears
it) and the PA1-PA4 analogue sliders, with the live 3D view and angle plot to watch what the
buttons do."""

from __future__ import annotations

import time

from nicegui import ui

from rcb4hv.protocol import Button
from rcb4hv.ui.context import UiContext, guarded, tid
from rcb4hv.ui.live3d import live_view
from rcb4hv.ui.plot import angle_chart, set_series
from rcb4hv.ui.plot import spread as spread_of

__all__ = ["PAD", "Pad", "build"]

PAD: tuple[tuple[str, Button, str], ...] = (
    ("↑", Button.UP, "up"),
    ("↓", Button.DOWN, "down"),
    ("←", Button.LEFT, "left"),
    ("→", Button.RIGHT, "right"),
    ("△", Button.TRIANGLE, "triangle"),
    ("×", Button.CROSS, "cross"),
    ("○", Button.CIRCLE, "circle"),
    ("□", Button.SQUARE, "square"),
    ("S1", Button.S1, "s1"),
    ("S2", Button.S2, "s2"),
    ("S3", Button.S3, "s3"),
    ("S4", Button.S4, "s4"),
)


class Pad:
    """The buttons held in one browser tab; every change writes the whole word."""

    def __init__(self, ctx: UiContext) -> None:
        self.ctx = ctx
        self.held = Button.NONE

    async def press(self, button: Button) -> None:
        if button not in self.held:
            self.held |= button
            await self._write()

    async def release(self, button: Button) -> None:
        if button in self.held:
            self.held &= ~button
            await self._write()

    async def _write(self) -> None:
        word = self.held
        await guarded(self.ctx.session.submit(lambda r: r.set_buttons(word)), "button")


def build(ctx: UiContext) -> None:
    session = ctx.session
    pad = Pad(ctx)
    with ui.row().classes("w-full no-wrap items-start"):
        with ui.column():
            word = tid(ui.label("button word 0000h"), "remote-word")
            for group in (PAD[0:4], PAD[4:8], PAD[8:12]):
                with ui.row():
                    for text, button, name in group:
                        b = tid(ui.button(text).classes("w-16 h-12 text-lg"), f"pad-{name}")
                        b.on("pointerdown", lambda _e, btn=button: pad.press(btn))
                        for ev in ("pointerup", "pointerleave", "pointercancel"):
                            b.on(ev, lambda _e, btn=button: pad.release(btn))
            for i in range(1, 5):
                with ui.row().classes("items-center w-72"):
                    ui.label(f"PA{i}").classes("w-10")
                    s = tid(ui.slider(min=0, max=255, step=1, value=0), f"pa-{i}").props("label")
                    s.classes("grow")
                    s.on_value_change(lambda e, i=i: _set_pa(ctx, i, e.value))
        live_view(ctx, "remote")
        with ui.column().classes("grow"):
            motion = tid(ui.label("motion: -"), "remote-motion")
            chart = tid(angle_chart(session.history.seconds), "remote-plot")
            spread = tid(ui.label(""), "remote-plot-spread")

    def refresh() -> None:
        st = session.state
        word.text = f"button word {st.buttons:04X}h"
        motion.text = f"motion: {st.motion if st.motion is not None else '-'}"
        series = session.history.series([2, 3, 4, 5], time.monotonic())
        set_series(chart, series)
        spread.text = "plot range " + ", ".join(
            f"ICS {k}: {spread_of({k: pts}):.1f} deg" for k, pts in sorted(series.items())
        )

    ui.timer(0.25, refresh)


async def _set_pa(ctx: UiContext, index: int, value: float | None) -> None:
    if value is None:
        return
    v = int(value)
    await guarded(ctx.session.submit(lambda r: r.set_pa(index, v)), f"PA{index}")
