"""The Project page's actions: simulate a motion in virtual time (with its angle plot),
build and upload the ROM image (confirmation, progress bar, verify), and downloads of the
built image and of a dump of the board's ROM."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from dataclasses import dataclass, field

from nicegui import ui

from rcb4hv.client import Robot
from rcb4hv.emulator import Board
from rcb4hv.hth4 import Project
from rcb4hv.project.relocate import project_image
from rcb4hv.project.run import run_motions
from rcb4hv.project.simresult import MotionResult
from rcb4hv.project.upload import UploadResult, upload_image
from rcb4hv.protocol import position_to_degrees
from rcb4hv.ui.context import UiContext, guarded, tid
from rcb4hv.ui.plot import angle_chart, set_series

__all__ = [
    "READY_TIMEOUT_S",
    "SimulationTrace",
    "build",
    "built_image",
    "confirm",
    "simulate_motion",
]

READY_TIMEOUT_S = 5.0
"""How long the board may take to restart its ROM program after a ROM write (its boot runs
the startup motion; the fixture's takes well under a second)."""

SAMPLE_EVERY = 2
"""Keep every 2nd output period of a simulation for the plot."""


def built_image(project: Project) -> bytes | None:
    """The ROM image of ``project`` in its own HeartToHeart4 layout
    (:func:`rcb4hv.project.relocate.project_image`), or None after telling the user why it
    cannot be built."""
    try:
        return project_image(project)[0]
    except ValueError as exc:
        ui.notify(f"cannot build: {exc}", type="negative", multi_line=True)
        return None


async def confirm(question: str, detail: str, button: str, test_id: str) -> bool:
    """Ask ``question`` in a dialog (``detail`` below it); True when ``button`` (red, marked
    ``test_id``) is pressed, False on Cancel."""
    with ui.dialog() as dialog, ui.card():
        ui.label(question)
        ui.label(detail)
        with ui.row():
            tid(ui.button(button, color="red", on_click=lambda: dialog.submit(True)), test_id)
            ui.button("Cancel", on_click=lambda: dialog.submit(False))
    return bool(await dialog)


@dataclass
class _Phase:
    text: str = ""
    done: int = 0
    total: int = 0


@dataclass
class SimulationTrace:
    result: MotionResult
    series: dict[int, list[tuple[float, float]]] = field(default_factory=dict)


def simulate_motion(project: Project, slot: int) -> SimulationTrace:
    """Boot the project's image in a virtual-time emulator and play ``slot`` (the one run
    API, :func:`rcb4hv.project.run.run_motions`, and its defaults); record the angle of every
    servo at an angle (the board's own free/hold rule) each other output period, from the
    motion's start."""
    samples: list[tuple[float, dict[int, int | None]]] = []

    def listen(t: float, board: Board) -> None:
        samples.append((t, board.sent_angles()))

    image, layout = project_image(project)
    name = project.motion(slot).name or ""
    run = run_motions(image, [slot], names={slot: name}, motion_layout=layout, listener=listen)
    m = run.motions[0]
    series: dict[int, list[tuple[float, float]]] = {}
    played = [(t - m.start_s, values) for t, values in samples if t >= m.start_s]
    for t, values in played[::SAMPLE_EVERY]:
        for k, v in values.items():
            if v is not None:
                series.setdefault(k, []).append((round(t, 3), round(position_to_degrees(v), 2)))
    return SimulationTrace(m.result, series)


def build(ctx: UiContext, motions: ui.table) -> None:
    session = ctx.session
    with ui.row().classes("items-center"):
        tid(ui.button("Simulate selected motion", icon="science"), "project-simulate").on_click(
            lambda: simulate()
        )
        tid(ui.button("Build + upload to board", icon="upload"), "project-upload-rom").on_click(
            lambda: upload()
        )
        only_changed = tid(ui.checkbox("only changed pages", value=True), "upload-only-changed")
        tid(ui.button("Download built image", icon="download"), "project-download-image").on_click(
            lambda: download_image()
        )
        tid(ui.button("Download ROM dump", icon="download"), "project-download-dump").on_click(
            lambda: dump()
        )
    sim_status = tid(ui.label(""), "simulate-status")
    chart = tid(angle_chart(10.0, x_name="s from start"), "simulate-plot")
    progress = tid(ui.linear_progress(value=0, show_value=False), "upload-progress")
    upload_status = tid(ui.label(""), "upload-status")
    phase = _Phase()

    def show_progress() -> None:
        p = session.progress
        if p.total:
            progress.set_value(p.fraction)
            upload_status.text = f"{p.label}: {p.done:,} / {p.total:,} bytes"
        elif phase.total:
            progress.set_value(phase.done / phase.total)
            upload_status.text = f"{phase.text}: {phase.done:,} / {phase.total:,} bytes"

    ui.timer(0.1, show_progress)

    def selected_slot() -> int | None:
        if ctx.project is None:
            ui.notify("open a project first", type="warning")
            return None
        if motions.selected:
            return int(motions.selected[0]["slot"])
        used = ctx.project.used_motions
        return used[0].slot if used else None

    async def simulate() -> None:
        slot = selected_slot()
        if slot is None or ctx.project is None:
            return
        project = ctx.project
        sim_status.text = f"simulating motion {slot}..."
        try:
            trace = await asyncio.to_thread(simulate_motion, project, slot)
        except ValueError as exc:
            sim_status.text = f"cannot simulate: {exc}"
            return
        r = trace.result
        end = max((p[-1][0] for p in trace.series.values() if p), default=1.0)
        set_series(chart, trace.series, x_range=(0.0, max(end, 0.1)))
        sim_status.text = (
            f"motion {slot} {r.name}: {r.status} after {r.duration:.3f} s virtual time, "
            f"{r.instructions} instructions {r.detail}"
        )

    async def upload() -> None:
        if ctx.project is None:
            ui.notify("open a project first", type="warning")
            return
        image = built_image(ctx.project)
        if image is None or not await confirm(
            f"Write the ROM of the board at {session.url}?",
            "The program on the board is replaced. Each chunk is read back to verify.",
            "Write ROM",
            "upload-confirm",
        ):
            return
        changed = bool(only_changed.value)

        def set_phase(text: str) -> Callable[[int, int], None]:
            def cb(done: int, total: int) -> None:
                phase.text, phase.done, phase.total = text, done, total

            return cb

        def job(robot: Robot) -> UploadResult:
            result = upload_image(
                robot,
                image,
                only_changed=changed,
                verify=True,
                progress=set_phase("writing + verifying"),
                read_progress=set_phase("reading the board's ROM"),
            )
            robot.wait_ready(timeout=READY_TIMEOUT_S)
            robot.discover_servos()
            return result

        result = await guarded(session.submit(job, label="upload"), "upload")
        phase.total = 0
        if result is not None:
            progress.set_value(1.0)
            upload_status.text = (
                f"upload done: wrote {result.pages_written} of {result.pages_total} pages "
                f"({result.bytes_written:,} bytes), verified"
            )

    def download_image() -> None:
        if ctx.project is None:
            ui.notify("open a project first", type="warning")
            return
        image = built_image(ctx.project)
        if image is None:
            return
        name = (ctx.project_name or "project").rsplit(".", 1)[0]
        ui.download.content(image, f"{name}.bin", "application/octet-stream")

    async def dump() -> None:
        data = await guarded(session.rom_dump(), "ROM dump")
        if data is not None:
            upload_status.text = f"ROM dump: {len(data):,} bytes"
            ui.download.content(data, "rom-dump.bin", "application/octet-stream")
