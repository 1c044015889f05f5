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

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nicegui import ui
from nicegui.elements.scene.scene_object3d import Object3D

from rcb4hv.robot import RobotModel, Transform
from rcb4hv.robot.balance import placed
from rcb4hv.robot.geometry import Soles, Stance, stance
from rcb4hv.robot.kinematics import apply, compose, from_xyz_rpy
from rcb4hv.robot.model import Vec3

__all__ = ["GRID_CELL_M", "Framing", "RobotBody", "RobotScene", "frame_points", "outline"]

GRID_CELL_M = 0.05
"""Ground grid cell: 5 cm, so a step (a few centimetres on a 40 cm humanoid) can be read off."""
GRID_SIZE_M = 3.0
"""Ground extent: 3 m square, seven times the height of the largest built-in robot."""
GRID_SEGMENT_M = 0.2
"""The grid is drawn in 20 cm segments. Software WebGL drops a whole segment that reaches
behind the camera; the camera's nearest visible ground is more than a segment ahead of it
(0.5 m for a 40 cm humanoid, 0.2-0.3 m for the flat KXR-L6 and L4T), so no dropped segment is
in view. Fewer, longer segments also cost a software renderer less than one per cell edge."""
FIELD_OF_VIEW_DEG = 45.0
"""Vertical field of view of the camera (a moderate lens: little perspective distortion)."""
VIEW_FROM: Vec3 = (1.5, 0.9, 0.35)
"""Where the camera looks from, as a direction from the robot's centre: in front of the robot
(+x), to its left (+y), a little above."""
FILL = 0.85
"""The robot's outline fills at most this share of the view's width and height."""
DIGITS = 5
"""Decimals sent to the browser: 10 µm for positions, 1e-5 for rotation matrix entries."""
_JS = Path(__file__).with_name("robot3d.js")


def _rows(t: Transform) -> list[float]:
    """The top three rows of a transform, flat and rounded (what robot3d.js reads)."""
    return [round(v, DIGITS) for row in t[:3] for v in row]


def outline(model: RobotModel, st: Stance) -> list[Vec3]:
    """The corners of the box around each geom of ``model`` placed as in ``st`` (world
    frame): every point of the drawn robot lies inside their convex hull."""
    points: list[Vec3] = []
    for link in model.links:
        frame = st.frames.get(link.name)
        if frame is None:
            continue
        for g in link.geoms:
            if g.shape == "box":
                half = (g.size[0] / 2, g.size[1] / 2, g.size[2] / 2)
            elif g.shape == "cylinder":
                half = (g.size[0], g.size[0], g.size[1] / 2)
            else:  # a sphere
                half = (g.size[0], g.size[0], g.size[0])
            place = compose(frame, from_xyz_rpy(g.pos, g.rpy))
            points += [
                apply(place, (sx * half[0], sy * half[1], sz * half[2]))
                for sx in (-1, 1)
                for sy in (-1, 1)
                for sz in (-1, 1)
            ]
    return points


@dataclass(frozen=True)
class Framing:
    """A camera that shows given points whole: where it is, what it looks at (up is +z),
    and its clipping planes."""

    position: Vec3
    target: Vec3
    near: float
    far: float


def _unit(v: Vec3) -> Vec3:
    n = math.sqrt(sum(c * c for c in v))
    return (v[0] / n, v[1] / n, v[2] / n)


def _cross(a: Vec3, b: Vec3) -> Vec3:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a: Vec3, b: Vec3) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def camera_axes(position: Vec3, target: Vec3) -> tuple[Vec3, Vec3, Vec3]:
    """(right, up, back) of a camera at ``position`` looking at ``target`` with +z up."""
    back = _unit((position[0] - target[0], position[1] - target[1], position[2] - target[2]))
    right = _unit(_cross((0.0, 0.0, 1.0), back))
    return right, _cross(back, right), back


def frame_points(
    points: Iterable[Vec3],
    aspect: float,
    fov_deg: float = FIELD_OF_VIEW_DEG,
    view_from: Vec3 = VIEW_FROM,
    fill: float = FILL,
) -> Framing:
    """The camera looking from direction ``view_from`` at the middle of ``points`` from just
    far enough that every point falls inside ``fill`` of a view of width/height ``aspect``
    and vertical field of view ``fov_deg``: a tall robot is framed by its height, a flat one
    (a hexapod, a car) by its spread over the floor, in a wide or a narrow view alike."""
    pts = list(points) or [(0.0, 0.0, 0.0)]
    lo = [min(p[k] for p in pts) for k in range(3)]
    hi = [max(p[k] for p in pts) for k in range(3)]
    target: Vec3 = ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2)
    right, up, back = camera_axes(_unit(view_from), (0.0, 0.0, 0.0))
    tan_v = math.tan(math.radians(fov_deg) / 2) * fill
    tan_h = tan_v * aspect
    size = max(max(h - low for h, low in zip(hi, lo, strict=True)), 0.05)
    distance = size  # never closer than the robot is large
    for p in pts:
        r: Vec3 = (p[0] - target[0], p[1] - target[1], p[2] - target[2])
        # the point's depth in front of the camera is distance - r.back; it is in view when
        # its sideways and upward offsets are within tan(half angle) of that depth
        depth_needed = max(abs(_dot(r, right)) / tan_h, abs(_dot(r, up)) / tan_v)
        distance = max(distance, _dot(r, back) + depth_needed)
    position: Vec3 = (
        target[0] + distance * back[0],
        target[1] + distance * back[1],
        target[2] + distance * back[2],
    )
    return Framing(position, target, near=distance / 20, far=distance * 60)


def project(p: Vec3, framing: Framing, aspect: float, fov_deg: float = FIELD_OF_VIEW_DEG) -> Vec3:
    """Where ``p`` shows in the view: (x, y) from -1 to 1 across its width and height
    (inside when both are), and its depth in front of the camera."""
    right, up, back = camera_axes(framing.position, framing.target)
    q: Vec3 = (p[0] - framing.position[0], p[1] - framing.position[1], p[2] - framing.position[2])
    depth = -_dot(q, back)
    tan_v = math.tan(math.radians(fov_deg) / 2)
    return (_dot(q, right) / (depth * tan_v * aspect), _dot(q, up) / (depth * tan_v), depth)


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
        # the camera frames the whole robot, tall or flat, in this view's shape
        self.framing = frame_points(outline(model, self.stance), width / height)
        f = self.framing
        self.scene = ui.scene(
            width,
            height,
            grid=False,
            camera=ui.scene.perspective_camera(fov=FIELD_OF_VIEW_DEG, near=f.near, far=f.far),
            background_color="#f1f5f9",
        )
        self.scene.move_camera(*f.position, *f.target, duration=0.0)
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
