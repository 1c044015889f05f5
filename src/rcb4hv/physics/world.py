"""The MuJoCo world of one robot: load its MJCF, place it on the floor, step, read it back.

:class:`PhysicsWorld` knows joints by name and servos by ICS number and nothing about the
board (that is :mod:`rcb4hv.physics.backend`). MuJoCo is imported on first use; without it
:func:`require_mujoco` raises :class:`~rcb4hv.errors.PhysicsUnavailableError`.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

from rcb4hv.errors import PhysicsError, PhysicsUnavailableError
from rcb4hv.physics.load import add_load
from rcb4hv.physics.options import PhysicsOptions
from rcb4hv.robot.balance import signed_margin
from rcb4hv.robot.geometry import (
    Matrix3,
    box_corners,
    convex_hull,
    lowest_z,
    quaternion_matrix,
)
from rcb4hv.robot.mjcf import (
    FLOOR_FRICTION,
    IMPRATIO,
    TIMESTEP,
    TORSIONAL_FRICTION,
    to_mjcf,
)
from rcb4hv.robot.model import GeomShape, RobotModel, ServoSpec, Vec3
from rcb4hv.robot.servos import (
    DEFAULT_SERVO,
    FREE_DAMPING_FRACTION,
    back_emf_damping,
    stiffness,
)

__all__ = ["BasePose", "PhysicsWorld", "engine_version", "require_mujoco", "with_torque"]

SATURATION = 0.999
"""An actuator at this fraction of its stall torque counts as saturated (rounding margin)."""


def require_mujoco() -> Any:
    """The ``mujoco`` module, or :class:`PhysicsUnavailableError` naming the extra."""
    try:
        import mujoco
    except ImportError as exc:  # pragma: no cover - the test environment has MuJoCo
        raise PhysicsUnavailableError(
            "physics needs MuJoCo: install rcb4hv[sim] (pip install 'rcb4hv[sim]')"
        ) from exc
    return mujoco


def engine_version() -> str:
    """The physics engine and its version (``"mujoco 3.3.0"``): outcomes depend on it, so
    reports record it. Raises :class:`PhysicsUnavailableError` without MuJoCo."""
    return f"mujoco {require_mujoco().__version__}"


@dataclass(frozen=True, slots=True)
class BasePose:
    """The root link's position (m) and orientation in the world: ``yaw`` (rad, CCW about
    z: the twist of its orientation about the vertical, which is the heading of its x axis
    while upright and stays defined lying down), ``tilt`` (rad between its z axis and the
    vertical) and the world's up direction in its frame (``up``: x forward, y left, z up)."""

    x: float
    y: float
    z: float
    yaw: float
    tilt: float
    up: tuple[float, float, float]


def with_torque(model: RobotModel, factor: float) -> RobotModel:
    """``model`` with every servo's stall torque ``x factor`` (``PhysicsOptions.torque``;
    the same model at 1). Each servo's other figures (no-load speed, mass) are kept."""
    if factor == 1.0:
        return model
    servos = tuple(
        replace(
            s,
            servo=replace(
                spec := s.servo or DEFAULT_SERVO,
                stall_torque=spec.stall_torque * factor,
                source=f"{spec.source} (stall torque x{factor:g}: a what-if)",
            ),
        )
        for s in model.servos
    )
    return replace(model, servos=servos)


@dataclass(frozen=True, slots=True)
class _Servo:
    index: int
    joint: str
    spec: ServoSpec
    qpos: int
    dof: int
    actuator: int
    wheel: bool = False


class PhysicsWorld:
    """One robot on a flat floor in MuJoCo, stepped by :meth:`step` (``timestep`` s each)."""

    def __init__(
        self,
        model: RobotModel,
        *,
        timestep: float = TIMESTEP,
        options: PhysicsOptions | None = None,
    ) -> None:
        mj = require_mujoco()
        self._mj = mj
        self.model = model
        self.timestep = timestep
        self.options = opts = options or PhysicsOptions()
        """Factors on the model's chosen figures (default: none)."""
        built = with_torque(model, opts.torque)
        mjcf = to_mjcf(
            built,
            timestep=timestep,
            floor_friction=FLOOR_FRICTION * opts.friction,
            armature_scale=opts.armature,
            damping_scale=opts.servo_damping,
            impratio=IMPRATIO * opts.impratio,
            torsional_friction=TORSIONAL_FRICTION * opts.torsional_friction,
        )
        try:
            self.m = mj.MjModel.from_xml_string(mjcf)
        except ValueError as exc:
            raise PhysicsError(f"{model.name}: MuJoCo refuses the model: {exc}") from exc
        m = self.m
        if opts.mass != 1.0:
            m.body_mass[:] *= opts.mass
            m.body_inertia[:] *= opts.mass
        if opts.floor_tilt_deg:
            m.opt.gravity[:] = opts.gravity(-float(m.opt.gravity[2]))
        if opts.carry_left_g:
            add_load(mj, m, model, "left", opts.carry_left_g)
        if opts.carry_right_g:
            add_load(mj, m, model, "right", opts.carry_right_g)
        self.d = mj.MjData(self.m)
        self.servos: dict[int, _Servo] = {}
        for s in built.servos:
            j = m.joint(s.joint)
            self.servos[s.index] = _Servo(
                s.index,
                s.joint,
                s.servo or DEFAULT_SERVO,
                int(j.qposadr[0]),
                int(j.dofadr[0]),
                int(m.actuator(f"servo{s.index}").id),
                model.joint(s.joint).kind == "wheel",
            )
        self._indices = list(self.servos)
        self._qpos = [s.qpos for s in self.servos.values()]
        self._joint_qpos = {j.name: int(m.joint(j.name).qposadr[0]) for j in model.joints}
        self._gyro = int(m.sensor("gyro").adr[0])
        self._accel = int(m.sensor("accelerometer").adr[0])
        self._floor = int(m.geom("floor").id)
        self._root = int(m.jnt_bodyid[0])  # the free joint's body: the root link
        self._powered: dict[int, bool] = dict.fromkeys(self.servos, True)
        self._kp: dict[int, float] = {}
        # each position servo's controller braking (the MJCF's -kd): off while it is free
        self._kd = {i: float(m.actuator_biasprm[s.actuator, 2]) for i, s in self.servos.items()}

    def __deepcopy__(self, memo: dict[int, Any]) -> PhysicsWorld:
        """A world in the same state that goes on by itself: MuJoCo's model (whose servo
        gains :meth:`drive` and :meth:`release` change) and data are copied; the robot
        model, the options and the MuJoCo module are shared (never changed)."""
        new = object.__new__(type(self))
        memo[id(self)] = new
        shared = ("_mj", "model", "options")
        for name, value in self.__dict__.items():
            setattr(new, name, value if name in shared else copy.deepcopy(value, memo))
        return new

    # ------------------------------------------------------------------ time

    @property
    def time(self) -> float:
        return float(self.d.time)

    def step(self, n: int = 1) -> None:
        """Advance ``n`` physics steps."""
        if n > 0:
            self._mj.mj_step(self.m, self.d, nstep=n)

    # ------------------------------------------------------------------ pose

    def place(self, angles: Mapping[str, float], yaw: float = 0.0, pitch: float = 0.0) -> None:
        """Put the robot at rest with joint ``angles`` (rad), its root at the origin turned
        by ``yaw`` about z and then ``pitch`` about its y axis (-pi/2: lying on its back, +pi/2:
        on its front), lowered until its lowest point just touches the floor."""
        d = self.d
        d.qpos[:] = 0.0
        d.qvel[:] = 0.0
        cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
        cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
        # q = q_yaw(z) * q_pitch(y)
        d.qpos[3:7] = (cy * cp, -sy * sp, cy * sp, sy * cp)
        for name, a in angles.items():
            adr = self._joint_qpos.get(name)
            if adr is not None:
                d.qpos[adr] = a
        d.ctrl[:] = [
            0.0 if self.servos[i].wheel else angles.get(self.servos[i].joint, 0.0)
            for i in self._actuator_order()
        ]
        self._mj.mj_forward(self.m, d)
        d.qpos[2] = -self.lowest_point()
        d.time = 0.0
        self._mj.mj_forward(self.m, d)

    def _actuator_order(self) -> list[int]:
        return [s.index for s in sorted(self.servos.values(), key=lambda s: s.actuator)]

    def _geom_shapes(self) -> list[tuple[GeomShape, Vec3, Matrix3, Vec3]]:
        """Each robot geom (the floor left out) as :mod:`rcb4hv.robot.geometry` takes a shape:
        kind, centre, rotation, half extents (MuJoCo's sizes are half sizes already)."""
        m, d = self.m, self.d
        out: list[tuple[GeomShape, Vec3, Matrix3, Vec3]] = []
        for g in range(m.ngeom):
            if g == self._floor:
                continue
            r = d.geom_xmat[g].tolist()
            px, py, pz = d.geom_xpos[g].tolist()
            size = m.geom_size[g].tolist()
            kind = int(m.geom_type[g])
            shape: GeomShape
            if kind == self._mj.mjtGeom.mjGEOM_BOX:
                shape, half = "box", (size[0], size[1], size[2])
            elif kind == self._mj.mjtGeom.mjGEOM_CYLINDER:
                shape, half = "cylinder", (size[0], size[0], size[1])
            else:
                shape, half = "sphere", (size[0], size[0], size[0])
            rotation = ((r[0], r[1], r[2]), (r[3], r[4], r[5]), (r[6], r[7], r[8]))
            out.append((shape, (px, py, pz), rotation, half))
        return out

    def touching(self) -> tuple[str, ...]:
        """The links touching the floor now (sorted; only the floor touches the robot)."""
        m, d = self.m, self.d
        bodies = {
            int(m.geom_bodyid[g])
            for c in d.contact[: d.ncon]
            for g in (int(c.geom1), int(c.geom2))
            if g != self._floor
        }
        return tuple(sorted(m.body(b).name for b in bodies))

    def centre_of_mass(self) -> tuple[float, float, float]:
        """The whole robot's centre of mass (world, m)."""
        x, y, z = self.d.subtree_com[self._root].tolist()
        return (x, y, z)

    def com_margin(self) -> float | None:
        """How far (m) the centre of mass's ground projection lies inside the convex hull of
        the robot's floor contacts (negative: outside it, the robot tipping over that edge);
        None while nothing touches the floor. Static balance: how far from toppling."""
        points = [(float(c.pos[0]), float(c.pos[1])) for c in self.d.contact[: self.d.ncon]]
        if not points:
            return None
        x, y, _ = self.centre_of_mass()
        return signed_margin(convex_hull(points), (x, y))

    def lowest_point(self) -> float:
        """The lowest z (m) of the robot's geoms."""
        return min((lowest_z(*shape) for shape in self._geom_shapes()), default=math.inf)

    def shapes(self) -> list[tuple[tuple[float, float, float], ...]]:
        """The corners (world, m) of each robot geom's box (a cylinder's or sphere's bounding
        box): enough to draw the robot from any side."""
        return [box_corners(center, r, half) for _, center, r, half in self._geom_shapes()]

    def base(self) -> BasePose:
        d = self.d
        x, y, z = (float(v) for v in d.qpos[0:3])
        w, qx, qy, qz = (float(v) for v in d.qpos[3:7])
        r20, r21, r22 = quaternion_matrix((w, qx, qy, qz))[2]
        # the twist about the vertical of a swing-twist decomposition: the heading, also
        # where the forward axis points up or down (lying on the back or front)
        yaw = math.remainder(2 * math.atan2(qz, w), 2 * math.pi)
        tilt = math.acos(max(-1.0, min(1.0, r22)))
        # the world's up (0, 0, 1) in the root frame is the third row of R
        return BasePose(x, y, z, yaw, tilt, (r20, r21, r22))

    def quaternion(self) -> tuple[float, float, float, float]:
        """The root link's orientation (w, x, y, z)."""
        w, x, y, z = self.d.qpos[3:7].tolist()
        return (w, x, y, z)

    def joint_angles(self) -> dict[str, float]:
        q = self.d.qpos
        return {name: float(q[adr]) for name, adr in self._joint_qpos.items()}

    def servo_angle(self, index: int) -> float:
        return float(self.d.qpos[self.servos[index].qpos])

    def servo_angles(self) -> dict[int, float]:
        """Every mapped servo's joint angle (rad) by servo index."""
        return dict(zip(self._indices, self.d.qpos[self._qpos].tolist(), strict=True))

    # ------------------------------------------------------------------ servos

    def drive(self, index: int, target: float, kp: float) -> None:
        """Servo ``index`` holds ``target`` (rad) with gain ``kp`` (N·m/rad)."""
        s = self.servos[index]
        m = self.m
        if not self._powered[index]:
            m.dof_damping[s.dof] = back_emf_damping(s.spec)
            m.actuator_biasprm[s.actuator, 2] = self._kd[index]
            self._powered[index] = True
        if self._kp.get(index) != kp:
            m.actuator_gainprm[s.actuator, 0] = kp
            m.actuator_biasprm[s.actuator, 1] = -kp
            self._kp[index] = kp
        self.d.ctrl[s.actuator] = target

    def spin(self, index: int, duty: float) -> None:
        """Wheel servo ``index`` drives its motor at ``duty`` (-1..1): torque ``duty x
        stall`` against its back-EMF damping (:data:`rcb4hv.robot.servos.WHEEL_FULL_SCALE_DEG`)."""
        s = self.servos[index]
        m = self.m
        if not self._powered[index]:
            m.dof_damping[s.dof] = back_emf_damping(s.spec)
            self._powered[index] = True
        m.actuator_gainprm[s.actuator, 0] = s.spec.stall_torque
        self._kp[index] = -1.0  # not a position gain: the next drive() sets its own
        self.d.ctrl[s.actuator] = duty

    def wheel_speed(self, index: int) -> float:
        """Wheel servo ``index``'s turning speed (rad/s)."""
        return float(self.d.qvel[self.servos[index].dof])

    def release(self, index: int) -> None:
        """Servo ``index`` goes limp: no torque, only the gear train's passive damping."""
        s = self.servos[index]
        if self._powered[index]:
            free = FREE_DAMPING_FRACTION * self.options.free_damping
            self.m.dof_damping[s.dof] = free * back_emf_damping(s.spec)
            self.m.actuator_gainprm[s.actuator, 0] = 0.0
            self.m.actuator_biasprm[s.actuator, 1] = 0.0
            self.m.actuator_biasprm[s.actuator, 2] = 0.0
            self._kp[index] = 0.0
            self._powered[index] = False

    def stiffness(self, index: int, stretch: int | None) -> float:
        return self.options.stiffness * stiffness(self.servos[index].spec, stretch)

    def torque(self, index: int) -> float:
        """The servo's motor torque (N·m) at the last step."""
        return float(self.d.actuator_force[self.servos[index].actuator])

    def saturated(self, index: int) -> bool:
        s = self.servos[index]
        return abs(self.torque(index)) >= SATURATION * s.spec.stall_torque

    def saturated_servos(self, commanded: Mapping[int, float | None]) -> list[int]:
        """The servos of ``commanded`` driven to an angle (not None) that are
        :meth:`saturated`, in its order: one pass for every servo."""
        force = self.d.actuator_force.tolist()
        servos = self.servos
        return [
            index
            for index, goal in commanded.items()
            if goal is not None
            and abs(force[(s := servos[index]).actuator]) >= SATURATION * s.spec.stall_torque
        ]

    def push(self, force: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        """Push the root link with ``force`` (N, world frame, at its centre of mass) at every
        step from now until the next call (the default: no push)."""
        self.d.xfrc_applied[self._root, :3] = force

    # ------------------------------------------------------------------ sensors

    def imu(self) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
        """(angular velocity rad/s, specific force m/s²) at the root link's IMU site, in the
        root frame (x forward, y left, z up); at rest upright the accelerometer reads +g on z."""
        s = self.d.sensordata
        g, a = self._gyro, self._accel
        return (
            (float(s[g]), float(s[g + 1]), float(s[g + 2])),
            (float(s[a]), float(s[a + 1]), float(s[a + 2])),
        )
