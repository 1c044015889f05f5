"""The Project page's 3D preview: a motion of the open project, simulated in virtual time,
played in the 3D view with play / pause and a time scrubber; a fall (from physics) is marked.

The simulation runs once (in a worker thread) and gives a :class:`~rcb4hv.ui.playback.Playback`;
playing only picks its frames by time, so scrubbing back and forth costs nothing.
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

__all__ = ["FRAME_PERIOD_S", "Player", "build", "make_playback"]

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
        scrubber.on_value_change(lambda e: self._scrubbed(e.value))

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

    def _scrubbed(self, value: float | None) -> None:
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
    holder = ui.column()
    player: list[Player] = []
    shown: list[RobotModel | None] = [None]

    def make_view() -> None:
        holder.clear()
        player.clear()
        shown[0] = ctx.robot
        if ctx.robot is None:
            with holder:
                ui.label("no robot model (rcb4hv ui --robot NAME|FILE)")
            return
        with holder:
            view = RobotScene(ctx.robot, width=560, height=480)
            tid(view.scene, "preview-3d")
        player.append(Player(view, status, scrubber))

    def model_changed() -> None:
        if holder.is_deleted:  # its browser tab is gone
            ctx.off_project(model_changed)
        elif ctx.robot is not shown[0]:
            make_view()

    make_view()
    ctx.on_project(model_changed)

    def show_state() -> None:
        playing = bool(player) and player[0].playing
        clock.active = playing  # the clock only runs while a motion plays
        text = "Pause" if playing else "Play"
        if play.text != text:
            play.text = text
            play.props(f"icon={'pause' if playing else 'play_arrow'}")

    def tick() -> None:
        if player:
            player[0].tick()
            show_state()

    clock = ui.timer(FRAME_PERIOD_S, tick, active=False)

    def toggle() -> None:
        if player:
            player[0].toggle()
            show_state()

    play.on_click(toggle)

    async def preview() -> None:
        project, model = ctx.project, ctx.robot
        if project is None or model is None or not player:
            ui.notify("open a project (and give a robot model) first", type="warning")
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
        player[0].load(pb)
        info.text = (
            f"motion {pb.slot} {pb.name}: {pb.status}, {pb.duration:.2f} s, "
            f"{len(pb.frames)} frames ({pb.source})"
        )
        toggle()

    run.on_click(preview)
