"""Editor page: change a HeartToHeart4 project's motions in the browser.

Open a project file (a path on this computer, or the project opened on the Project page),
pick a motion: its flowchart shows every block, the poses selectable (other blocks are
read-only). The selected pose is drawn in 3D and gets one slider per joint (degrees, with
the raw value beside it) and its frame count. Insert / duplicate / delete / move poses,
mirror the pose or the motion (in place or into a free slot), bind remote buttons, undo and
redo. "Send pose" moves the board (or emulator) there; "Play motion" writes the edited project
to the board and plays the motion (:mod:`rcb4hv.ui.editor_play`); "Preview" plays it in 3D
in virtual time. "Save" writes the ``.h4p`` atomically and offers it and
each changed plain-chain motion's flowchart ``.xml`` for download. The browser asks before
leaving while there are unsaved changes. The trim panel is :mod:`rcb4hv.ui.trim_panel`.
"""

from __future__ import annotations

import asyncio
import logging
import math
from collections.abc import Callable
from pathlib import Path

from nicegui import ui

from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import BUTTON_SYMBOLS, dump_project
from rcb4hv.hth4.edit import (
    bind_button,
    delete_pose,
    duplicate_pose,
    insert_pose,
    mirror_motion,
    mirror_pose,
    move_pose,
    set_pose,
)
from rcb4hv.robot import RobotModel
from rcb4hv.ui import flow_editor, trim_panel
from rcb4hv.ui.context import UiContext, attempt, tid
from rcb4hv.ui.editor_play import play_on_board
from rcb4hv.ui.editor_state import Editor
from rcb4hv.ui.flowsvg import motion_svg
from rcb4hv.ui.playback import physics_available
from rcb4hv.ui.preview import FRAME_PERIOD_S, Player, make_playback
from rcb4hv.ui.scene3d import RobotScene

__all__ = ["build"]

log = logging.getLogger(__name__)

LEAVE_GUARD = (
    "window.onbeforeunload = {on} ? (e) => {{ e.preventDefault(); e.returnValue = ''; }} : null"
)
"""Browsers show their own "leave site?" question when onbeforeunload cancels the event."""


def build(ctx: UiContext) -> None:
    ed = Editor()
    loading = [False]
    guard = [False]  # whether the browser is asked to confirm leaving
    client = ui.context.client

    def fail(exc: Exception) -> None:
        ui.notify(str(exc), type="negative", multi_line=True)

    def edit(fn: object, *args: object, **kw: object) -> None:
        try:
            ed.apply(fn, *args, **kw)  # type: ignore[arg-type]
        except (Rcb4Error, ValueError) as exc:
            fail(exc)
        redraw()

    # ------------------------------------------------------------------ layout
    with ui.row().classes("items-center w-full"):
        path_in = tid(ui.input("Project file (.h4p) on this computer"), "editor-path")
        path_in.classes("w-96")
        tid(ui.button("Open", icon="folder_open"), "editor-open").on_click(lambda: open_path())
        tid(ui.button("Edit the Project page's project"), "editor-take").on_click(
            lambda: take_project()
        )
        tid(ui.checkbox("override ranges and joint limits"), "editor-force").bind_value(ed, "force")
        status = tid(ui.label(ed.status()), "editor-status").classes("text-sm")
    with ui.row().classes("items-center"):
        motion_sel = tid(ui.select({}, label="Motion", with_input=True), "editor-motion")
        motion_sel.classes("w-80").on_value_change(lambda e: choose_motion(e.value))
        pose_sel = tid(ui.select({}, label="Pose"), "editor-pose").classes("w-32")
        pose_sel.on_value_change(lambda e: choose_pose(e.value))
        for label, icon, name, action in (
            ("Insert", "add", "editor-insert", lambda: insert()),
            ("Duplicate", "content_copy", "editor-duplicate", lambda: on_pose(duplicate_pose)),
            ("Delete", "delete", "editor-delete", lambda: on_pose(delete_pose)),
            ("Up", "arrow_upward", "editor-up", lambda: move(-1)),
            ("Down", "arrow_downward", "editor-down", lambda: move(1)),
            ("Mirror pose", "flip", "editor-mirror-pose", lambda: mirror_one()),
            ("Undo", "undo", "editor-undo", lambda: history(ed.undo)),
            ("Redo", "redo", "editor-redo", lambda: history(ed.redo)),
        ):
            tid(ui.button(label, icon=icon).props("dense"), name).on_click(action)
    with ui.row().classes("w-full no-wrap items-start"):
        chart = tid(ui.html("", sanitize=False), "editor-flowchart")
        chart.style("max-height: 640px; overflow-y: auto")
        chart.on(
            "click",
            lambda e: choose_pose(int(e.args)) if e.args not in (None, "") else None,
            js_handler="(e) => emit(e.target.closest('[data-pose]')?.dataset.pose ?? '')",
        )
        with ui.column().classes("items-center"):
            caption = tid(ui.label(""), "editor-3d-caption").classes("text-sm text-slate-600")
            holder = ui.column()
            with ui.row().classes("items-center"):
                tid(
                    ui.button("Preview", icon="view_in_ar").props("dense"), "editor-preview"
                ).on_click(lambda: preview())
                play = tid(ui.button("Play", icon="play_arrow").props("dense"), "editor-play")
                play.on_click(lambda: toggle())
                can_physics = physics_available()
                physics = tid(ui.checkbox("with physics", value=can_physics), "editor-physics")
                physics.set_enabled(can_physics)
            scrubber = tid(ui.slider(min=0, max=1, step=0.001, value=0), "editor-scrubber")
            scrubber.classes("w-96")
            preview_status = tid(ui.label(""), "editor-preview-status").classes("text-xs")
        with ui.column().classes("grow"):
            frames_in = tid(ui.number("Frames (output periods)", min=1, max=255), "editor-frames")
            frames_in.on_value_change(lambda e: set_frames(e.value))
            joints = ui.column().classes("w-full gap-0")
    with ui.row().classes("items-center"):
        to_sel = tid(
            ui.select({}, label="Mirror motion into", with_input=True), "editor-mirror-to"
        ).classes("w-48")
        name_in = tid(ui.input("Name of the mirror"), "editor-mirror-name")
        tid(ui.button("Mirror motion", icon="flip"), "editor-mirror-motion").on_click(
            lambda: mirror_all()
        )
        buttons_sel = tid(
            ui.select({bit: sym for bit, sym in BUTTON_SYMBOLS}, label="Remote buttons",
                      multiple=True),
            "editor-buttons",
        ).classes("w-56")  # fmt: skip
        tid(ui.button("Bind", icon="gamepad").props("dense"), "editor-bind").on_click(
            lambda: bind()
        )
        tid(ui.button("Send pose", icon="send"), "editor-send").on_click(lambda: send())
        tid(ui.button("Play motion", icon="smart_display"), "editor-play-board").on_click(
            lambda: play_board()
        )
        tid(ui.button("Save", icon="save", color="green"), "editor-save").on_click(lambda: save())
        downloads = ui.row()
    trims_refresh = trim_panel.build(ctx, ed, on_change=lambda: redraw())
    flow_refresh = flow_editor.build(ctx, ed, on_change=lambda: redraw())

    view: list[RobotScene | None] = [None]  # the RobotScene, built when a model is known
    player: list[Player] = []
    ui.timer(FRAME_PERIOD_S, lambda: player[0].tick() if player else None)

    # ------------------------------------------------------------------ actions
    def named_robot() -> RobotModel | None:
        """The model given with ``rcb4hv ui --robot``; otherwise None: the editor detects
        the robot from the project it edits (a default model must not drive a mirror)."""
        return ctx.robot if ctx.robot_source.startswith("--robot") else None

    def open_path() -> None:
        path = Path(path_in.value or "").expanduser()
        if path.suffix.lower() != ".h4p":
            fail(ValueError(f"{path}: not a .h4p project file"))
            return
        try:
            data = path.read_bytes()
            if len(data) > ctx.max_upload:
                raise ValueError(f"{path}: {len(data):,} bytes; the limit is {ctx.max_upload:,}")
            ed.open(data, path, named_robot())
        except (OSError, Rcb4Error, ValueError) as exc:
            fail(exc)
            return
        ui.notify(f"editing {path}")
        rebuild_view()
        redraw()

    def take_project() -> None:
        if ctx.project is None:
            fail(ValueError("no project is open on the Project page"))
            return
        ed.open(dump_project(ctx.project), None, named_robot())
        rebuild_view()
        redraw()

    def history(step: Callable[[], None]) -> None:
        step()
        redraw()

    def choose_motion(slot: object) -> None:
        if not loading[0] and slot is not None:
            ed.select(int(str(slot)))
            redraw()

    def choose_pose(index: object) -> None:
        if not loading[0] and index is not None:
            ed.select(ed.slot, int(str(index)))
            redraw()

    def on_pose(fn: object) -> None:
        if ed.slot is not None and ed.pose_index is not None:
            edit(fn, ed.slot, ed.pose_index)

    def insert() -> None:
        pose = ed.pose
        if ed.slot is None or pose is None:
            fail(ValueError("select a pose: the new one goes after it, as a copy to change"))
            return
        edit(insert_pose, ed.slot, pose.index + 1, pose.values, pose.speed, ed.checks)
        ed.select(ed.slot, pose.index + 1)
        redraw()

    def move(step: int) -> None:
        if ed.slot is not None and ed.pose_index is not None:
            to = ed.pose_index + step
            edit(move_pose, ed.slot, ed.pose_index, to)
            if ed.session is not None and ed.session.history[-1:] == ["move pose"]:
                ed.select(ed.slot, to)
                redraw()

    def mirror_one() -> None:
        if ed.slot is not None and ed.pose_index is not None:
            edit(mirror_pose, ed.slot, ed.pose_index, ed.model, ed.checks)

    def mirror_all() -> None:
        if ed.slot is None:
            return
        to = None if to_sel.value in (None, 0) else int(to_sel.value)
        name = name_in.value or None
        edit(mirror_motion, ed.slot, ed.model, to=to, name=name, checks=ed.checks)

    def bind() -> None:
        """Bind the motion to the chosen buttons (none: unbind)."""
        if ed.slot is not None:
            word = sum(int(b) for b in buttons_sel.value or [])
            edit(bind_button, ed.slot, word, force=ed.force)

    def set_value(ics: int, value: object) -> None:
        if loading[0] or value is None or ed.slot is None or ed.pose_index is None:
            return
        edit(set_pose, ed.slot, ed.pose_index, {ics: int(float(str(value)))}, None, ed.checks)

    def set_degrees(ics: int, degrees: object) -> None:
        if not loading[0] and degrees is not None:
            set_value(ics, ed.value_for(ics, float(str(degrees))))

    def set_frames(value: object) -> None:
        if loading[0] or value is None or ed.slot is None or ed.pose_index is None:
            return
        edit(set_pose, ed.slot, ed.pose_index, None, int(float(str(value))), ed.checks)

    async def send() -> None:
        pose = ed.pose
        if pose is None:
            return
        values, speed = pose.values, pose.speed

        def do(robot: object) -> None:
            from rcb4hv.client import Robot

            assert isinstance(robot, Robot)
            known = set(robot.servo_ids())
            robot.client.run_const_frame_servo(
                speed, {k: v for k, v in values.items() if k in known}
            )

        if await attempt(ctx.session.submit(do, label="send pose"), "Send pose"):
            ui.notify(f"pose {pose.index + 1} sent ({speed} frames)")

    async def play_board() -> None:
        if ed.session is not None and ed.slot is not None:
            await play_on_board(ctx, ed.project, ed.slot)

    def save() -> None:
        target = Path(path_in.value).expanduser() if path_in.value else None
        if target is not None and target.suffix.lower() != ".h4p":
            fail(ValueError(f"{target}: save to a .h4p file"))
            return
        try:
            saved, charts = ed.save(target)
        except (OSError, Rcb4Error, ValueError) as exc:
            fail(exc)
            return
        path_in.value = str(saved)
        ctx.set_project(ed.project, saved.name)
        downloads.clear()
        with downloads:
            data = saved.read_bytes()
            tid(
                ui.button(f"{saved.name}", icon="download").props("flat dense"),
                "editor-download-h4p",
            ).on_click(lambda: ui.download.content(data, saved.name))
            for i, (name, xml) in enumerate(sorted(charts.items())):
                tid(
                    ui.button(name, icon="download").props("flat dense"), f"editor-download-xml-{i}"
                ).on_click(lambda xml=xml, name=name: ui.download.content(xml, name))
        ui.notify(f"saved {saved}")
        redraw()

    def toggle() -> None:
        if player and player[0].playback is not None:
            player[0].toggle()
            play.text = "Pause" if player[0].playing else "Play"

    async def preview() -> None:
        """Simulate the edited motion in virtual time and play it in the 3D view."""
        if ed.session is None or ed.slot is None or ed.model is None or not player:
            ui.notify("open a project with a robot model and pick a motion", type="warning")
            return
        preview_status.text = f"simulating motion {ed.slot}..."
        try:
            pb = await asyncio.to_thread(
                make_playback, ed.project, ed.slot, ed.model, physics=bool(physics.value)
            )
        except (Rcb4Error, ValueError) as exc:
            preview_status.text = f"cannot simulate motion {ed.slot}: {exc}"
            return
        player[0].load(pb)
        toggle()

    # ------------------------------------------------------------------ drawing
    def rebuild_view() -> None:
        holder.clear()
        player.clear()
        view[0] = None
        if ed.model is None:
            caption.text = f"no 3D view: {ed.model_error or 'no robot model'}"
            return
        caption.text = ed.model.title
        with holder:
            scene = RobotScene(ed.model, width=420, height=420)
            tid(scene.scene, "editor-3d")
        view[0] = scene
        player.append(Player(scene, preview_status, scrubber))

    def draw_joints() -> None:
        joints.clear()
        with joints:
            for row in ed.joint_rows():
                with ui.row().classes("items-center w-full no-wrap gap-2"):
                    ui.label(row.label).classes("w-48 text-xs")
                    if not math.isnan(row.degrees):
                        slider = ui.slider(
                            min=round(row.lower, 1), max=round(row.upper, 1), step=0.1,
                            value=round(row.degrees, 1),
                        ).classes("w-64")  # fmt: skip
                        tid(slider, f"editor-joint-{row.ics}")
                        slider.on("change", lambda e, ics=row.ics: set_degrees(ics, e.args))
                        ui.label(f"{row.degrees:.1f}°").classes("w-14 text-xs")
                    raw = tid(
                        ui.number(value=row.value, format="%d").props("dense").classes("w-24"),
                        f"editor-raw-{row.ics}",
                    )
                    raw.on_value_change(lambda e, ics=row.ics: set_value(ics, e.value))

    def redraw() -> None:
        loading[0] = True
        try:
            status.text = ed.status()
            motion_sel.options = ed.motion_options()
            motion_sel.value = ed.slot
            motion_sel.update()
            poses = ed.poses()
            pose_sel.options = {p.index: f"pose {p.index + 1}" for p in poses}
            pose_sel.value = ed.pose_index
            pose_sel.update()
            free = {0: "(in place)"} | {s: f"M{s:03d} (free)" for s in ed.free_slots()}
            to_sel.options = free
            to_sel.update()
            if ed.slot is not None:
                word = ed.project.motion(ed.slot).button_data
                buttons_sel.value = [bit for bit, _ in BUTTON_SYMBOLS if word & bit]
            pose = ed.pose
            frames_in.value = pose.speed if pose is not None else None
            blocks = ed.blocks()
            if ed.slot is not None and blocks:
                m = ed.project.motion(ed.slot)
                selectable = {b.entry: b.pose.index for b in blocks if b.pose is not None}
                chart.set_content(motion_svg(m.frames, m.address, selectable, ed.pose_index))
            else:
                chart.set_content("")
            draw_joints()
            trims_refresh()
            flow_refresh()
            scene = view[0]
            if player:
                player[0].playing = False
                play.text = "Play"
            if scene is not None:
                scene.update(ed.pose_angles())
            if ed.dirty != guard[0]:
                guard[0] = ed.dirty
                client.run_javascript(LEAVE_GUARD.format(on="true" if ed.dirty else "false"))
        finally:
            loading[0] = False

    redraw()
