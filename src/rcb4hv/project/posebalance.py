"""Static balance and servo load of every pose of a motion (``rcb4hv project poses``, and the
``pose-cannot-stand`` / ``pose-over-torque`` findings of ``rcb4hv project check --balance``).

A motion's pose names only the servos it moves; the others keep the value the previous pose
gave them. So the poses are accumulated from the robot's home pose (the model's resting pose,
which is where a motion played from the home position starts), hold (7FFFh) and free
(8000h) keeping the previous angle. Each accumulated pose then goes through
:func:`rcb4hv.robot.balance.pose_balance`.

A statically unbalanced pose is not always a fault: a walk passes through poses that only
stand while moving, and a get-up lies down on purpose. The findings are warnings.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from rcb4hv.hth4.model import Motion, Project
from rcb4hv.hth4.poses import SPECIAL_POSITIONS, motion_poses
from rcb4hv.project.check import Finding
from rcb4hv.robot.balance import PoseBalance, pose_balance
from rcb4hv.robot.model import RobotModel

__all__ = ["PoseReport", "balance_findings", "motion_balance", "motion_pose_angles"]


@dataclass(frozen=True)
class PoseReport:
    """Pose ``index`` (0-based) of a motion: its joint angles and their balance."""

    index: int
    frames: int
    angles: dict[str, float]
    balance: PoseBalance

    def to_dict(self) -> dict[str, object]:
        return {"pose": self.index + 1, "frames": self.frames, **self.balance.to_dict()}


def motion_pose_angles(
    model: RobotModel, motion: Motion, start: Mapping[str, float] | None = None
) -> list[tuple[int, dict[str, float]]]:
    """Each pose's frame count and whole pose (joint angles, rad), accumulated from ``start``
    (default: the model's home pose)."""
    angles = {j.name: 0.0 for j in model.joints}
    angles.update(model.home if start is None else start)
    mapped = set(model.indices)
    out: list[tuple[int, dict[str, float]]] = []
    for pose in motion_poses(motion):
        values = {
            i: v for i, v in pose.values.items() if i in mapped and v not in SPECIAL_POSITIONS
        }
        angles.update(model.motion_angles(values))
        out.append((pose.frames, dict(angles)))
    return out


def motion_balance(model: RobotModel, motion: Motion) -> list[PoseReport]:
    """The balance and servo loads of every pose of ``motion``."""
    return [
        PoseReport(i, frames, angles, pose_balance(model, angles))
        for i, (frames, angles) in enumerate(motion_pose_angles(model, motion))
    ]


def balance_findings(project: Project, model: RobotModel) -> list[Finding]:
    """Warnings for the poses whose centre of mass lies outside their support polygon and the
    joints whose servo cannot hold the pose's static load (above its stall torque)."""
    out: list[Finding] = []
    for m in project.used_motions:
        for r in motion_balance(model, m):
            b = r.balance
            where = f"motion {m.slot} pose {r.index + 1}"
            if not b.balanced:
                touching = ", ".join(b.contacts) or "nothing"
                out.append(
                    Finding(
                        "warning",
                        "pose-cannot-stand",
                        m.slot,
                        m.name or "",
                        m.address,
                        "",
                        f"{where}: {b.margin_text} ({touching})",
                    )
                )
            for joint in b.overloaded:
                out.append(
                    Finding(
                        "warning",
                        "pose-over-torque",
                        m.slot,
                        m.name or "",
                        m.address,
                        "",
                        f"{where}: joint {joint} needs {b.torque_ratio[joint]:.0%} of its "
                        "servo's stall torque to hold the pose",
                    )
                )
    return out
