"""Bring your own robot: a URDF plus a joint-map file (TOML).

The joint map says which RCB-4 servo drives which URDF joint::

    urdf = "myrobot.urdf"          # optional: the URDF, relative to this file
    title = "My robot"             # optional

    [servo]                        # optional: the servo type of every joint
    name = "KRS-3304R2"
    stall_torque = 1.363           # N·m
    no_load_speed = 8.055          # rad/s
    mass = 0.0337                  # kg

    [joints.l_knee]                # a URDF joint name
    index = 13                     # RCB-4 servo index (ICS number, 0..35)
    sign = 1                       # +1 or -1: which way a larger servo value turns the joint
    offset = 0                     # counts beyond centre and trim that are joint angle 0
    mirror = "r_knee"              # optional: the joint on the other side
    kind = "pitch"                 # optional: pitch, roll, yaw, grip or wheel
    side = "left"                  # optional: left, right or centre

What is not given is inferred: ``kind`` from the joint's axis in the robot's base frame at
the zero pose (x roll, y pitch, z yaw); ``side`` from the name (``l_``/``left_``/``_l`` or
``r_``/``right_``/``_r``, any case); ``mirror`` by swapping that side marker when the other
name exists. Joints the map does not name are still joints of the model (moved by nobody).
TOML is read with :mod:`tomllib` (Python 3.11+) or its backport ``tomli`` on 3.10.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from rcb4hv.errors import RobotModelError
from rcb4hv.robot.kinematics import IDENTITY, compose, from_xyz_rpy
from rcb4hv.robot.model import (
    Joint,
    JointKind,
    RobotModel,
    ServoJoint,
    ServoSpec,
    Side,
    side_of_name,
)
from rcb4hv.robot.urdf import UrdfRobot, parse_urdf

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = ["build_model", "load_urdf_robot", "parse_joint_map", "to_joint_map"]

_KINDS = ("pitch", "roll", "yaw", "grip", "wheel")
_SIDES = ("left", "right", "centre")
_SWAPS = (
    ("l_", "r_"),
    ("left", "right"),
    ("_l", "_r"),
    ("L_", "R_"),
    ("Left", "Right"),
    ("LEFT", "RIGHT"),
)


def parse_joint_map(text: str, source: str = "joint map") -> dict[str, Any]:
    """The joint-map TOML as a checked dict (``joints``, optional ``servo``, ``urdf``,
    ``title``)."""
    try:
        data: dict[str, Any] = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise RobotModelError(f"{source}: not TOML: {exc}") from None
    joints = data.get("joints")
    if not isinstance(joints, dict) or not joints:
        raise RobotModelError(f"{source}: needs a [joints.NAME] table per servo")
    for name, entry in joints.items():
        where = f"{source}: joints.{name}"
        if not isinstance(entry, dict):
            raise RobotModelError(f"{where}: must be a table")
        unknown = set(entry) - {"index", "sign", "offset", "mirror", "kind", "side"}
        if unknown:
            raise RobotModelError(f"{where}: unknown keys {sorted(unknown)}")
        index = entry.get("index")
        if not isinstance(index, int) or not 0 <= index <= 35:
            raise RobotModelError(f"{where}: index must be a servo index 0..35")
        if entry.get("sign", 1) not in (1, -1):
            raise RobotModelError(f"{where}: sign must be 1 or -1")
        if not isinstance(entry.get("offset", 0), int):
            raise RobotModelError(f"{where}: offset must be whole counts")
        if entry.get("kind", "pitch") not in _KINDS:
            raise RobotModelError(f"{where}: kind must be one of {', '.join(_KINDS)}")
        if entry.get("side", "left") not in _SIDES:
            raise RobotModelError(f"{where}: side must be one of {', '.join(_SIDES)}")
    servo = data.get("servo")
    if servo is not None:
        for key in ("stall_torque", "no_load_speed", "mass"):
            if not isinstance(servo.get(key), (int, float)) or servo[key] <= 0:
                raise RobotModelError(f"{source}: servo.{key} must be a positive number")
    return data


def _side_of(name: str) -> Side:
    return side_of_name(name) or "centre"


def _mirror_name(name: str, names: set[str]) -> str | None:
    for a, b in _SWAPS:
        for x, y in ((a, b), (b, a)):
            if x in name:
                other = name.replace(x, y, 1)
                if other in names and other != name:
                    return other
    return None


def _kind_of(axis_world: tuple[float, float, float]) -> JointKind:
    big = max(range(3), key=lambda k: abs(axis_world[k]))
    kinds: tuple[JointKind, JointKind, JointKind] = ("roll", "pitch", "yaw")
    return kinds[big]


def build_model(urdf: UrdfRobot, jmap: Mapping[str, Any], name: str) -> RobotModel:
    """A :class:`RobotModel` from parsed URDF links/joints and a parsed joint map."""
    entries: dict[str, dict[str, Any]] = dict(jmap["joints"])
    known = {j.name for j in urdf.joints}
    unknown = sorted(set(entries) - known)
    if unknown:
        raise RobotModelError(
            f"{name}: the joint map names joints the URDF lacks: {', '.join(unknown)} "
            f"(URDF joints: {', '.join(sorted(known))})"
        )
    # each joint's axis in the base frame at the zero pose
    frames = {urdf.root: IDENTITY}
    pending = list(urdf.joints)
    while pending:
        rest = [j for j in pending if j.parent not in frames]
        for j in pending:
            if j.parent in frames:
                frames[j.child] = compose(frames[j.parent], from_xyz_rpy(j.xyz, j.rpy))
        if len(rest) == len(pending):
            raise RobotModelError(f"{name}: joints {[j.name for j in rest]} hang from nothing")
        pending = rest
    joints: list[Joint] = []
    for j in urdf.joints:
        e = entries.get(j.name, {})
        r = frames[j.child]
        axis_world = tuple(sum(r[a][k] * j.axis[k] for k in range(3)) for a in range(3))
        kind: JointKind = e.get("kind") or _kind_of((axis_world[0], axis_world[1], axis_world[2]))
        side: Side = e.get("side") or _side_of(j.name)
        mirror = e.get("mirror") or (None if side == "centre" else _mirror_name(j.name, known))
        if mirror is not None and mirror not in known:
            raise RobotModelError(f"{name}: joint {j.name!r} mirrors unknown joint {mirror!r}")
        joints.append(
            Joint(
                j.name,
                j.parent,
                j.child,
                j.xyz,
                j.rpy,
                j.axis,
                j.lower,
                j.upper,
                kind,
                side,
                mirror,
                j.advisory,
            )
        )
    servo_data = jmap.get("servo")
    servos: list[ServoJoint] = []
    for j in urdf.joints:
        if j.name not in entries:
            continue
        e = entries[j.name]
        if servo_data is not None:
            spec = ServoSpec(
                str(servo_data.get("name", "servo")),
                float(servo_data["stall_torque"]),
                float(servo_data["no_load_speed"]),
                float(servo_data["mass"]),
                str(servo_data.get("source", "joint map")),
            )
        else:  # the URDF's own limit effort and velocity, when it gives them
            spec = ServoSpec("URDF limit", j.effort, j.velocity, 0.0, "URDF <limit>")
        servos.append(ServoJoint(e["index"], j.name, e.get("sign", 1), e.get("offset", 0), spec))
    return RobotModel(
        name=name,
        title=str(jmap.get("title") or urdf.name),
        root=urdf.root,
        links=urdf.links,
        joints=tuple(joints),
        servos=tuple(sorted(servos, key=lambda s: s.index)),
        sources={"model": f"URDF {urdf.name!r} with a joint map"},
    )


def load_urdf_robot(
    path: str | os.PathLike[str], joint_map: str | os.PathLike[str] | None = None
) -> RobotModel:
    """A robot from a joint-map file (``.toml``, naming its URDF with ``urdf = ...``) or from
    a URDF (``.urdf``) with its joint map (``joint_map``, default: the same path with
    ``.toml``)."""
    path = Path(path)
    if path.suffix.lower() == ".toml":
        map_path = path
        data = parse_joint_map(map_path.read_text(encoding="utf-8"), str(map_path))
        if "urdf" not in data:
            raise RobotModelError(f'{map_path}: name the robot\'s URDF with urdf = "FILE"')
        urdf_path = map_path.parent / str(data["urdf"])
    else:
        urdf_path = path
        map_path = Path(joint_map) if joint_map is not None else path.with_suffix(".toml")
        if not map_path.is_file():
            raise RobotModelError(
                f"{path}: a URDF robot needs a joint map (servo index, sign, offset per joint); "
                f"none at {map_path} (`rcb4hv robot export NAME --joint-map FILE` writes one for "
                "a built-in model; docs/robots.md shows its form)"
            )
        data = parse_joint_map(map_path.read_text(encoding="utf-8"), str(map_path))
    if not urdf_path.is_file():
        raise RobotModelError(f"{urdf_path}: no such URDF file")
    urdf = parse_urdf(urdf_path.read_bytes(), str(urdf_path))
    return build_model(urdf, data, urdf_path.stem)


def _toml_str(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def to_joint_map(model: RobotModel, urdf: str | None = None) -> str:
    """The model's joint map as TOML (reads back with :func:`parse_joint_map`)."""
    out = []
    if urdf is not None:
        out.append(f"urdf = {_toml_str(urdf)}")
    out.append(f"title = {_toml_str(model.title)}")
    specs = {s.servo for s in model.servos if s.servo is not None}
    if len(specs) == 1:
        spec = specs.pop()
        out += [
            "",
            "[servo]",
            f"name = {_toml_str(spec.name)}",
            f"stall_torque = {spec.stall_torque!r}",
            f"no_load_speed = {spec.no_load_speed!r}",
            f"mass = {spec.mass!r}",
            f"source = {_toml_str(spec.source)}",
        ]
    for s in model.servos:
        j = model.joint(s.joint)
        out += [
            "",
            f"[joints.{_toml_str(j.name)}]",
            f"index = {s.index}",
            f"sign = {s.sign}",
            f"offset = {s.offset}",
            f"kind = {_toml_str(j.kind)}",
            f"side = {_toml_str(j.side)}",
        ]
        if j.mirror is not None:
            out.append(f"mirror = {_toml_str(j.mirror)}")
    return "\n".join(out) + "\n"
