"""Teach page: free servos, pose the robot by hand, capture keyframes, edit their times,
play them on the board, and save them as a new motion of the open project (then download
the .h4p and the motion's flowchart)."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from nicegui import ui

from rcb4hv.client import Robot
from rcb4hv.hth4 import Project, dump_motion_xml, dump_project, parse_project
from rcb4hv.hth4.keyframes import (
    Keyframe,
    add_motion,
    flowchart_from_keyframes,
    free_slots,
    motion_from_keyframes,
)
from rcb4hv.project.check import unlisted_servos
from rcb4hv.project.relocate import project_image, project_layout
from rcb4hv.project.run import run_motions
from rcb4hv.project.simresult import MotionResult
from rcb4hv.protocol import POSITION_MAX, POSITION_MIN, SystemRegister
from rcb4hv.session import StepJob
from rcb4hv.ui.context import UiContext, attempt, guard_leaving, guarded, tid
from rcb4hv.ui.remote_page import PAD

__all__ = ["SavedMotion", "build", "save_keyframes", "servo_mismatch"]

DEFAULT_TIME = 0.5


@dataclass(frozen=True)
class SavedMotion:
    project: Project
    data: bytes
    slot: int
    result: MotionResult


def save_keyframes(
    project: Project, keyframes: list[Keyframe], *, slot: int, name: str, button: int = 0
) -> SavedMotion:
    """Store ``keyframes`` as motion ``slot`` of ``project``, then prove the result: the saved
    bytes reload and dump back identical, the image builds, and the motion simulates to its
    end."""
    period = SystemRegister.from_word(project.system_register).frame_period_ms
    layout = project_layout(project)
    motion = motion_from_keyframes(
        keyframes, slot=slot, name=name, period_ms=period, button=button, layout=layout
    )
    data = dump_project(add_motion(project, motion))
    again = parse_project(data)
    if dump_project(again) != data:
        raise ValueError("the saved project does not round-trip byte for byte")
    image, built = project_image(again)
    result = run_motions(image, [slot], names={slot: name}, motion_layout=built).results[0]
    if result.status != "completed":
        raise ValueError(
            f"the new motion did not complete in simulation: {result.status} {result.detail}"
        )
    return SavedMotion(again, data, slot, result)


def servo_mismatch(project: Project, slot: int, keyframes: list[Keyframe]) -> str:
    """A warning when the taught motion ``slot`` and the project's servo table differ (poses
    captured from a board of another robot): the servos it moves that the table lacks (the
    board skips them, :func:`~rcb4hv.project.check.unlisted_servos`) and the servos of the
    table no keyframe holds (they keep whatever position they had). Empty when they agree."""
    unlisted = unlisted_servos(project, slot)
    moved = {k for kf in keyframes for k in kf.positions}
    missing = sorted(s.device_number for s in project.servos if s.in_use) if moved else []
    missing = [k for k in missing if k not in moved]
    parts = []
    if unlisted:
        parts.append(
            f"motion {slot} moves servos this project's servo table has not (ICS "
            f"{', '.join(map(str, unlisted))}; the board skips them)"
        )
    if missing:
        parts.append(
            f"{'it' if parts else f'motion {slot}'} leaves out the project's ICS "
            f"{', '.join(map(str, missing))} (they stay where they are)"
        )
    if not parts:
        return ""
    return "; ".join(parts) + ": poses captured from another robot? `project check` lists each"


def capture(robot: Robot) -> dict[int, int]:
    """The pose now: measured positions of every servo inside the documented range."""
    return {
        k: p
        for k, p in robot.positions(kind="measured").items()
        if POSITION_MIN <= p <= POSITION_MAX
    }


def play_job(keyframes: list[Keyframe]) -> Callable[[Robot], StepJob[None]]:
    def job(robot: Robot) -> StepJob[None]:
        for i, kf in enumerate(keyframes):
            robot.move(dict(kf.positions), kf.time)
            deadline = time.monotonic() + kf.time + 2.0
            while robot.interpolating(list(kf.positions)) and time.monotonic() < deadline:
                time.sleep(0.01)
                yield i, len(keyframes)
            yield i + 1, len(keyframes)

    return job


def build(ctx: UiContext) -> None:
    session = ctx.session
    frames: list[Keyframe] = []
    client = ui.context.client
    saved_frames: list[Keyframe] = []  # what "Save into project" last saved

    def changed() -> None:
        """The keyframes changed: a reload would lose them unless they were saved."""
        guard_leaving(client, "teach", bool(frames) and frames != saved_frames)

    ics_all = [s.ics for s in session.state.servos]
    with ui.row().classes("items-center"):
        chosen = tid(
            ui.select(ics_all, value=[], multiple=True, label="Servos to free").classes("w-72"),
            "teach-free-select",
        )
        tid(ui.button("Free chosen", icon="lock_open"), "teach-free").on_click(
            lambda: (
                guarded(session.submit(lambda r: r.free([int(k) for k in chosen.value])), "free")
                if chosen.value
                else ui.notify("choose servos first")
            )
        )
        tid(ui.button("Hold all", icon="lock"), "teach-hold").on_click(
            lambda: guarded(session.submit(lambda r: r.hold()), "hold")
        )
        tid(
            ui.button("Capture pose", icon="photo_camera", color="green"), "teach-capture"
        ).on_click(lambda: do_capture())
        tid(ui.button("Play on board", icon="play_arrow"), "teach-play").on_click(lambda: play())
        tid(ui.button("Clear", icon="delete"), "teach-clear").on_click(lambda: clear())
    count = tid(ui.label("0 keyframes"), "teach-count")

    @ui.refreshable
    def keyframe_list() -> None:
        changed()
        count.text = f"{len(frames)} keyframes"
        for i, kf in enumerate(frames):
            with ui.row().classes("items-center"):
                ui.label(f"#{i + 1}").classes("w-10")
                t = tid(
                    ui.number("time s", value=kf.time, min=0.0, max=6.0, step=0.05, format="%.2f"),
                    f"teach-time-{i}",
                ).classes("w-28")
                t.on_value_change(lambda e, i=i: set_time(i, e.value))
                ui.label(
                    f"{len(kf.positions)} servos: "
                    + ", ".join(f"{k}={p}" for k, p in list(kf.positions.items())[:6])
                    + " …"
                )
                ui.button(icon="close", on_click=lambda i=i: remove(i)).props("dense flat")

    def set_time(i: int, value: float | None) -> None:
        if value is None or i >= len(frames):
            return
        try:
            frames[i] = Keyframe(float(value), frames[i].positions, frames[i].name)
        except ValueError as exc:
            ui.notify(str(exc), type="negative")
        changed()

    def clear() -> None:
        frames.clear()
        keyframe_list.refresh()

    def remove(i: int) -> None:
        del frames[i]
        keyframe_list.refresh()

    keyframe_list()

    async def do_capture() -> None:
        pose = await guarded(session.submit(capture), "capture")
        if not pose:
            ui.notify("no servo position to capture", type="warning")
            return
        left = sorted({s.ics for s in session.state.servos} - set(pose))
        if left:  # free servos report 8000h, others nothing usable: not in the keyframe
            ui.notify(f"ICS {left} left out: no position in 3500..11500 (free?)", type="warning")
        frames.append(Keyframe(DEFAULT_TIME, pose, f"Pos{len(frames) + 1}"))
        keyframe_list.refresh()

    async def play() -> None:
        if not frames:
            ui.notify("capture a pose first", type="warning")
            return
        ui.notify(f"playing {len(frames)} keyframes on the board")
        done = session.submit_steps(play_job(list(frames)), "teach play")
        if await attempt(done, "play"):  # type: ignore[arg-type]
            ui.notify(f"played {len(frames)} keyframes on the board", type="positive")

    ui.separator()
    with ui.row().classes("items-center"):
        name = tid(ui.input("Motion name", value="taught motion"), "teach-name")
        slot = tid(ui.select([], label="Free slot").classes("w-32"), "teach-slot")
        buttons = {"none": 0, **{f"{t} ({n})": int(b) for t, b, n in PAD}}
        button = tid(
            ui.select(list(buttons), value="none", label="Button").classes("w-40"), "teach-button"
        )
        tid(ui.button("Save into project", icon="save"), "teach-save").on_click(lambda: save())
        tid(ui.button("Download .h4p", icon="download"), "teach-download").on_click(
            lambda: download()
        )
        tid(
            ui.button("Download flowchart .xml", icon="account_tree"), "teach-download-xml"
        ).on_click(lambda: download_xml())
    status = tid(ui.label(""), "teach-status")

    def slots() -> None:
        free = free_slots(ctx.project) if ctx.project is not None else []
        slot.set_options(free, value=free[0] if free else None)

    ctx.on_project(slots)
    slots()

    def save() -> None:
        if ctx.project is None:
            ui.notify("open a project on the Project page first", type="warning")
            return
        if not frames or slot.value is None:
            ui.notify("capture poses and pick a free slot first", type="warning")
            return
        try:
            saved = save_keyframes(
                ctx.project,
                list(frames),
                slot=int(slot.value),
                name=str(name.value or "taught motion"),
                button=buttons[button.value],
            )
        except ValueError as exc:
            status.text = f"not saved: {exc}"
            ui.notify(f"not saved: {exc}", type="negative", multi_line=True)
            return
        ctx.set_project(saved.project, ctx.project_name)
        saved_frames[:] = frames
        changed()
        note = servo_mismatch(saved.project, saved.slot, list(frames))
        if note:
            ui.notify(note, type="warning", multi_line=True)
        status.text = (
            f"saved as motion {saved.slot} ({len(frames)} keyframes): reloads, round-trips byte "
            f"for byte, builds, and simulates to completion in {saved.result.duration:.2f} s"
        )

    def download() -> None:
        if ctx.project is None:
            ui.notify("no project open", type="warning")
            return
        ui.download.content(dump_project(ctx.project), ctx.project_name or "project.h4p")

    def download_xml() -> None:
        if not frames or ctx.project is None:
            ui.notify("capture poses first", type="warning")
            return
        period = SystemRegister.from_word(ctx.project.system_register).frame_period_ms
        ui.download.content(dump_motion_xml(flowchart_from_keyframes(frames, period)), "motion.xml")
