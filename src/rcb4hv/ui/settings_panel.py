"""Project settings on the Editor page: the start-up and low-power motions, the servo output
period, mixing and the AD calibration, each "Apply" one undoable edit
(:mod:`rcb4hv.hth4.newproject`). "Read from board"
fills the AD calibration with the board's inputs now, as HeartToHeart4's calibration reads
the sensors of the robot at rest."""

from __future__ import annotations

from collections.abc import Callable

from nicegui import ui

from rcb4hv.errors import EditError, Rcb4Error
from rcb4hv.hth4.newproject import (
    mixing_source,
    set_ad_references,
    set_low_power,
    set_mixing,
    set_output_period,
    set_startup,
)
from rcb4hv.protocol.memory import ADDR, FRAME_PERIODS_MS, SystemRegister
from rcb4hv.ui.context import UiContext, guarded, tid
from rcb4hv.ui.editor_state import Editor

__all__ = ["build"]


def build(ctx: UiContext, ed: Editor, on_change: Callable[[], None]) -> Callable[[], None]:
    """The settings panel; returns its refresh function."""

    def apply(fn: object, *args: object) -> None:
        try:
            ed.apply(fn, *args)  # type: ignore[arg-type]
        except (Rcb4Error, ValueError) as exc:
            ui.notify(str(exc), type="negative", multi_line=True)
        on_change()

    def slot_of(value: object) -> int | None:
        return None if value in (None, 0) else int(str(value))

    with tid(ui.expansion("Project settings", icon="settings"), "settings-panel").classes("w-full"):
        with ui.row().classes("items-center"):
            startup = tid(ui.select({}, label="Start-up motion"), "settings-startup")
            startup.classes("w-64")
            tid(ui.button("Apply").props("dense"), "settings-startup-apply").on_click(
                lambda: apply(set_startup, slot_of(startup.value))
            )
            low = tid(ui.select({}, label="Low-power motion"), "settings-low-power")
            low.classes("w-64")
            low_value = tid(ui.number("at AD0 <=", min=0, max=1023), "settings-low-power-value")
            tid(ui.button("Apply").props("dense"), "settings-low-power-apply").on_click(
                lambda: apply(
                    set_low_power,
                    slot_of(low.value),
                    None if low_value.value is None else int(low_value.value),
                )
            )
        with ui.row().classes("items-center"):
            period = tid(
                ui.select({ms: f"{ms} ms" for ms in FRAME_PERIODS_MS}, label="Output period"),
                "settings-period",
            ).classes("w-40")
            ui.label("a pose's frames are periods: this sets the pace of every motion").classes(
                "text-xs"
            )
            tid(ui.button("Apply").props("dense"), "settings-period-apply").on_click(
                lambda: None if period.value is None else apply(set_output_period, period.value)
            )
        with ui.row().classes("items-center"):
            ui.label("AD calibration (value at rest)").classes("text-sm")
            refs = [
                tid(ui.number(f"AD{i}", format="%d").classes("w-20"), f"settings-ad-{i}")
                for i in range(ADDR.AD_COUNT)
            ]
            tid(
                ui.button("Read from board", icon="sensors").props("dense"), "settings-ad-read"
            ).on_click(lambda: read_board())
            tid(ui.button("Apply").props("dense"), "settings-ad-apply").on_click(
                lambda: apply(
                    set_ad_references,
                    {i: int(r.value) for i, r in enumerate(refs) if r.value is not None},
                )
            )
        with ui.row().classes("items-center"):
            servo = tid(ui.select({}, label="Mixing: servo"), "settings-mix-servo").classes("w-56")
            which = tid(ui.select({1: "input 1", 2: "input 2"}, value=1), "settings-mix-input")
            source = tid(ui.input("source (AD1, 0024h, none)"), "settings-mix-source")
            rate = tid(ui.number("rate", value=1, min=-127, max=127), "settings-mix-rate")

            def mix() -> None:
                if servo.value is None:
                    return
                try:
                    where = mixing_source(source.value or "")
                except EditError as exc:
                    ui.notify(str(exc), type="negative")
                    return
                apply(set_mixing, int(servo.value), int(which.value), where, int(rate.value or 0))

            tid(ui.button("Apply").props("dense"), "settings-mix-apply").on_click(mix)

    async def read_board() -> None:
        """Fill AD1-AD10 with the board's inputs now (the robot still); AD0, the supply, keeps
        its reference."""
        values = await guarded(
            ctx.session.submit(lambda robot: robot.ad_readings().inputs, label="read AD"), "Read AD"
        )
        if values is not None:
            for r, v in list(zip(refs, values, strict=True))[1:]:
                r.value = v
            ui.notify("AD1-AD10 read from the board: Apply stores them")

    def refresh() -> None:
        if ed.session is None:
            return
        p = ed.project
        motions = {0: "(none)"} | {m.slot: f"M{m.slot:03d} {m.name}" for m in p.used_motions}
        for sel, address in (
            (startup, p.startup_motion_address),
            (low, p.low_power_motion_address),
        ):
            sel.options = motions
            at = p.motion_at(address) if address >= 0 else None
            sel.value = at.slot if at is not None else 0
            sel.update()
        low_value.value = p.low_power_value
        try:
            period.value = SystemRegister.from_word(p.system_register).frame_period_ms
        except ValueError:  # a Config that is not one word: nothing to show (Apply says why)
            period.value = None
        for r, v in zip(refs, p.adc_reference_words, strict=False):
            r.value = v
        servo.options = {
            s.device_number: f"ICS {s.device_number} {s.name}" for s in p.servos if s.in_use
        }
        servo.update()

    return refresh
