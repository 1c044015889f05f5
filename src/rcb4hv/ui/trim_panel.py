"""The Editor page's trim panel: the calibration workflow.

Pick a servo, free it if you want to feel it, then move it with the slider (output values,
to which the board adds its trim) until the joint sits at its true zero. "Store trim" makes
that the zero: the new trim is ``old trim + (value - 7500)``, so the output 7500 now sends the
servo where the joint is at zero (spec 9: value sent = output + base). The trim goes into the
project (an undoable edit) and onto the board, where the servo's output returns to 7500 in
the same job, so the joint stays where it was put. "Write trims to board" copies every trim
of the project into the board's RAM servo blocks (base value, +2), where it acts at once
(after an undo, say); uploading the project makes it permanent.
"""

from __future__ import annotations

from collections.abc import Callable

from nicegui import ui

from rcb4hv.client import Robot
from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4.edit import set_trim
from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD, POSITION_MAX, POSITION_MIN
from rcb4hv.protocol.memory import CENTER, SERVO
from rcb4hv.ui.context import UiContext, attempt, tid
from rcb4hv.ui.editor_state import Editor

__all__ = ["build", "new_trim", "write_trims"]


def new_trim(old: int, value: int) -> int:
    """The trim that makes output ``value`` (with trim ``old``) the new centre."""
    return old + value - CENTER


def write_trims(robot: Robot, trims: dict[int, int]) -> list[int]:
    """Write ``trims`` (ICS -> trim) into the board's servo blocks; the ICS numbers written."""
    done = []
    for info in robot.discover_servos():
        if info.ics in trims:
            address, size = SERVO.F_BASE.span(info.block_address)
            robot.write_ram(address, trims[info.ics].to_bytes(size, "little", signed=True))
            done.append(info.ics)
    return done


def _recentre(robot: Robot, ics: int, trim: int) -> None:
    """Give servo ``ics`` the trim ``trim`` and the output 7500 (its new zero)."""
    write_trims(robot, {ics: trim})
    robot.client.run_const_frame_servo(1, {ics: CENTER})


def build(ctx: UiContext, ed: Editor, on_change: Callable[[], None]) -> Callable[[], None]:
    """The panel; returns its refresh function (call it when the project changes)."""
    with tid(ui.expansion("Trims (calibration)", icon="tune"), "trim-panel").classes("w-full"):
        with ui.row().classes("items-center"):
            ics_sel = tid(ui.select({}, label="Servo"), "trim-ics").classes("w-64")
            tid(ui.button("Free", icon="pan_tool").props("dense"), "trim-free").on_click(
                lambda: torque(POSITION_FREE)
            )
            tid(ui.button("Hold", icon="lock").props("dense"), "trim-hold").on_click(
                lambda: torque(POSITION_HOLD)
            )
            position = tid(
                ui.slider(min=POSITION_MIN, max=POSITION_MAX, step=1, value=CENTER),
                "trim-position",
            ).classes("w-96")
            position.on("change", lambda e: move(e.args))
            value_label = tid(ui.label(""), "trim-value").classes("text-sm")
        with ui.row().classes("items-center"):
            tid(ui.button("Store trim", icon="save"), "trim-store").on_click(lambda: store())
            tid(ui.button("Write trims to board", icon="upload"), "trim-write").on_click(
                lambda: write()
            )

    def servos() -> dict[int, str]:
        if ed.session is None:
            return {}
        return {
            s.device_number: f"ICS {s.device_number} {s.name or ''} (trim {s.trim})"
            for s in ed.project.servos
            if s.in_use
        }

    def refresh() -> None:
        options = servos()
        if options != ics_sel.options:
            ics_sel.options = options
            ics_sel.update()
        ics = ics_sel.value
        if ics is not None and ed.session is not None:
            old = ed.project.servo(int(ics)).trim
            v = int(position.value)
            value_label.text = f"output {v}: trim {old} -> {new_trim(old, v)}"

    ics_sel.on_value_change(lambda _: refresh())

    async def torque(value: int) -> None:
        if ics_sel.value is None:
            return
        ics = int(ics_sel.value)
        await attempt(
            ctx.session.submit(lambda r: r.client.run_const_frame_servo(1, {ics: value})),
            "free" if value == POSITION_FREE else "hold",
        )

    def move(value: object) -> None:
        if ics_sel.value is None or value is None:
            return
        try:
            ctx.session.set_target(int(ics_sel.value), int(float(str(value))))
        except (Rcb4Error, ValueError) as exc:
            ui.notify(str(exc), type="negative")
        refresh()

    async def store() -> None:
        if ics_sel.value is None or ed.session is None:
            return
        ics = int(ics_sel.value)
        old = ed.project.servo(ics).trim
        trim = new_trim(old, int(position.value))
        if trim == old:  # the output is 7500: the zero is where it was
            ui.notify(
                f"ICS {ics}: trim {old} unchanged (the output is {CENTER}): nothing stored; "
                "move the servo to its true zero first"
            )
            return
        try:
            ed.apply(set_trim, ics, trim)
        except (Rcb4Error, ValueError) as exc:
            ui.notify(str(exc), type="negative")
            return
        position.value = CENTER
        refresh()
        on_change()
        # the servo takes the new trim with the output 7500 in one job: the joint stays where
        # the user put it (output 7500 with the old trim would send it back to the old zero,
        # the old output with the new trim past the new one by the same amount)
        fut = ctx.session.submit(lambda r: _recentre(r, ics, trim), label="store trim")
        if await attempt(fut, "store trim"):  # type: ignore[arg-type]
            ui.notify(f"ICS {ics}: trim {trim} stored in the project and set on the board")

    async def write() -> None:
        if ed.session is None:
            return
        trims = {s.device_number: s.trim for s in ed.project.servos if s.in_use}
        fut = ctx.session.submit(lambda r: write_trims(r, trims), label="write trims")
        if await attempt(fut, "write trims"):  # type: ignore[arg-type]
            ui.notify(f"{len(fut.result())} trims written to the board's RAM")

    return refresh
