"""The live 3D view of the Servos and Remote pages: the robot follows the board.

Twice per poll period it takes the last polled servo positions (the measured values the board
reports into the servo blocks: position minus base, so in motion space, without the trim),
turns them into joint angles through the model's joint map
(:meth:`~rcb4hv.robot.RobotModel.motion_angles`; adding the trims again would count them
twice) and updates the :class:`~rcb4hv.ui.scene3d.RobotScene`
(nothing is sent when the pose did not change). A servo that reports no position keeps its last
angle. The view is rebuilt when the robot model changes (a project opened with another robot).
"""

from __future__ import annotations

from nicegui import ui

from rcb4hv.protocol import POSITION_FREE, POSITION_HOLD
from rcb4hv.robot import RobotModel
from rcb4hv.session import BoardState
from rcb4hv.ui.context import UiContext, tid
from rcb4hv.ui.scene3d import RobotScene

__all__ = ["LiveView", "live_view", "servo_pose"]


def servo_pose(state: BoardState) -> dict[int, int]:
    """Measured positions (motion space: the board reports position minus trim) by ICS number
    of the servos that report a position."""
    return {
        s.ics: s.measured for s in state.servos if s.measured not in (POSITION_FREE, POSITION_HOLD)
    }


class LiveView:
    """A :class:`RobotScene` that follows ``ctx.session``; ``name`` prefixes its test ids."""

    def __init__(self, ctx: UiContext, name: str, *, width: int = 460, height: int = 420) -> None:
        self.ctx = ctx
        self.name = name
        self.size = (width, height)
        self.view: RobotScene | None = None
        self._model: RobotModel | None = None
        self._polls = -1
        self._angles: dict[str, float] = {}
        with ui.column().classes("items-center gap-1") as self.box:
            self.caption = tid(ui.label(""), f"{name}-3d-caption").classes("text-sm text-slate-600")
            self.holder = ui.column()
        self._build()
        # twice per poll period: a new poll is shown within half a period of its arrival
        period = 0.5 / ctx.session.poll_hz if ctx.session.poll_hz > 0 else 0.1
        self.timer = ui.timer(period, self.follow)
        ctx.on_project(self._model_changed)

    def _build(self) -> None:
        self._model = self.ctx.robot
        self._angles = {}
        self._polls = -1
        self.holder.clear()
        with self.holder:
            if self._model is None:
                self.view = None
                self.caption.text = "no robot model (rcb4hv ui --robot NAME|FILE)"
                return
            self.view = RobotScene(self._model, width=self.size[0], height=self.size[1])
            tid(self.view.scene, f"{self.name}-3d")
        self.caption.text = self.ctx.robot_caption

    def _model_changed(self) -> None:
        if self.holder.is_deleted:  # its browser tab is gone
            self.ctx.off_project(self._model_changed)
        elif self.ctx.robot is not self._model:
            self._build()

    def follow(self) -> None:
        """Show the last poll (called at the poll rate)."""
        st = self.ctx.session.state
        if self.view is None or st.polls == self._polls:
            return
        self._polls = st.polls
        self._angles.update(self.view.model.motion_angles(servo_pose(st)))
        self.view.update(self._angles)


def live_view(ctx: UiContext, name: str) -> LiveView:
    """A live 3D view for a page (see :class:`LiveView`)."""
    return LiveView(ctx, name)
