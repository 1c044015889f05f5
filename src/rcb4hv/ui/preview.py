"""The Project page's 3D preview: a motion of the open project, simulated in virtual time,
played in the 3D view with play / pause and a time scrubber; a fall (from physics) is marked.

The simulation runs once (in a worker thread) and gives a :class:`~rcb4hv.ui.playback.Playback`;
playing only picks its frames by time, so scrubbing back and forth costs nothing.
:class:`PreviewPlayer` is the one preview player: its Play / Pause button, scrubber, status and
clock (which runs only while a motion plays) around a :class:`Player`; this page and the
Editor page both use it.
"""

from __future__ import annotations

import asyncio
import time

from nicegui import ui

from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import Project
from rcb4hv.robot import RobotModel
from rcb4hv.ui.context import UiContext, tid
from rcb4hv.ui.playback import (
    Playback,
    physics_available,
    physics_playback,
    simulated_playback,
)
from rcb4hv.ui.scene3d import RobotScene

__all__ = ["FRAME_PERIOD_S", "Player", "PreviewPlayer", "build", "make_playback"]

FRAME_PERIOD_S = 1 / 30
"""The player's clock tick: 30 frames a second, twice the rate the eye needs to see smooth
motion of a robot whose servo frames come every 10-20 ms."""


def make_playback(project: Project, slot: int, model: RobotModel, *, physics: bool) -> Playback:
    """Simulate motion ``slot`` of ``project`` for ``model``, with ``physics`` or without."""
    if physics:
        return physics_playback(project, slot, model)
    return simulated_playback(project, slot, model)


class Player:
    """Play / pause / scrub a :class:`Playback` in a :class:`RobotScene`."""

    def __init__(self, view: RobotScene, status: ui.label, scrubber: ui.slider) -> None:
        self.view = view
        self.status = status
        self.scrubber = scrubber
        self.playback: Playback | None = None
        self.t = 0.0
        self.playing = False
        self._wall: float | None = None
        self._quiet = False

    def load(self, playback: Playback) -> None:
        self.playback = playback
        self.playing = False
        self.scrubber.props["max"] = round(max(playback.duration, 0.001), 3)
        fell = playback.fell_at
        self.scrubber.props["marker-labels"] = {} if fell is None else {round(fell, 3): "fall"}
        self.seek(0.0)

    def seek(self, t: float) -> None:
        """Show the pose at ``t`` seconds (clamped to the motion)."""
        pb = self.playback
        if pb is None:
            return
        self.t = min(max(t, 0.0), pb.duration)
        f = pb.at(self.t)
        self.view.update(f.angles, f.base, fallen=pb.fallen(self.t))
        self._quiet = True
        self.scrubber.set_value(round(self.t, 3))
        self._quiet = False
        fall = "" if pb.fell_at is None else f" - FELL at {pb.fell_at:.2f} s"
        self.status.text = f"t = {self.t:.2f} / {pb.duration:.2f} s{fall}"

    def scrubbed(self, value: float | None) -> None:
        """The user moved the scrubber to ``value``: pause there."""
        if not self._quiet and value is not None:
            self.playing = False
            self.seek(float(value))

    def toggle(self) -> None:
        """Play from here (from the start at the end), or pause."""
        pb = self.playback
        if pb is None:
            return
        self.playing = not self.playing
        if self.playing and self.t >= pb.duration:
            self.seek(0.0)
        self._wall = time.monotonic()

    def tick(self) -> None:
        """Advance by the wall time since the last tick (called every FRAME_PERIOD_S)."""
        if not self.playing or self.playback is None:
            return
        now = time.monotonic()
        dt = now - (self._wall if self._wall is not None else now)
        self._wall = now
        self.seek(self.t + dt)
        if self.t >= self.playback.duration:
            self.playing = False


class PreviewPlayer:
    """The preview player's controls around a :class:`Player`: the Play / Pause button
    (``play``, its text and icon follow the player), the ``scrubber`` and ``status``, and the
    clock, active only while a motion plays. :meth:`show` puts a new 3D view behind the
    controls (None: none), :meth:`load` plays a new playback from its start, :meth:`stop`
    pauses (e.g. when the pose it shows is edited)."""

    def __init__(self, play: ui.button, scrubber: ui.slider, status: ui.label) -> None:
        self.play = play
        self.scrubber = scrubber
        self.status = status
        self.player: Player | None = None
        self.clock = ui.timer(FRAME_PERIOD_S, self._tick, active=False)
        play.on_click(self.toggle)
        scrubber.on_value_change(lambda e: self._scrubbed(e.value))

    def show(self, view: RobotScene | None) -> None:
        self.player = None if view is None else Player(view, self.status, self.scrubber)
        self._show_state()

    def load(self, playback: Playback) -> None:
        if self.player is not None:
            self.player.load(playback)
            self.toggle()

    def toggle(self) -> None:
        if self.player is not None and self.player.playback is not None:
            self.player.toggle()
        self._show_state()

    def stop(self) -> None:
        if self.player is not None:
            self.player.playing = False
        self._show_state()

    @property
    def playing(self) -> bool:
        return self.player is not None and self.player.playing

    def _scrubbed(self, value: float | None) -> None:
        if self.player is not None:
            self.player.scrubbed(value)
            self._show_state()

    def _tick(self) -> None:
        if self.player is not None:
            self.player.tick()
        self._show_state()

    def _show_state(self) -> None:
        playing = self.playing
        self.clock.active = playing  # the clock only runs while a motion plays
        text = "Pause" if playing else "Play"
        if self.play.text != text:
            self.play.text = text
            self.play.props(f"icon={'pause' if playing else 'play_arrow'}")


def build(ctx: UiContext, motions: ui.table) -> None:
    with ui.row().classes("items-center"):
        run = tid(ui.button("Preview selected motion", icon="view_in_ar"), "preview-run")
        can = physics_available()
        physics = tid(ui.checkbox("with physics", value=can), "preview-physics")
        if not can:
            physics.disable()
            physics.tooltip("needs MuJoCo: pip install 'rcb4hv[sim]'")
        play = tid(ui.button("Play", icon="play_arrow"), "preview-play")
        info = tid(ui.label("select a motion, then Preview"), "preview-info")
    scrubber = tid(ui.slider(min=0, max=1, step=0.001, value=0), "preview-scrubber")
    scrubber.classes("w-full")
    status = tid(ui.label(""), "preview-status")
    caption = tid(ui.label(""), "preview-3d-caption").classes("text-sm text-slate-600")
    holder = ui.column()
    player = PreviewPlayer(play, scrubber, status)
    shown: list[RobotModel | None] = [None]

    def make_view() -> None:
        holder.clear()
        shown[0] = ctx.robot
        # the model named, and where it came from (detected, picked, --robot, the board's)
        caption.text = ctx.robot_caption
        if ctx.robot is None:
            player.show(None)
            with holder:
                ui.label("no robot model (rcb4hv ui --robot NAME|FILE)")
            return
        with holder:
            view = RobotScene(ctx.robot, width=560, height=480)
            tid(view.scene, "preview-3d")
        player.show(view)

    def model_changed() -> None:
        if holder.is_deleted:  # its browser tab is gone
            ctx.off_project(model_changed)
        elif ctx.robot is not shown[0]:
            make_view()
        else:  # the same model, perhaps from another source (a new project)
            caption.text = ctx.robot_caption

    make_view()
    ctx.on_project(model_changed)

    async def preview() -> None:
        project, model = ctx.project, ctx.robot
        if project is None or model is None or player.player is None:
            ui.notify("open a project (and give a robot model) first", type="warning")
            return
        if ctx.robot_candidates:  # never the wrong robot in silence
            info.text = (
                f"the project fits {', '.join(ctx.robot_candidates)}: pick one on the Editor "
                "page (or rcb4hv ui --robot NAME)"
            )
            return
        slot = int(motions.selected[0]["slot"]) if motions.selected else None
        if slot is None:
            used = project.used_motions
            slot = used[0].slot if used else None
        if slot is None:
            return
        info.text = f"simulating motion {slot}..."
        try:
            pb = await asyncio.to_thread(
                make_playback, project, slot, model, physics=bool(physics.value)
            )
        except (Rcb4Error, ValueError) as exc:
            info.text = f"cannot simulate motion {slot}: {exc}"
            return
        player.load(pb)
        info.text = (
            f"motion {pb.slot} {pb.name}: {pb.status}, {pb.duration:.2f} s, "
            f"{len(pb.frames)} frames ({pb.source})"
        )

    run.on_click(preview)
