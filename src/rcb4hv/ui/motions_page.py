"""Motions page: the board's motion slots (names and buttons from the open project),
play / stop / pause / resume, the current motion and a wait-for-end status."""

from __future__ import annotations

import asyncio
import time

from nicegui import ui

from rcb4hv.client import Robot
from rcb4hv.client.robot_types import MotionStatus
from rcb4hv.hth4 import button_label
from rcb4hv.session import StepJob
from rcb4hv.ui.context import UiContext, guarded, tid

__all__ = ["build", "motion_rows", "scan_slots"]

END_WAIT_LIMIT = 120.0


def scan_slots(robot: Robot) -> StepJob[list[int]]:
    """Which motion slots of the board's layout hold a program (first frame not erased)."""
    lay = robot.board_layout()
    used = []
    for n in range(1, lay.motion_count + 1):
        head = robot.read_rom(lay.address(n), 2)
        if head[0] not in (0x00, 0xFF):
            used.append(n)
        yield n, lay.motion_count
    return used


def motion_rows(ctx: UiContext, used: list[int]) -> list[dict[str, object]]:
    names: dict[int, tuple[str, str]] = {}
    if ctx.project is not None:
        for m in ctx.project.used_motions:
            names[m.slot] = (m.name or "", button_label(m.button_data) if m.button_data else "")
    slots = sorted(set(used) | set(names))
    lay = ctx.session.layout
    return [
        {
            "slot": n,
            "address": f"{lay.address(n):05X}",
            "name": names.get(n, ("", ""))[0],
            "button": names.get(n, ("", ""))[1],
            "on board": "yes" if n in used else "?",
        }
        for n in slots
    ]


def build(ctx: UiContext) -> None:
    session = ctx.session
    used: list[int] = []
    current = tid(ui.label("current motion: -"), "motion-current")
    status = tid(ui.label(""), "motion-status")
    with ui.row().classes("items-center"):
        count = session.layout.motion_count
        slot = tid(
            ui.number("Motion", value=1, min=1, max=count, step=1).classes("w-24"), "motion-slot"
        )
        tid(ui.button("Play", icon="play_arrow"), "motion-play").on_click(
            lambda: _play(ctx, slot.value, status, wait=False)
        )
        tid(ui.button("Play and wait", icon="playlist_play"), "motion-play-wait").on_click(
            lambda: _play(ctx, slot.value, status, wait=True)
        )
        tid(ui.button("Stop", icon="stop"), "motion-stop").on_click(
            lambda: guarded(session.submit(lambda r: r.stop_motion(reset=True)), "stop")
        )
        tid(ui.button("Pause", icon="pause"), "motion-pause").on_click(
            lambda: guarded(session.submit(lambda r: r.stop_motion(reset=False)), "pause")
        )
        tid(ui.button("Resume", icon="play_circle"), "motion-resume").on_click(
            lambda: guarded(session.submit(lambda r: r.resume_motion()), "resume")
        )
        tid(ui.button("Scan board", icon="search"), "motion-scan").on_click(lambda: scan())
    table = tid(
        ui.table(
            columns=[
                {"name": c, "label": c, "field": c, "align": "left"}
                for c in ("slot", "address", "name", "button", "on board")
            ],
            rows=motion_rows(ctx, used),
            row_key="slot",
            selection="single",
            pagination=15,
        ).props("dense flat"),
        "motion-table",
    )
    table.on_select(lambda e: slot.set_value(e.selection[0]["slot"]) if e.selection else None)

    async def scan() -> None:
        found = await guarded(session.submit_steps(scan_slots, "scan motions"), "scan")
        if found is not None:
            used[:] = found
            redraw()

    def redraw() -> None:
        table.rows = motion_rows(ctx, used)
        table.update()

    def refresh() -> None:
        st = session.state
        paused = (
            st.system is not None and not st.rom_running and st.pc >= session.layout.motion_base
        )
        what = "-" if st.motion is None else f"{st.motion}"
        current.text = f"current motion: {what}" + (" (paused)" if paused else "")

    ctx.on_project(redraw)
    ui.timer(0.2, refresh)


def _played(robot: Robot, slot: int) -> MotionStatus:
    """Play ``slot``; the program's state just after (a slot with no motion in it stops the
    program with a ROM error at once)."""
    robot.play_motion(slot)
    return robot.motion_status()


async def _play(ctx: UiContext, value: object, status: ui.label, *, wait: bool) -> None:
    session = ctx.session
    count = session.layout.motion_count
    if not isinstance(value, int | float) or value != int(value) or not 1 <= value <= count:
        ui.notify(f"a motion is a whole number 1..{count}, not {value!r}", type="warning")
        return
    slot = int(value)
    after = await guarded(session.submit(lambda r: _played(r, slot)), f"play {slot}")
    if after is None:
        return
    if after.rom_error:
        status.text = f"motion {slot}: the board's program stopped (ROM error)"
        ui.notify(
            f"motion {slot}: the board's program stopped with a ROM error at PC "
            f"{after.pc:06X} (does the slot hold a motion?); STOP sets it going again",
            type="negative",
            multi_line=True,
        )
        return
    status.text = f"motion {slot} started"
    if not wait:
        return
    status.text = f"waiting for motion {slot} to end..."
    t0 = time.monotonic()
    polls = session.state.polls
    while time.monotonic() - t0 < END_WAIT_LIMIT:
        await asyncio.sleep(0.05)
        st = session.state
        if st.polls > polls + 1 and st.motion is None:
            status.text = f"motion {slot} ended after {time.monotonic() - t0:.1f} s"
            return
    status.text = f"motion {slot} still playing after {END_WAIT_LIMIT:g} s"
