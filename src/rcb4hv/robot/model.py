"""A robot model as data: links, joints and the joint map from RCB-4 servo index to joint.

This module is the contract every robot-level feature builds on (kinematics, the 3D view,
physics, mirroring, URDF/MJCF export). It is pure data and arithmetic: no I/O, no clock.

Conventions (ROS REP 103): metres, kilograms, radians; the base frame has x forward, y left,
z up. A joint's ``axis`` is a unit vector in the child link's frame. Left and right joints
are defined mirror-symmetric: a pitch joint turns about +y on both sides, so equal pitch
angles move both limbs the same way, while equal roll or yaw angles move them apart. So the
mirror image of a pose keeps each pitch angle and negates each roll and yaw angle (see
:meth:`RobotModel.mirror_angles`).

Servo values to joint angles (one formula, :meth:`RobotModel.motion_angle`)::

    angle = sign * (value - CENTER - offset) / COUNTS_PER_DEGREE   (degrees)

where ``value`` is in **motion space**: a pose value of a motion, the board's servo-block
output (+6) or measured position (+4). The board adds the servo's trim (the block's base,
+2) when it sends (spec 9: sent = output + base + mixing) and reports ``position - base``
back, so motion-space values never include the trim and their angles do not depend on it.
Only the value actually **sent** to (or reported by) the servo includes the trim; for those,
:meth:`RobotModel.angle` / :meth:`RobotModel.value` (and the mapping forms
:meth:`~RobotModel.angles` / :meth:`~RobotModel.values`) take the trim explicitly::

    angle(index, sent, trim) == motion_angle(index, sent - trim)

The rule for callers: a motion pose, a block's output or measured position, a slider value
-> ``motion_angle(s)`` / ``motion_value(s)``; the board's ``servo_outputs()`` (what goes on
the ICS bus) or a physical servo position -> ``angle(s)`` / ``value(s)`` with the trim.
``CENTER`` (7500) and ``COUNTS_PER_DEGREE`` (8000/270) come from the protocol's memory map;
``offset`` is the joint map's extra zero offset in counts (0 for the built-in models).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Literal

from rcb4hv.errors import ArgumentError, RobotLookupError, RobotModelError
from rcb4hv.protocol.memory import CENTER, COUNTS_PER_DEGREE

__all__ = [
    "Geom",
    "Inertial",
    "Joint",
    "JointKind",
    "LimitVerdict",
    "Link",
    "RobotModel",
    "ServoJoint",
    "ServoSpec",
    "Side",
    "Vec3",
    "chain",
    "side_of_name",
]

Vec3 = tuple[float, float, float]
JointKind = Literal["pitch", "roll", "yaw", "grip", "wheel"]
Side = Literal["left", "right", "centre"]


def _side_words(kanji: str, word: str) -> re.Pattern[str]:
    c = word[0]
    return re.compile(
        rf"{kanji}"  # HeartToHeart4's 左 / 右, wherever it stands
        rf"|(?<![A-Za-z])(?i:{word})(?![A-Za-z])"  # the whole word: left_knee, front left leg
        rf"|^[{c}{c.upper()}](?=[\s_\-.])|[\s_\-.][{c}{c.upper()}]$"  # l_knee, knee_L
        rf"|^{c}(?=[A-Z])"  # camel case: lKnee
    )


_SIDE_WORDS: dict[Literal["left", "right"], re.Pattern[str]] = {
    "left": _side_words("左", "left"),
    "right": _side_words("右", "right"),
}


def side_of_name(name: str) -> Literal["left", "right"] | None:
    """The side a joint's or servo's name states: HeartToHeart4's 左 / 右, the word ``left`` /
    ``right`` (any case, not inside another word), or ``l`` / ``r`` set off at either end
    (``l_knee``, ``R shoulder``, ``knee_l``, ``lKnee``); None when it states none
    (``shoulder_pitch`` holds ``r_`` and ``leg`` starts with ``l``, but neither names a side)
    or both."""
    found = [side for side, word in _SIDE_WORDS.items() if word.search(name.strip())]
    return found[0] if len(found) == 1 else None


GeomShape = Literal["box", "cylinder", "sphere"]
LimitVerdict = Literal["ok", "advisory", "hard"]


@dataclass(frozen=True, slots=True)
class Geom:
    """A primitive shape in its link's frame (drawn and collided).

    ``size``: box full extents (x, y, z); cylinder (radius, length, 0) along its local z;
    sphere (radius, 0, 0).
    """

    shape: GeomShape
    size: Vec3
    pos: Vec3 = (0.0, 0.0, 0.0)
    rpy: Vec3 = (0.0, 0.0, 0.0)
    rgba: tuple[float, float, float, float] = (0.6, 0.6, 0.65, 1.0)


@dataclass(frozen=True, slots=True)
class Inertial:
    """Mass (kg), centre of mass (m, link frame) and inertia about the CoM (kg·m²):
    (ixx, iyy, izz, ixy, ixz, iyz)."""

    mass: float
    com: Vec3
    inertia: tuple[float, float, float, float, float, float]


@dataclass(frozen=True, slots=True)
class Link:
    name: str
    inertial: Inertial
    geoms: tuple[Geom, ...] = ()


@dataclass(frozen=True, slots=True)
class Joint:
    """A revolute joint from ``parent`` to ``child``.

    ``xyz``/``rpy``: the child frame's origin in the parent frame at angle 0 (URDF
    ``<origin>``); ``axis`` in the child frame. ``mirror`` names the joint on the other side
    (None for a centre joint, which mirrors onto itself).

    Two ranges, radians (see :meth:`RobotModel.limit_check`):

    * ``lower``/``upper``, the **hard** limits: mechanical only, where the brackets collide or
      the servo's own travel ends. A value beyond them is refused (and MuJoCo stops the
      joint there).
    * ``advisory``, a narrower **advisory** range (e.g. a library's software limits): a value
      outside it only warns, because the robot maker's own motions may use it. None: the
      hard range.
    """

    name: str
    parent: str
    child: str
    xyz: Vec3
    rpy: Vec3
    axis: Vec3
    lower: float
    upper: float
    kind: JointKind
    side: Side = "centre"
    mirror: str | None = None
    advisory: tuple[float, float] | None = None

    @property
    def advisory_range(self) -> tuple[float, float]:
        """The advisory range (radians), inside the hard limits; the hard range when the joint
        has none."""
        if self.advisory is None:
            return self.lower, self.upper
        return max(self.lower, self.advisory[0]), min(self.upper, self.advisory[1])


@dataclass(frozen=True, slots=True)
class ServoSpec:
    """A servo type's physical figures, each with its source."""

    name: str
    stall_torque: float  # N·m
    no_load_speed: float  # rad/s
    mass: float  # kg
    source: str = ""


@dataclass(frozen=True, slots=True)
class ServoJoint:
    """One entry of the joint map: RCB-4 servo index (ICS number) -> joint."""

    index: int
    joint: str
    sign: int = 1  # +1 or -1: which way a larger value turns the joint
    offset: int = 0  # counts: the value (beyond centre and trim) that is joint angle 0
    servo: ServoSpec | None = None


@dataclass(frozen=True)
class RobotModel:
    """Links, joints and joint map of one robot. ``root`` is the floating base link."""

    name: str
    title: str
    root: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    servos: tuple[ServoJoint, ...]
    sources: Mapping[str, str] = field(default_factory=dict)
    #: the robot's own resting pose (joint angles in radians by name), e.g. the pose its
    #: standard project holds after boot; joints not named are at 0
    home: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        names = {link.name for link in self.links}
        if self.root not in names:
            raise RobotModelError(f"{self.name}: root link {self.root!r} is not a link")
        joints = {j.name for j in self.joints}
        for j in self.joints:
            if j.parent not in names or j.child not in names:
                raise RobotModelError(f"{self.name}: joint {j.name!r} links an unknown link")
            if j.mirror is not None and j.mirror not in joints:
                raise RobotModelError(f"{self.name}: joint {j.name!r} mirrors unknown {j.mirror!r}")
            if j.lower > j.upper or (
                j.advisory is not None and not j.lower <= j.advisory[0] <= j.advisory[1] <= j.upper
            ):
                raise RobotModelError(
                    f"{self.name}: joint {j.name!r} needs lower <= upper and its advisory range "
                    "inside them"
                )
        seen: set[int] = set()
        for s in self.servos:
            if s.joint not in joints:
                raise RobotModelError(
                    f"{self.name}: servo {s.index} maps to unknown joint {s.joint!r}"
                )
            if s.index in seen:
                raise RobotModelError(f"{self.name}: servo index {s.index} is mapped twice")
            if s.sign not in (1, -1):
                raise RobotModelError(f"{self.name}: servo {s.index} sign must be +1 or -1")
            seen.add(s.index)

    # ------------------------------------------------------------------ look-ups

    def _missing(self, what: str, name: object, have: Iterable[object]) -> RobotLookupError:
        listed = ", ".join(str(h) for h in have)
        return RobotLookupError(f"{self.name}: no {what} {name!r} (it has: {listed or 'none'})")

    def link(self, name: str) -> Link:
        """The link called ``name``; RobotLookupError (also a KeyError) listing the links."""
        for link in self.links:
            if link.name == name:
                return link
        raise self._missing("link", name, (lk.name for lk in self.links))

    def joint(self, name: str) -> Joint:
        """The joint called ``name``; RobotLookupError (also a KeyError) listing the joints."""
        for j in self.joints:
            if j.name == name:
                return j
        raise self._missing("joint", name, (j.name for j in self.joints))

    def servo(self, index: int) -> ServoJoint:
        """The servo at ``index``; RobotLookupError (also a KeyError) listing the indices."""
        for s in self.servos:
            if s.index == index:
                return s
        raise self._missing("servo at index", index, self.indices)

    def servo_for_joint(self, joint: str) -> ServoJoint | None:
        for s in self.servos:
            if s.joint == joint:
                return s
        return None

    @property
    def indices(self) -> tuple[int, ...]:
        return tuple(sorted(s.index for s in self.servos))

    @property
    def mass(self) -> float:
        return sum(link.inertial.mass for link in self.links)

    # ------------------------------------------------------------------ servo <-> joint

    def motion_angle(self, index: int, value: int) -> float:
        """Joint angle (radians) of servo ``index`` at motion-space ``value`` (a motion's pose
        value, a servo block's output or measured position: before the board adds the trim;
        see the module docstring). The one conversion formula."""
        s = self.servo(index)
        return math.radians(s.sign * (value - CENTER - s.offset) / COUNTS_PER_DEGREE)

    def motion_value(self, index: int, angle: float) -> int:
        """Motion-space value that puts servo ``index``'s joint at ``angle`` (radians);
        :class:`~rcb4hv.errors.ArgumentError` (a ValueError) for an angle that is not finite."""
        s = self.servo(index)
        if not math.isfinite(angle):
            raise ArgumentError(
                f"servo {index} ({s.joint}): angle {angle!r} is not a finite number"
            )
        return round(CENTER + s.offset + s.sign * math.degrees(angle) * COUNTS_PER_DEGREE)

    def angle(self, index: int, sent: int, trim: int) -> float:
        """Joint angle (radians) of servo ``index`` at the value ``sent`` to the servo (motion
        value + ``trim``, the block's base), e.g. from ``Board.servo_outputs()``."""
        return self.motion_angle(index, sent - trim)

    def value(self, index: int, angle: float, trim: int) -> int:
        """The value to send (servo position) that puts servo ``index``'s joint at ``angle``
        (radians) with ``trim``: the motion value plus the trim."""
        return self.motion_value(index, angle) + trim

    def motion_angles(self, values: Mapping[int, int]) -> dict[str, float]:
        """Joint angles (radians) by joint name from motion-space values by index; indices
        the model does not map are ignored."""
        return {
            self.servo(i).joint: self.motion_angle(i, v)
            for i, v in values.items()
            if i in self._mapped
        }

    def motion_values(self, angles: Mapping[str, float]) -> dict[int, int]:
        """Motion-space values by index from joint angles by joint name (unmapped joints
        ignored)."""
        out: dict[int, int] = {}
        for name, a in angles.items():
            s = self.servo_for_joint(name)
            if s is not None:
                out[s.index] = self.motion_value(s.index, a)
        return out

    def angles(self, sent: Mapping[int, int], trims: Mapping[int, int]) -> dict[str, float]:
        """Joint angles (radians) by joint name from the values ``sent`` to the servos and
        their ``trims`` (by index; a missing trim is 0); unmapped indices are ignored."""
        return self.motion_angles({i: v - trims.get(i, 0) for i, v in sent.items()})

    def values(self, angles: Mapping[str, float], trims: Mapping[int, int]) -> dict[int, int]:
        """The values to send by index from joint angles by joint name, with ``trims``."""
        return {i: v + trims.get(i, 0) for i, v in self.motion_values(angles).items()}

    @property
    def _mapped(self) -> frozenset[int]:
        return frozenset(s.index for s in self.servos)

    def mirror_angles(self, angles: Mapping[str, float]) -> dict[str, float]:
        """The left-right mirror image of a pose in joint space: each joint's angle moves to
        its mirror joint; roll and yaw angles change sign, pitch and grip keep it."""
        out: dict[str, float] = {}
        for name, a in angles.items():
            j = self.joint(name)
            target = j.mirror or name
            out[target] = -a if j.kind in ("roll", "yaw") else a
        return out

    def out_of_limits(self, angles: Mapping[str, float]) -> list[str]:
        """Names of the joints whose angle lies outside their hard (mechanical) limits."""
        return [n for n, a in angles.items() if self.limit_check(n, a) == "hard"]

    def outside_advisory(self, angles: Mapping[str, float]) -> list[str]:
        """Names of the joints whose angle lies inside the hard limits but outside the
        advisory range (a warning, never a refusal)."""
        return [n for n, a in angles.items() if self.limit_check(n, a) == "advisory"]

    def limit_check(self, joint: str, angle: float) -> LimitVerdict:
        """Where ``angle`` (radians) of ``joint`` lies: ``"ok"`` inside the advisory range,
        ``"advisory"`` outside it but inside the hard limits (warn), ``"hard"`` beyond the
        hard (mechanical) limits (refuse). The one rule for the editor, the mirror and
        ``project check``."""
        j = self.joint(joint)
        if not j.lower <= angle <= j.upper:
            return "hard"
        lo, hi = j.advisory_range
        return "ok" if lo <= angle <= hi else "advisory"


def chain(joints: Iterable[Joint], root: str) -> list[Joint]:
    """Joints ordered parent-first from ``root`` (a tree walk)."""
    children: dict[str, list[Joint]] = {}
    for j in joints:
        children.setdefault(j.parent, []).append(j)
    out: list[Joint] = []
    stack = [root]
    while stack:
        for j in reversed(children.get(stack.pop(), [])):
            out.append(j)
            stack.append(j.child)
    return out
