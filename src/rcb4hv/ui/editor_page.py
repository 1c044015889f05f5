"""Editor page: change a HeartToHeart4 project's motions in the browser.

Open a project file (a path on this computer, or the project opened on the Project page),
pick a motion: its flowchart shows every block, the poses selectable (other blocks are
read-only). The selected pose is drawn in 3D and gets one slider per joint (degrees, with
the raw value beside it) and its frame count. Insert / duplicate / delete / move poses,
mirror the pose or the motion (in place or into a free slot), bind remote buttons, undo and
redo. "Send pose" moves the board (or emulator) there; "Play motion" writes the edited project
to the board and plays the motion (:mod:`rcb4hv.ui.editor_play`); "Preview" plays it in 3D
in virtual time. "Save" writes the ``.h4p`` atomically (:mod:`rcb4hv.ui.editor_files`: it asks
before writing over another file, and Open before discarding unsaved edits) and offers it and
each changed plain-chain motion's flowchart ``.xml`` for download. The browser asks before
leaving while there are unsaved changes. The trim panel is :mod:`rcb4hv.ui.trim_panel`.

:class:`EditorPage` is one browser tab's page: its widgets, the edit state
(:class:`~rcb4hv.ui.editor_state.Editor`, no NiceGUI) and the preview player it shares with the
Project page (:class:`~rcb4hv.ui.preview.PreviewPlayer`).
"""

from __future__ import annotations

import asyncio
import functools
import logging
import math
from collections.abc import Callable
from typing import Any

from nicegui import ui

from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4.edit import (
    delete_pose,
    duplicate_pose,
    insert_pose,
    mirror_motion,
    mirror_pose,
    move_pose,
    new_motion_at_home,
    set_pose,
)
from rcb4hv.ui import editor_files, flow_editor, trim_panel
from rcb4hv.ui.context import UiContext, attempt, guard_leaving, on_commit, tid
from rcb4hv.ui.editor_play import play_on_board
from rcb4hv.ui.editor_state import Editor
from rcb4hv.ui.flowsvg import motion_svg
from rcb4hv.ui.playback import physics_available
from rcb4hv.ui.pose_aids import EditorAids
from rcb4hv.ui.preview import PreviewPlayer, make_playback
from rcb4hv.ui.scene3d import RobotScene

__all__ = ["EditorPage", "build"]

log = logging.getLogger(__name__)


def build(ctx: UiContext) -> None:
    EditorPage(ctx)


class EditorPage:
    """The Editor page of one browser tab (see the module docstring)."""

    def __init__(self, ctx: UiContext) -> None:
        self.ctx = ctx
        self.ed = Editor()
        self.loading = False  # True while widgets are set from the state: not user edits
        self.client = ui.context.client
        self.scene: RobotScene | None = None  # the 3D view, built when a model is known
        self._layout()
        self.redraw()

    # ------------------------------------------------------------------ layout

    def _layout(self) -> None:
        ed = self.ed
        with ui.row().classes("items-center w-full"):
            self.path_in = tid(ui.input("Project file (.h4p) on this computer"), "editor-path")
            self.path_in.classes("w-96")
            tid(ui.button("Open", icon="folder_open"), "editor-open").on_click(self.open_path)
            tid(ui.button("Edit the Project page's project"), "editor-take").on_click(
                self.take_project
            )
            tid(
                ui.checkbox("override ranges, joint limits and button bindings"), "editor-force"
            ).bind_value(ed, "force")
            self.status = tid(ui.label(ed.status()), "editor-status").classes("text-sm")
        with ui.row().classes("items-center"):
            self.motion_sel = tid(ui.select({}, label="Motion", with_input=True), "editor-motion")
            self.motion_sel.classes("w-80").on_value_change(lambda e: self.choose_motion(e.value))
            self.pose_sel = tid(ui.select({}, label="Pose"), "editor-pose").classes("w-32")
            self.pose_sel.on_value_change(lambda e: self.choose_pose(e.value))
            for label, icon, name, action in (
                ("Insert", "add", "editor-insert", self.insert),
                ("Duplicate", "content_copy", "editor-duplicate",
                 lambda: self.on_pose(duplicate_pose)),
                ("Delete", "delete", "editor-delete", lambda: self.on_pose(delete_pose)),
                ("Up", "arrow_upward", "editor-up", lambda: self.move(-1)),
                ("Down", "arrow_downward", "editor-down", lambda: self.move(1)),
                ("Mirror pose", "flip", "editor-mirror-pose", self.mirror_one),
                ("Undo", "undo", "editor-undo", lambda: self.history(ed.undo)),
                ("Redo", "redo", "editor-redo", lambda: self.history(ed.redo)),
            ):  # fmt: skip
                tid(ui.button(label, icon=icon).props("dense"), name).on_click(action)
        with ui.row().classes("w-full no-wrap items-start"):
            self.chart = tid(ui.html("", sanitize=False), "editor-flowchart")
            self.chart.style("max-height: 640px; overflow-y: auto")
            self.chart.on(
                "click",
                lambda e: self.choose_pose(int(e.args)) if e.args not in (None, "") else None,
                js_handler="(e) => emit(e.target.closest('[data-pose]')?.dataset.pose ?? '')",
            )
            with ui.column().classes("items-center"):
                self.caption = tid(ui.label(""), "editor-3d-caption")
                self.caption.classes("text-sm text-slate-600")
                self.pick = tid(
                    ui.select([], label="robot", on_change=lambda e: self.pick_robot(e.value)),
                    "editor-robot-pick",
                ).classes("min-w-[12rem]")
                self.pick.set_visibility(False)
                self.holder = ui.column()
                with ui.row().classes("items-center"):
                    tid(
                        ui.button("Preview", icon="view_in_ar").props("dense"), "editor-preview"
                    ).on_click(self.preview)
                    play = tid(ui.button("Play", icon="play_arrow").props("dense"), "editor-play")
                    can_physics = physics_available()
                    self.physics = tid(
                        ui.checkbox("with physics", value=can_physics), "editor-physics"
                    )
                    self.physics.set_enabled(can_physics)
                scrubber = tid(ui.slider(min=0, max=1, step=0.001, value=0), "editor-scrubber")
                scrubber.classes("w-96")
                self.preview_status = tid(ui.label(""), "editor-preview-status")
                self.preview_status.classes("text-xs")
                self.player = PreviewPlayer(play, scrubber, self.preview_status)
                self.aids = EditorAids(ed, self.edit)  # IK handles, balance, easing
            with ui.column().classes("grow"):
                self.frames_in = tid(
                    ui.number("Frames (output periods)", min=1, max=255), "editor-frames"
                )
                on_commit(self.frames_in, self.set_frames)
                self.joints = ui.column().classes("w-full gap-0")
        with ui.row().classes("items-center"):
            self.to_sel = tid(
                ui.select({}, label="Into slot", with_input=True), "editor-mirror-to"
            ).classes("w-48")
            self.name_in = tid(ui.input("Name"), "editor-mirror-name")
            tid(ui.button("Mirror motion", icon="flip"), "editor-mirror-motion").on_click(
                self.mirror_all
            )
            tid(ui.button("New motion", icon="note_add"), "editor-new-motion").on_click(
                self.new_motion
            )
            tid(ui.button("Send pose", icon="send"), "editor-send").on_click(self.send)
            tid(ui.button("Play motion", icon="smart_display"), "editor-play-board").on_click(
                self.play_board
            )
            tid(ui.button("Save", icon="save", color="green"), "editor-save").on_click(self.save)
            self.downloads = ui.row()
        self.trims_refresh = trim_panel.build(self.ctx, ed, on_change=self.redraw)
        self.flow_refresh = flow_editor.build(self.ctx, ed, on_change=self.redraw)

    # ------------------------------------------------------------------ editing

    def fail(self, exc: Exception) -> None:
        ui.notify(str(exc), type="negative", multi_line=True)

    def edit(self, fn: Callable[..., Any], *args: object, **kw: object) -> bool:
        """Apply the edit ``fn(project, *args, **kw)`` (one undo step), then redraw; False
        when it was refused (the reason is shown)."""
        try:
            self.ed.apply(fn, *args, **kw)
        except (Rcb4Error, ValueError) as exc:
            self.fail(exc)
            self.redraw()
            return False
        self.redraw()
        return True

    def named_robot(self) -> str | None:
        """The model named with ``rcb4hv ui --robot``; otherwise None: the editor detects
        the robot from the project it edits (a default model must not drive a mirror)."""
        return self.ctx.robot_spec

    async def open_path(self) -> None:
        await editor_files.open_path(self)

    async def take_project(self) -> None:
        await editor_files.take_project(self)

    def history(self, step: Callable[[], None]) -> None:
        step()
        self.redraw()

    def choose_motion(self, slot: object) -> None:
        if not self.loading and slot is not None:
            self.ed.select(int(str(slot)))
            self.redraw()

    def choose_pose(self, index: object) -> None:
        if not self.loading and index is not None:
            self.ed.select(self.ed.slot, int(str(index)))
            self.redraw()

    def on_pose(self, fn: Callable[..., Any]) -> None:
        ed = self.ed
        if ed.slot is not None and ed.pose_index is not None:
            self.edit(fn, ed.slot, ed.pose_index)

    def insert(self) -> None:
        ed = self.ed
        pose = ed.pose
        if ed.slot is None or pose is None:
            self.fail(ValueError("select a pose: the new one goes after it, as a copy to change"))
            return
        self.edit(insert_pose, ed.slot, pose.index + 1, pose.values, pose.speed, ed.checks)
        ed.select(ed.slot, pose.index + 1)
        self.redraw()

    def move(self, step: int) -> None:
        ed = self.ed
        if ed.slot is not None and ed.pose_index is not None:
            to = ed.pose_index + step
            self.edit(move_pose, ed.slot, ed.pose_index, to)
            if ed.session is not None and ed.session.history[-1:] == ["move pose"]:
                ed.select(ed.slot, to)
                self.redraw()

    def mirror_one(self) -> None:
        ed = self.ed
        if ed.slot is not None and ed.pose_index is not None:
            before = ed.project
            if self.edit(mirror_pose, ed.slot, ed.pose_index, ed.model, ed.checks) and (
                ed.project is before
            ):
                ui.notify(
                    f"pose {ed.pose_index + 1} is already symmetric: its mirror is the same pose"
                )

    def mirror_all(self) -> None:
        ed = self.ed
        if ed.slot is None:
            return
        to = None if self.to_sel.value in (None, 0) else int(self.to_sel.value)
        name = self.name_in.value or None
        self.edit(mirror_motion, ed.slot, ed.model, to=to, name=name, checks=ed.checks)

    def new_motion(self) -> None:
        """A new motion in the chosen free slot (else the first), one pose at home, selected."""
        ed = self.ed
        free = ed.free_slots()
        if not free:
            self.fail(ValueError("open a project with a free motion slot first"))
            return
        slot = int(self.to_sel.value) if self.to_sel.value in free else free[0]
        name = self.name_in.value or f"new motion {slot}"
        self.edit(new_motion_at_home, slot, name, checks=ed.checks)
        if slot not in ed.free_slots():
            ed.select(slot, 0)
            self.redraw()

    def restore(self, box: Any, value: int | None) -> None:
        """Show ``value`` in ``box`` again (a refused or emptied field must show the truth)."""
        self.loading = True
        try:
            box.value = value
        finally:
            self.loading = False

    def whole(self, box: Any, value: object, shown: int | None, what: str) -> int | None:
        """``value`` typed into ``box`` as a whole number; None (the box shows ``shown``
        again, with a notice unless it was emptied) when it is not one."""
        try:
            number = float(str(value))
        except ValueError:
            number = math.nan
        if value is not None and str(value).strip() != "" and number.is_integer():
            return int(number)
        if value is not None and str(value).strip() != "":
            ui.notify(f"{what}: {value} is not a whole number: kept {shown}", type="warning")
        if box is not None:
            self.restore(box, shown)
        return None

    def set_value(self, ics: int, value: object, box: Any = None) -> None:
        ed = self.ed
        pose = ed.pose
        if self.loading or ed.slot is None or ed.pose_index is None or pose is None:
            return
        shown = pose.values.get(ics)
        number = self.whole(box, value, shown, f"ICS {ics}")
        if number is None or number == shown:
            return  # the value it has: no edit (Enter and then leaving the field both commit)
        values = {ics: number}
        if self.edit(set_pose, ed.slot, ed.pose_index, values, None, ed.checks):
            notes = ed.checks.advisories(values)  # kept, but the user must know (not only a log)
            if notes:
                text = "; ".join(notes) + " (kept: only a warning)"
                ui.notify(text, type="warning", multi_line=True)

    def set_degrees(self, ics: int, degrees: object) -> None:
        if not self.loading and degrees is not None:
            self.set_value(ics, self.ed.value_for(ics, float(str(degrees))))

    def set_frames(self, value: object) -> None:
        ed = self.ed
        pose = ed.pose
        if self.loading or ed.slot is None or ed.pose_index is None or pose is None:
            return
        frames = self.whole(self.frames_in, value, pose.speed, "frames")
        if frames is None or frames == pose.speed:
            return
        self.edit(set_pose, ed.slot, ed.pose_index, None, frames, ed.checks)

    # ------------------------------------------------------------------ board, files, preview

    async def send(self) -> None:
        pose = self.ed.pose
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

        if await attempt(self.ctx.session.submit(do, label="send pose"), "Send pose"):
            ui.notify(f"pose {pose.index + 1} sent ({speed} frames)")

    async def play_board(self) -> None:
        ed = self.ed
        if ed.session is not None and ed.slot is not None:
            await play_on_board(self.ctx, ed.project, ed.slot)

    async def save(self) -> None:
        await editor_files.save(self)

    async def preview(self) -> None:
        """Simulate the edited motion in virtual time and play it in the 3D view."""
        ed = self.ed
        if ed.session is None or ed.slot is None or ed.model is None or self.scene is None:
            ui.notify("open a project with a robot model and pick a motion", type="warning")
            return
        self.preview_status.text = f"simulating motion {ed.slot}..."
        try:
            pb = await asyncio.to_thread(
                make_playback, ed.project, ed.slot, ed.model, physics=bool(self.physics.value)
            )
        except (Rcb4Error, ValueError) as exc:
            self.preview_status.text = f"cannot simulate motion {ed.slot}: {exc}"
            return
        self.aids.playing()
        self.player.load(pb)

    # ------------------------------------------------------------------ drawing

    def pick_robot(self, name: str | None) -> None:
        """The user picked one of the models an ambiguous project fits."""
        if not name or name not in self.ed.model_candidates:
            return
        try:
            self.ed.pick_robot(name)
            if name in self.ctx.robot_candidates:  # the same question on the Project page
                self.ctx.pick_robot(name)
        except Rcb4Error as exc:
            self.fail(exc)
            return
        self.rebuild_view()
        self.redraw()

    def rebuild_view(self) -> None:
        ed = self.ed
        self.holder.clear()
        self.scene = None
        self.pick.set_options(list(ed.model_candidates), value=None)
        self.pick.set_visibility(bool(ed.model_candidates))
        if ed.model is None:
            why = (
                f"the project fits {', '.join(ed.model_candidates)}: pick one here"
                if ed.model_candidates
                else ed.model_error or "no robot model"
            )
            self.caption.text = f"no 3D view: {why}"
            self.player.show(None)
            self.aids.attach(None)
            return
        self.caption.text = ed.model.title + (f" ({ed.model_note})" if ed.model_note else "")
        with self.holder:
            self.scene = RobotScene(ed.model, width=420, height=420)
            tid(self.scene.scene, "editor-3d")
        self.player.show(self.scene)
        self.aids.attach(self.scene)

    def draw_joints(self) -> None:
        self.joints.clear()
        with self.joints:
            for row in self.ed.joint_rows():
                with ui.row().classes("items-center w-full no-wrap gap-2"):
                    ui.label(row.label).classes("w-48 text-xs")
                    if not math.isnan(row.degrees):
                        slider = ui.slider(
                            min=round(row.lower, 1), max=round(row.upper, 1), step=0.1,
                            value=round(row.degrees, 1),
                        ).classes("w-64")  # fmt: skip
                        tid(slider, f"editor-joint-{row.ics}")
                        slider.on("change", lambda e, ics=row.ics: self.set_degrees(ics, e.args))
                        mark = ui.label(f"{row.degrees:.1f}°" + (" ⚠" if row.advisory else ""))
                        mark.classes("w-14 text-xs")
                        if row.advisory:
                            mark.tooltip(row.advisory)
                    raw = tid(
                        ui.number(value=row.value, format="%d").props("dense").classes("w-24"),
                        f"editor-raw-{row.ics}",
                    )
                    on_commit(raw, functools.partial(self.set_value, row.ics, box=raw))

    def redraw(self) -> None:
        """Show the edit state: every widget, the flowchart, the joints, the 3D pose."""
        ed = self.ed
        self.loading = True
        try:
            self.status.text = ed.status()
            self.motion_sel.options = ed.motion_options()
            self.motion_sel.value = ed.slot
            self.motion_sel.update()
            poses = ed.poses()
            self.pose_sel.options = {p.index: f"pose {p.index + 1}" for p in poses}
            self.pose_sel.value = ed.pose_index
            self.pose_sel.update()
            self.to_sel.options = {0: "(in place)"} | {
                s: f"M{s:03d} (free)" for s in ed.free_slots()
            }
            self.to_sel.update()
            pose = ed.pose
            self.frames_in.value = pose.speed if pose is not None else None
            blocks = ed.blocks()
            if ed.slot is not None and blocks:
                m = ed.project.motion(ed.slot)
                selectable = {b.entry: b.pose.index for b in blocks if b.pose is not None}
                self.chart.set_content(motion_svg(m.frames, m.address, selectable, ed.pose_index))
            else:
                self.chart.set_content("")
            self.draw_joints()
            self.trims_refresh()
            self.flow_refresh()
            self.player.stop()  # the view shows the edited pose, not the preview
            if self.scene is not None:
                self.scene.update(ed.pose_angles())
                self.aids.refresh()
            guard_leaving(self.client, "editor", ed.dirty)
        finally:
            self.loading = False
