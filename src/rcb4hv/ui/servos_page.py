"""Servos page: the live servo table (with each servo's joint from the robot model), a
degree slider with hold/free per servo, all hold/free/neutral, the live 3D view, and a live
angle plot of the selected servos over the last 10 s."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from nicegui import ui

from rcb4hv.errors import Rcb4Error
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD
from rcb4hv.robot import RobotModel
from rcb4hv.robot.servos import TRAVEL_DEG
from rcb4hv.session import BoardState
from rcb4hv.ui.context import UiContext, guarded, tid
from rcb4hv.ui.live3d import live_view
from rcb4hv.ui.plot import angle_chart, set_series

__all__ = ["COLUMNS", "build", "joint_name", "servo_rows"]

COLUMNS = ("ics", "joint", "id", "port", "trim", "measured", "degrees", "output", "state")


def joint_name(model: RobotModel | None, ics: int) -> str:
    """The joint servo ``ics`` drives in ``model`` ("-" if none)."""
    if model is None:
        return "-"
    try:
        return model.servo(ics).joint
    except KeyError:
        return "-"


def servo_rows(state: BoardState, model: RobotModel | None = None) -> list[dict[str, object]]:
    return [
        {
            "ics": s.ics,
            "joint": joint_name(model, s.ics),
            "id": s.id,
            "port": s.port,
            "trim": s.trim,
            "measured": s.measured,
            "degrees": "-" if math.isnan(s.degrees) else f"{s.degrees:.1f}",
            "output": {POSITION_HOLD: "hold", POSITION_FREE: "free"}.get(s.output, s.output),
            "state": s.state,
        }
        for s in state.servos
    ]


def build(ctx: UiContext) -> None:
    session = ctx.session
    sliders = _Sliders()
    with ui.row().classes("items-center"):
        tid(ui.button("Hold all", icon="lock"), "servos-hold-all").on_click(
            lambda: guarded(session.submit(lambda r: r.hold()), "hold all")
        )
        tid(ui.button("Free all", icon="lock_open"), "servos-free-all").on_click(
            lambda: guarded(session.submit(lambda r: r.free()), "free all")
        )
        tid(ui.button("Neutral", icon="center_focus_strong"), "servos-neutral").on_click(
            lambda: _neutral(ctx, sliders)
        )
        ics_all = [s.ics for s in session.state.servos]
        picked = tid(
            ui.select(
                ics_all,
                value=[k for k in (2, 3, 4, 5) if k in ics_all] or ics_all[:2],
                multiple=True,
                label="Plot ICS",
            ).classes("w-64"),
            "servos-plot-select",
        )
    # the table, the 3D view and the controls side by side on a wide screen; the controls
    # wrap below them on a narrower one (a laptop's 1280 px) rather than being squeezed
    with ui.row().classes("w-full items-start"):
        table = tid(
            ui.table(
                columns=[{"name": c, "label": c, "field": c} for c in COLUMNS],
                rows=servo_rows(session.state, ctx.robot),
                row_key="ics",
            ).props("dense flat"),
            "servo-table",
        )
        live_view(ctx, "servos")
        with ui.column().classes("grow").style(f"flex: 1 1 {CONTROLS_MIN_PX}px; {_MIN_WIDTH}"):
            chart = tid(angle_chart(session.history.seconds), "servo-plot")
            shown: list[int] = []

            @ui.refreshable
            def controls() -> None:
                sliders.by_ics.clear()
                shown[:] = [s.ics for s in session.state.servos]
                picked.set_options(shown, value=[k for k in (picked.value or []) if k in shown])
                for s in session.state.servos:
                    deg = 0.0 if math.isnan(s.degrees) else s.degrees
                    _servo_controls(ctx, s.ics, deg, sliders)

            controls()

    def refresh() -> None:
        table.rows = servo_rows(session.state, ctx.robot)
        table.update()
        if [s.ics for s in session.state.servos] != shown:
            controls.refresh()
        sliders.follow(session.state)

    def replot() -> None:
        sel = [int(k) for k in (picked.value or [])]
        set_series(chart, session.history.series(sel, time.monotonic()))

    ui.timer(0.1, refresh)
    ui.timer(0.25, replot)


CONTROLS_MIN_PX = 480
"""The servo controls' narrowest width (a label, a slider of at least
:data:`SLIDER_MIN_PX`, hold and free): with less room beside the table and the 3D view they
wrap below them."""
SLIDER_MIN_PX = 160
_MIN_WIDTH = f"min-width: min({CONTROLS_MIN_PX}px, 100%)"
SLIDER_STEP = 0.5
"""Degrees per step of a servo slider."""
FOLLOW_AFTER_S = 1.0
"""A slider follows its servo (moved by hand, a motion, another client) once the user has
left it alone this long: touching it then moves the servo from where it is, not from where
the slider was left."""


@dataclass
class _Sliders:
    """The Servos page's sliders by ICS number, when the user last moved each, and the ones
    the page is setting itself (no move is sent for those)."""

    by_ics: dict[int, ui.slider] = field(default_factory=dict)
    touched: dict[int, float] = field(default_factory=dict)
    following: set[int] = field(default_factory=set)

    def follow(self, state: BoardState) -> None:
        """Set each slider the user left alone to its servo's measured angle."""
        now = time.monotonic()
        for s in state.servos:
            slider = self.by_ics.get(s.ics)
            if slider is None or math.isnan(s.degrees):
                continue
            if now - self.touched.get(s.ics, 0.0) < FOLLOW_AFTER_S:
                continue
            if abs(float(slider.value) - s.degrees) >= SLIDER_STEP:
                self.show(s.ics, round(s.degrees, 1))

    def show(self, ics: int, degrees: float) -> None:
        """Set slider ``ics`` to ``degrees`` without sending a move (the servo is there, or
        the board takes it there)."""
        self.following.add(ics)
        try:
            self.by_ics[ics].value = degrees
        finally:
            self.following.discard(ics)


def _servo_controls(ctx: UiContext, ics: int, degrees: float, sliders: _Sliders) -> None:
    session = ctx.session

    def moved(value: float | None) -> None:
        if value is None or ics in sliders.following:
            return
        sliders.touched[ics] = time.monotonic()
        try:
            session.set_angle(ics, float(value))
        except (ValueError, Rcb4Error) as exc:
            ui.notify(str(exc), type="negative")

    with ui.row().classes("w-full items-center no-wrap"):
        with ui.column().classes("w-32 shrink-0 gap-0"):
            ui.label(f"ICS {ics}")
            tid(ui.label(joint_name(ctx.robot, ics)), f"joint-{ics}").classes("text-xs")
        slider = (
            tid(
                ui.slider(
                    min=-TRAVEL_DEG, max=TRAVEL_DEG, step=SLIDER_STEP, value=round(degrees, 1)
                ),
                f"slider-{ics}",
            )
            .props("label")
            .classes("grow")
            .style(f"min-width: {SLIDER_MIN_PX}px")
        )
        slider.on_value_change(lambda e: moved(e.value))
        sliders.by_ics[ics] = slider
        tid(ui.button("hold").props("dense flat").classes("shrink-0"), f"hold-{ics}").on_click(
            lambda: guarded(session.submit(lambda r: r.hold([ics])), f"hold ICS {ics}")
        )
        tid(ui.button("free").props("dense flat").classes("shrink-0"), f"free-{ics}").on_click(
            lambda: guarded(session.submit(lambda r: r.free([ics])), f"free ICS {ics}")
        )


async def _neutral(ctx: UiContext, sliders: _Sliders) -> None:
    await guarded(ctx.session.submit(lambda r: r.neutral(duration=0.5)), "neutral")
    for ics in sliders.by_ics:
        sliders.show(ics, 0.0)  # the board moves them there
