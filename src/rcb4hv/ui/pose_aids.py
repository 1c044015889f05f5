"""Posing aids of the Editor page's 3D view: hand and foot handles driven by inverse
kinematics, the pose's balance and servo loads, and easing previewed before it is applied.

* :class:`PoseHandles` puts a draggable sphere on each hand and foot
  (:func:`rcb4hv.robot.ik.effectors`). Dropping one solves the limb's IK
  (:func:`rcb4hv.robot.ik.solve`, seeded by the pose shown, the sole kept parallel where the
  leg can) for the dropped point, taken in the torso frame of the pose as it was drawn: so a
  foot dragged 2 cm moves 2 cm relative to the torso in the pose saved. The page gets the new
  joint angles as one edit (one undo step for the whole drag). A target out of reach gives the
  nearest pose and a warning.
  With "keep balance" the feet stay and the body shifts over them
  (:func:`rcb4hv.robot.wholebody.solve_balanced`).
* :func:`balance_text` is the line under the view: whether the pose stands still
  (:func:`rcb4hv.robot.balance.pose_balance`), its margin, and the servos it loads beyond their
  stall torque. The view itself draws the centre of mass over the support polygon.
* :func:`ease_preview` gives the joint angles of the poses "ease over K poses" would write, for
  the view to step through before the edit is applied.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from nicegui import ui

from rcb4hv.hth4.ease import Curve, eased_poses
from rcb4hv.hth4.model import Motion
from rcb4hv.hth4.poses import SPECIAL_POSITIONS
from rcb4hv.robot.balance import pose_balance
from rcb4hv.robot.ik import IKResult, effector_point, effectors, solve
from rcb4hv.robot.kinematics import apply, forward, invert
from rcb4hv.robot.model import RobotModel
from rcb4hv.robot.wholebody import solve_balanced
from rcb4hv.ui.scene3d import RobotScene

__all__ = ["HANDLE_RADIUS_M", "PoseHandles", "balance_text", "ease_preview"]

HANDLE_RADIUS_M = 0.009
"""A handle's radius: about a servo's width on the KXR, easy to grab, not hiding the limb."""
_COLOURS = {"hand": "#9333ea", "foot": "#db2777"}

OnPose = Callable[[dict[str, float], IKResult], None]


def balance_text(model: RobotModel, angles: Mapping[str, float]) -> tuple[str, bool]:
    """The balance line for joint ``angles`` and whether it warns."""
    b = pose_balance(model, angles)
    over = [f"{j} needs {b.torque_ratio[j]:.0%} of its stall torque" for j in b.overloaded]
    touching = ", ".join(b.contacts) or "nothing"
    text = f"{b.margin_text} ({touching})"  # the wording of `project check --balance`
    return text + "".join(f"; {o}" for o in over), not b.balanced or bool(over)


class PoseHandles:
    """Draggable hand and foot handles on ``view``; ``on_pose`` gets each drop's solution."""

    def __init__(self, view: RobotScene, on_pose: OnPose) -> None:
        self.view = view
        self.model = view.model
        self.on_pose = on_pose
        self.kinds = effectors(self.model)
        self.points = {link: effector_point(self.model, link) for link in self.kinds}
        self.drawn = {link: self._drawn_at(link) for link in self.kinds}
        self.angles: dict[str, float] = {}
        self.keep_balance = False  # move the body over the feet as the limb moves
        self.last: IKResult | None = None
        self.spheres: dict[str, Any] = {}
        with view.scene:
            for link, kind in self.kinds.items():
                sphere = ui.scene.sphere(HANDLE_RADIUS_M).material(_COLOURS[kind], opacity=0.8)
                self.spheres[link] = sphere.with_name(f"ik:{link}").draggable()
        view.scene.on_drag_end(self._dropped)
        self.show({})

    def _drawn_at(self, link: str) -> tuple[float, float, float]:
        """Where a handle is drawn in its link's frame: a hand's at its tip; a foot's beside
        the ankle, just outside the foot (the ankle itself is inside the foot's shape)."""
        px, py, pz = self.points[link]
        if self.kinds[link] != "foot":
            return (px, py, pz)
        outward = 1.0 if forward(self.model, {})[link][1][3] >= 0 else -1.0
        edge = max(
            (outward * g.pos[1] + g.size[1] / 2 for g in self.model.link(link).geoms),
            default=0.0,
        )
        return (px, py + outward * (edge + HANDLE_RADIUS_M), pz)

    def handle_position(self, link: str) -> tuple[float, float, float]:
        """Where ``link``'s handle is drawn (world frame of the view)."""
        return apply(self.view.stance.frames[link], self.drawn[link])

    def show(self, angles: Mapping[str, float]) -> None:
        """Put the handles on the pose the view shows (call after ``view.update``)."""
        self.angles = {j.name: 0.0 for j in self.model.joints} | dict(angles)
        for link, sphere in self.spheres.items():
            sphere.move(*self.handle_position(link))
            sphere.visible(True)

    def hide(self) -> None:
        """Take the handles off while the view plays something else (a preview): they
        belong to the edited pose, not to a moving robot."""
        for sphere in self.spheres.values():
            sphere.visible(False)

    def drop(self, link: str, world: tuple[float, float, float]) -> IKResult:
        """The pose with ``link``'s handle moved to ``world`` (the view's frame): its point
        moves as far as the handle did."""
        frames = self.view.stance.frames
        start = self.handle_position(link)
        point = apply(frames[link], self.points[link])
        goal = tuple(p + w - s for p, w, s in zip(point, world, start, strict=True))
        target = apply(invert(frames[self.model.root]), (goal[0], goal[1], goal[2]))
        if self.keep_balance:
            return solve_balanced(self.model, link, target, self.angles, point=self.points[link])
        return solve(self.model, link, target, self.angles, point=self.points[link])

    def _dropped(self, e: Any) -> None:
        name = str(e.object_name or "")
        if not name.startswith("ik:") or name[3:] not in self.spheres:
            return
        link = name[3:]
        result = self.drop(link, (float(e.x), float(e.y), float(e.z)))
        self.last = result
        self.on_pose(result.angles, result)


def ease_preview(
    model: RobotModel, motion: Motion, index: int, over: int, curve: Curve = "in-out"
) -> list[dict[str, float]]:
    """Joint angles of the poses that easing the move into pose ``index`` would write."""
    out = []
    for _, values in eased_poses(motion, index, over, curve):
        mapped = {
            i: v for i, v in values.items() if i in model.indices and v not in SPECIAL_POSITIONS
        }
        out.append(model.motion_angles(mapped))
    return out


class EditorAids:
    """The posing aids' controls on the Editor page, built where it is constructed: the
    balance line, the reach note and the easing row. :meth:`attach` gives them the 3D view
    (after each rebuild), :meth:`refresh` follows the selected pose (after each redraw)."""

    def __init__(self, ed: Any, edit: Callable[..., object]) -> None:
        from rcb4hv.ui.context import tid

        self.ed = ed
        self.edit = edit
        self.handles: PoseHandles | None = None
        self.balance = tid(ui.label(""), "editor-balance").classes("text-xs w-96")
        self.reach = tid(ui.label(""), "editor-reach").classes("text-xs w-96")
        self.keep = tid(
            ui.checkbox("keep balance (feet stay, body shifts over them)"), "editor-keep-balance"
        )
        self.keep.on_value_change(lambda e: self._keep(bool(e.value)))
        with ui.row().classes("items-center"):
            self.over = tid(ui.number("Ease over", value=4, min=2, max=255), "editor-ease-over")
            self.over.classes("w-24")
            self.curve = tid(
                ui.select(["in-out", "in", "out"], value="in-out"), "editor-ease-curve"
            )
            tid(ui.button("Preview ease").props("dense flat"), "editor-ease-preview").on_click(
                self.preview_ease
            )
            tid(ui.button("Ease").props("dense"), "editor-ease").on_click(self.apply_ease)

    def _keep(self, on: bool) -> None:
        if self.handles is not None:
            self.handles.keep_balance = on

    def attach(self, view: RobotScene | None) -> None:
        self.handles = None if view is None else PoseHandles(view, self._on_pose)
        if self.handles is not None:
            self.handles.keep_balance = bool(self.keep.value)

    def refresh(self) -> None:
        ed, handles = self.ed, self.handles
        if handles is None or ed.pose is None or ed.model is None:
            self.balance.text = ""
            return
        angles = ed.pose_angles()
        handles.show(angles)
        text, warn = balance_text(ed.model, handles.angles)
        self.balance.text = text
        self.balance.classes(
            replace="text-xs w-96 " + ("text-red-700" if warn else "text-green-700")
        )

    def playing(self) -> None:
        """A preview plays in the view: hide the handles until a pose is picked again."""
        if self.handles is not None:
            self.handles.hide()

    def _on_pose(self, angles: dict[str, float], result: IKResult) -> None:
        ed, handles = self.ed, self.handles
        if ed.slot is None or ed.pose is None or handles is None:
            ui.notify("pick a pose to change first", type="warning")
            return
        before = handles.angles
        changed = {j: a for j, a in angles.items() if abs(a - before.get(j, 0.0)) > 1e-9}
        from rcb4hv.hth4.edit import set_pose

        self.reach.text = "" if result.reached else result.message
        if not result.reached:
            ui.notify(result.message, type="warning")
        self.edit(
            set_pose, ed.slot, ed.pose.index, ed.model.motion_values(changed), None, ed.checks
        )

    async def preview_ease(self) -> None:
        import asyncio

        ed, handles = self.ed, self.handles
        if handles is None or ed.slot is None or ed.pose_index is None or ed.model is None:
            return
        motion = ed.project.motion(ed.slot)
        try:
            poses = ease_preview(
                ed.model, motion, ed.pose_index, int(self.over.value or 0), self.curve.value
            )
        except ValueError as exc:
            ui.notify(str(exc), type="negative")
            return
        for angles in poses:
            handles.view.update(angles)
            handles.show(angles)
            await asyncio.sleep(0.3)
        self.reach.text = f"previewed {len(poses)} eased poses: Ease writes them"

    def apply_ease(self) -> None:
        from rcb4hv.hth4.ease import ease_pose

        ed = self.ed
        if ed.slot is not None and ed.pose_index is not None:
            self.edit(
                ease_pose,
                ed.slot,
                ed.pose_index,
                int(self.over.value or 0),
                self.curve.value,
                ed.checks,
            )
