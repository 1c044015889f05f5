"""MJCF (MuJoCo's XML) of a :class:`~rcb4hv.robot.model.RobotModel`.

:func:`to_mjcf` writes one self-contained document: a ground plane, the robot on a free
joint (its root link), one body per link with the link's inertial and geoms, one hinge per
joint with its limits (a ``wheel`` joint turns without limits), one servo actuator per
mapped joint (a wheel's drives its speed, :data:`rcb4hv.robot.servos.WHEEL_FULL_SCALE_DEG`)
and an IMU site on the root link with a gyro and an accelerometer. The physics of
:mod:`rcb4hv.physics` loads it and drives the actuators itself (stiffness from each servo's
stretch, limp when free); exported on its own (``rcb4hv robot export NAME --format mjcf``)
the actuators are plain position servos at the default stretch, ready for MuJoCo's viewer or
a controller.

Each servo is a MuJoCo ``general`` actuator ``force = kp * (ctrl - q) - kd * qdot`` (kd the
controller's braking, :func:`~rcb4hv.robot.servos.controller_damping`) clamped to the servo's
stall torque, on a hinge with the servo's back-EMF damping ``stall_torque / no_load_speed`` and
the gear train's reflected inertia (``armature``): together a DC motor's straight
torque-speed line, so a joint can neither push harder than the stall torque nor turn faster
than the no-load speed. The servo model and its figures (each with its source) are
:mod:`rcb4hv.robot.servos`, which the export and :mod:`rcb4hv.physics` share; the contact
figures are below (the physics documentation lists them all).

Only the ground plane collides with the robot (no self-collision): legs and arms pass
through each other, which keeps the contact count, and so the cost, low.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from xml.sax.saxutils import quoteattr

from rcb4hv.robot.geometry import geom_lowest_z
from rcb4hv.robot.kinematics import forward
from rcb4hv.robot.model import Geom, Joint, Link, RobotModel, ServoSpec, Vec3, chain
from rcb4hv.robot.servos import (
    DEFAULT_SERVO,
    DEFAULT_STRETCH,
    armature,
    back_emf_damping,
    controller_damping,
    stiffness,
)

__all__ = [
    "FLOOR_FRICTION",
    "FRICTION_CONE",
    "IMPRATIO",
    "IMU_SITE",
    "JACOBIAN",
    "TIMESTEP",
    "lowest_point",
    "to_mjcf",
]

# ------------------------------------------------------------------------ simulation and contact

TIMESTEP = 0.002
"""Physics step (s). The fastest dynamics are a servo's position loop (at most
sqrt(kp / armature) = 170 rad/s at stretch 127, a 37 ms period) and MuJoCo's contact (time
constant 20 ms): 2 ms resolves both with 10 or more steps, and a 10/15/20/25 ms output period
is a whole number of steps. The fixture's motions give the same outcomes at 1 ms (checked:
falls, end poses and turns agree, displacements within a few mm; docs/physics.md), at about
two thirds of the cost."""

FLOOR_FRICTION = 0.4
"""Sliding friction of a plastic (ABS/polycarbonate) foot sole on a hard floor. Published
static coefficients of plastics on wood and laminate lie around 0.3-0.5 (engineering
friction tables); chosen in the middle."""

TORSIONAL_FRICTION = 0.005
ROLLING_FRICTION = 0.0001
"""Spin (m) and rolling (m) friction of a contact: MuJoCo's defaults, no measured figure.
A sole touches the floor at the corners of its boxes, whose sliding friction already resists
a spin with the corners' lever (a KXR-L2 sole: 62 mm, where a flat sole pressing evenly
resists with its mean radius, 33 mm); each contact's spin friction adds to that. The turns
depend on it: the fixture's fast turn left goes +137°, +127° and +65° with 0.0001, 0.005 and
0.02 m (``PhysicsOptions.torsional_friction``; docs/physics.md, "How sensitive the verdicts
are")."""

FRICTION_CONE = "elliptic"
"""MuJoCo's friction cone: Coulomb's circle of ``|tangential| <= mu * normal``. MuJoCo's
default, the pyramidal cone, is a linearised approximation that lets loaded contacts creep;
its XML reference says "elliptic cones are a better model of the physical reality" and its
computation chapter names them the first cure for contact slip. With the pyramidal cone the
KXR's feet crept: single steps turned it ~15° and the get-up from the back fell back."""

IMPRATIO = 1.0
"""How much harder MuJoCo makes a contact's friction than its normal force (``impratio``, for
elliptic cones): MuJoCo's default. MuJoCo's contacts are soft, and at 1 a foot loaded below
its friction limit still creeps where dry friction holds: the KXR-L2 with grippers holding
its pose on a 15° slope (tan 15° = 0.27, below the feet's 0.4) creeps 6.1 mm in 5 s
(``tests/physics/test_static_friction.py``). Larger values make the friction "harder ...
having the general effect of preventing slip, without increasing the actual friction
coefficient" (MuJoCo's XML reference); MuJoCo Menagerie's legged robots set 100
(``unitree_go2/go2.xml``, ``unitree_a1/a1.xml``), with which the creep is 0.17 mm. Not
adopted: it costs the Newton solver 2.7 iterations a step instead of 1.1, and physics runs 2-3
times slower (the 30-axis KXR at 13.7x real time instead of 33x, under the 30x this package
keeps; docs/physics.md, "Static friction"). ``--what-if impratio=100``
(:class:`~rcb4hv.physics.PhysicsOptions`) plays a motion with it."""

JACOBIAN = "sparse"
"""How MuJoCo stores the constraint Jacobian: a cost setting, not a physical one (the same
equations, solved to the same tolerance). MuJoCo's default ("auto") picks dense below 60
degrees of freedom; the kits have 18-38, and with their 12-24 floor contacts sparse is
faster: MuJoCo's step on a walking KXR-L2W2L6A4H2 takes 46 us instead of 56, and the outcomes
of every motion of Kondo's five sample projects and the fixture are the same to the
reported digit (docs/physics.md, "Time, determinism and speed")."""

IMU_SITE = "imu"
"""The site on the root link carrying the gyro and the accelerometer."""

# collision classes: the robot's geoms touch the floor only (contype & conaffinity)
_ROBOT_CONTYPE, _ROBOT_AFFINITY = 1, 2
_FLOOR_CONTYPE, _FLOOR_AFFINITY = 2, 1
_MIN_MASS = 1e-4  # kg: MuJoCo needs a moving body to have mass; a massless link gets this
_MIN_INERTIA = 1e-8  # kg·m²: likewise for each principal moment


def _f(x: float) -> str:
    """A number in XML: shortest exact repr, so the same model always gives the same text."""
    if x == 0.0:
        return "0"
    return repr(float(x))


def _v(values: Iterable[float]) -> str:
    return " ".join(_f(x) for x in values)


def _pose(pos: Vec3, rpy: Vec3) -> str:
    out = f'pos="{_v(pos)}"'
    if any(rpy):
        # URDF's fixed-axis roll, pitch, yaw (Rz @ Ry @ Rx): MuJoCo's extrinsic "XYZ" order
        out += f' euler="{_v(rpy)}"'
    return out


def _geom(link: Link, k: int, g: Geom) -> str:
    if g.shape == "box":
        size = _v(s / 2.0 for s in g.size)
    elif g.shape == "cylinder":
        size = _v((g.size[0], g.size[1] / 2.0))
    else:
        size = _f(g.size[0])
    name = quoteattr(f"{link.name}_{k}")
    return (
        f'<geom name={name} type="{g.shape}" size="{size}" {_pose(g.pos, g.rpy)} '
        f'rgba="{_v(g.rgba)}" mass="0"/>'
    )


def _inertial(link: Link) -> str:
    i = link.inertial
    mass = max(i.mass, _MIN_MASS)
    ixx, iyy, izz, ixy, ixz, iyz = i.inertia
    if ixy or ixz or iyz:
        full = (ixx, iyy, izz, ixy, ixz, iyz)
        return f'<inertial pos="{_v(i.com)}" mass="{_f(mass)}" fullinertia="{_v(full)}"/>'
    diag = (max(ixx, _MIN_INERTIA), max(iyy, _MIN_INERTIA), max(izz, _MIN_INERTIA))
    return f'<inertial pos="{_v(i.com)}" mass="{_f(mass)}" diaginertia="{_v(diag)}"/>'


def _spec(model: RobotModel, joint: str) -> ServoSpec | None:
    s = model.servo_for_joint(joint)
    if s is None:
        return None
    return s.servo or DEFAULT_SERVO


def _hinge(model: RobotModel, j: Joint, armature_scale: float) -> str:
    spec = _spec(model, j.name)
    damping = back_emf_damping(spec) if spec is not None else 0.0
    inertia = armature_scale * armature(spec) if spec is not None else 0.0
    limits = (
        'limited="false"'
        if j.kind == "wheel"
        else f'range="{_f(j.lower)} {_f(j.upper)}" limited="true"'
    )
    return (
        f'<joint name={quoteattr(j.name)} type="hinge" axis="{_v(j.axis)}" {limits} '
        f'damping="{_f(damping)}" armature="{_f(inertia)}"/>'
    )


def lowest_point(model: RobotModel) -> float:
    """The lowest z (m) of the model's shapes in its zero pose, root link at the origin."""
    frames = forward(model, {})
    return min(
        [0.0, *(geom_lowest_z(g, frames[link.name]) for link in model.links for g in link.geoms)]
    )


def _body(model: RobotModel, link: Link, indent: str, lines: list[str]) -> None:
    lines.append(indent + _inertial(link))
    lines.extend(indent + _geom(link, k, g) for k, g in enumerate(link.geoms))


def to_mjcf(
    model: RobotModel,
    *,
    timestep: float = TIMESTEP,
    floor_friction: float = FLOOR_FRICTION,
    stretch: int = DEFAULT_STRETCH,
    base_height: float | None = None,
    armature_scale: float = 1.0,
    damping_scale: float = 1.0,
    impratio: float = IMPRATIO,
    torsional_friction: float = TORSIONAL_FRICTION,
) -> str:
    """The MJCF document of ``model`` (see the module docstring).

    ``timestep`` is the physics step (s), ``floor_friction`` the sliding friction coefficient
    of the robot's feet on the floor, ``stretch`` the ICS stretch (1-127) the exported
    position servos get, ``base_height`` the root link's start height above the floor (m;
    default: the zero pose standing on the floor), ``armature_scale`` a factor on each
    servo's reflected inertia (1: :func:`armature`; for sensitivity studies),
    ``damping_scale`` one on each servo controller's braking (1: :func:`controller_damping`),
    ``impratio`` the friction's hardness (:data:`IMPRATIO`; 1 is MuJoCo's default),
    ``torsional_friction`` each contact's spin friction (m, :data:`TORSIONAL_FRICTION`).
    """
    if base_height is None:
        base_height = -lowest_point(model)
    if not timestep > 0:
        raise ValueError("timestep must be > 0")
    if not 0 < impratio < math.inf:
        raise ValueError(f"impratio must be a finite number > 0, not {impratio!r}")
    joints = chain(model.joints, model.root)
    by_parent: dict[str, list[Joint]] = {}
    for j in joints:
        by_parent.setdefault(j.parent, []).append(j)
    friction = f"{_f(floor_friction)} {_f(torsional_friction)} {_f(ROLLING_FRICTION)}"
    lines = [
        f"<mujoco model={quoteattr(model.name)}>",
        '  <compiler angle="radian" eulerseq="XYZ" autolimits="true"/>',
        f'  <option timestep="{_f(timestep)}" integrator="implicitfast" '
        f'cone="{FRICTION_CONE}" impratio="{_f(impratio)}" jacobian="{JACOBIAN}" '
        'gravity="0 0 -9.81"/>',
        "  <default>",
        f'    <geom contype="{_ROBOT_CONTYPE}" conaffinity="{_ROBOT_AFFINITY}" '
        f'condim="4" friction="{friction}"/>',
        "  </default>",
        "  <worldbody>",
        f'    <geom name="floor" type="plane" size="0 0 0.05" contype="{_FLOOR_CONTYPE}" '
        f'conaffinity="{_FLOOR_AFFINITY}" rgba="0.8 0.8 0.8 1"/>',
        f'    <body name={quoteattr(model.root)} pos="0 0 {_f(base_height)}">',
        '      <freejoint name="base"/>',
        f'      <site name="{IMU_SITE}" pos="0 0 0" size="0.005"/>',
    ]
    _body(model, model.link(model.root), "      ", lines)

    def walk(parent: str, indent: str) -> None:
        for j in by_parent.get(parent, []):
            lines.append(f"{indent}<body name={quoteattr(j.child)} {_pose(j.xyz, j.rpy)}>")
            lines.append(indent + "  " + _hinge(model, j, armature_scale))
            _body(model, model.link(j.child), indent + "  ", lines)
            walk(j.child, indent + "  ")
            lines.append(f"{indent}</body>")

    walk(model.root, "      ")
    lines += ["    </body>", "  </worldbody>", "  <actuator>"]
    for s in sorted(model.servos, key=lambda s: s.index):
        spec = s.servo or DEFAULT_SERVO
        if model.joint(s.joint).kind == "wheel":  # duty-driven motor (WHEEL_FULL_SCALE_DEG)
            lines.append(
                f'    <general name="servo{s.index}" joint={quoteattr(s.joint)} '
                f'gaintype="fixed" gainprm="{_f(spec.stall_torque)}" ctrlrange="-1 1" '
                f'forcerange="{_f(-spec.stall_torque)} {_f(spec.stall_torque)}"/>'
            )
            continue
        kp = stiffness(spec, stretch)
        kd = damping_scale * controller_damping(spec)
        lines.append(
            f'    <general name="servo{s.index}" joint={quoteattr(s.joint)} gaintype="fixed" '
            f'gainprm="{_f(kp)}" biastype="affine" biasprm="0 {_f(-kp)} {_f(-kd)}" '
            f'forcerange="{_f(-spec.stall_torque)} {_f(spec.stall_torque)}"/>'
        )
    lines += [
        "  </actuator>",
        "  <sensor>",
        f'    <gyro name="gyro" site="{IMU_SITE}"/>',
        f'    <accelerometer name="accelerometer" site="{IMU_SITE}"/>',
        "  </sensor>",
        "</mujoco>",
        "",
    ]
    return "\n".join(lines)
