"""The 3D robot view: a reusable NiceGUI component (``ui.scene``, three.js; no npm build).

``RobotScene(model)`` draws the robot from its :class:`~rcb4hv.robot.RobotModel` (boxes,
cylinders and spheres), the ground with a 5 cm grid, the centre of mass with its plumb line
to the ground, and the support polygon. :meth:`RobotScene.update` places a pose: it sends one
message with the link transforms (nothing is re-created), and nothing at all when the pose did
not change. Colours: the centre-of-mass mark is green over the support polygon, orange outside
it, red when the pose is marked fallen.

Usage (inside a NiceGUI page)::

    view = RobotScene(model)
    view.update({"l_knee_pitch": 0.5})             # joint angles in radians
    view.update_servos({16: 8000})                 # or motion-space servo values by ICS number
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from nicegui import ui
from nicegui.elements.scene.scene_object3d import Object3D

from rcb4hv.robot import RobotModel, Transform
from rcb4hv.robot.balance import placed
from rcb4hv.robot.geometry import Soles, Stance, stance
from rcb4hv.robot.kinematics import from_xyz_rpy

__all__ = ["GRID_CELL_M", "RobotBody", "RobotScene"]

GRID_CELL_M = 0.05
"""Ground grid cell: 5 cm, so a step (a few centimetres on a 40 cm humanoid) can be read off."""
GRID_SIZE_M = 3.0
"""Ground extent: 3 m square, seven times the height of the largest built-in robot."""
GRID_SEGMENT_M = 0.2
"""The grid is drawn in 20 cm segments. Software WebGL drops a whole segment that reaches
behind the camera; the default camera's nearest visible ground is about 1.2 robot heights
(0.4-0.5 m) ahead of it, more than twice this, so no dropped segment is in view. Fewer,
longer segments also cost a software renderer less than one per cell edge."""
FIELD_OF_VIEW_DEG = 45.0
"""Vertical field of view of the camera (a moderate lens: little perspective distortion)."""
DIGITS = 5
"""Decimals sent to the browser: 10 µm for positions, 1e-5 for rotation matrix entries."""
_JS = Path(__file__).with_name("robot3d.js")


def _rows(t: Transform) -> list[float]:
    """The top three rows of a transform, flat and rounded (what robot3d.js reads)."""
    return [round(v, DIGITS) for row in t[:3] for v in row]


class RobotBody(Object3D, component=_JS):
    """The three.js object of one robot: link groups, centre-of-mass mark, support polygon.

    ``links``: per link a list of ``[shape, size, local transform rows, rgba]``; ``pose``: see
    :meth:`set_pose`; ``ground``: (size in metres, grid cells a side, cells per drawn grid
    segment) or None. All are kept in
    ``args`` so a re-initialised scene redraws the last pose.
    """

    def __init__(
        self,
        links: list[list[list[Any]]],
        pose: list[Any],
        ground: tuple[float, int, int] | None,
    ) -> None:
        super().__init__(links, pose, list(ground) if ground else None)

    def set_pose(self, pose: list[Any]) -> None:
        """``[link transforms, com xyz, support polygon [[x, y], ...], com inside, fallen]``."""
        self.args[1] = pose
        self.run_method("set_pose", pose)


class RobotScene:
    """A 3D view of ``model``; call :meth:`update` with each new pose."""

    def __init__(
        self,
        model: RobotModel,
        *,
        width: int = 460,
        height: int = 420,
        foot_links: Sequence[str] | None = None,
    ) -> None:
        self.model = model
        self.link_names = [link.name for link in model.links]
        self.soles = Soles.of(model, foot_links)
        self.foot_links = foot_links
        self.fallen = False
        self.updates = 0
        """Poses sent to the browser (unchanged poses are not sent)."""
        self.stance = self._stance({}, None)
        # the camera frames the robot's size: its height, or for a flat robot (a hexapod, a
        # car) its spread over the floor
        spots = [(t[0][3], t[1][3], t[2][3]) for t in self.stance.frames.values()]
        spread = max(max(p[k] for p in spots) - min(p[k] for p in spots) for k in (0, 1))
        h = max(max(p[2] for p in spots), self.stance.com[2] * 2, 0.7 * spread, 0.1)
        self.scene = ui.scene(
            width,
            height,
            grid=False,
            camera=ui.scene.perspective_camera(fov=FIELD_OF_VIEW_DEG, near=h / 10, far=h * 100),
            background_color="#f1f5f9",
        )
        # in front of the robot (+x), to its left (+y), a little above: the whole robot in view
        # (distance 1.8 h fits 1.5 h in a 45° field of view)
        self.scene.move_camera(x=1.5 * h, y=0.9 * h, z=0.8 * h, look_at_z=0.45 * h, duration=0.0)
        self._sent = self._payload(self.stance)
        with self.scene:
            cells = round(GRID_SIZE_M / GRID_CELL_M)
            ground = (GRID_SIZE_M, cells, round(GRID_SEGMENT_M / GRID_CELL_M))
            self.body = RobotBody(self._links(), self._sent, ground)

    def _links(self) -> list[list[list[Any]]]:
        return [
            [
                [g.shape, list(g.size), _rows(from_xyz_rpy(g.pos, g.rpy)), list(g.rgba)]
                for g in self.model.link(name).geoms
            ]
            for name in self.link_names
        ]

    def _payload(self, st: Stance) -> list[Any]:
        return [
            [_rows(st.frames[name]) for name in self.link_names],
            [round(c, DIGITS) for c in st.com],
            [[round(x, DIGITS), round(y, DIGITS)] for x, y in st.support],
            st.com_inside,
            self.fallen,
        ]

    def update(
        self,
        angles: Mapping[str, float],
        base: Transform | None = None,
        *,
        fallen: bool = False,
    ) -> Stance:
        """Show joint ``angles`` (radians by joint name; missing joints at 0) with the base at
        ``base`` (None: feet on the ground); ``fallen`` marks a fall."""
        self.fallen = fallen
        self.stance = self._stance(angles, base)
        payload = self._payload(self.stance)
        if payload != self._sent:
            self._sent = payload
            self.body.set_pose(payload)
            self.updates += 1
        return self.stance

    def _stance(self, angles: Mapping[str, float], base: Transform | None) -> Stance:
        """The pose placed in the world: at ``base``, or set down on the floor as the balance
        line under the view sets it (:func:`rcb4hv.robot.balance.placed`), so the view's
        centre-of-mass mark and support polygon and that line never disagree."""
        if base is not None:
            return stance(self.model, angles, base, self.soles)
        return placed(self.model, angles, self.foot_links)

    def update_servos(self, values: Mapping[int, int]) -> Stance:
        """Show the pose of motion-space servo ``values`` by ICS number (a motion's pose, the
        board's block outputs or measured positions: before the trim; unmapped ignored)."""
        return self.update(self.model.motion_angles(values))
