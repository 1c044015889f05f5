"""A physics run's track as a table (``rcb4hv project simulate --physics --trace FILE.csv``).

One row per output period of each motion, from its start to the end of the settling after it
(what :attr:`~rcb4hv.project.runresult.MotionRun.track` keeps): the slot, the time from the
motion's start, the torso's position (m, in the world: the floor the robot was put on, x
forward and y left of where it first stood, z up), its heading and tilt, how far it leans
forward and to its right (degrees, from the world's up seen in the torso's frame: a bow leans
forward, standing on the right foot leans right), the links on the floor, the robot's centre
of mass (m, world) and how far its ground projection lies inside what the robot stands on
(``com_margin_mm``: inside the convex hull of the floor contacts; negative outside, tipping
over that edge; empty in the air), then every joint's angle and the angle the board commands
it to (degrees). What a spreadsheet or a plotting script needs to see why a motion fell:
when the lean grew, what it stood on, when the centre of mass left the support, and which
joints moved or could not follow.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterator

from rcb4hv.project.runresult import SimulationRun
from rcb4hv.robot.geometry import quaternion_matrix

__all__ = ["TRACE_COLUMNS", "trace_csv", "trace_rows"]

TRACE_COLUMNS = (
    "slot", "t_s", "x_m", "y_m", "z_m", "yaw_deg", "tilt_deg", "lean_forward_deg",
    "lean_right_deg", "touching", "com_x_m", "com_y_m", "com_z_m", "com_margin_mm",
)  # fmt: skip
"""The columns before the joints': each joint's angle (``<joint>_deg``), then the angle the
board commands it to (``<joint>_target_deg``; empty while it is free), in the model's order."""


def trace_rows(run: SimulationRun) -> Iterator[list[str]]:
    """The header, then one row per track point of every motion of ``run`` (a physics run
    made with ``track=True``; a motion without a track gives no rows)."""
    joints = next((list(p.angles) for m in run.motions for p in m.track), [])
    yield [*TRACE_COLUMNS, *(f"{j}_deg" for j in joints), *(f"{j}_target_deg" for j in joints)]
    for m in run.motions:
        for p in m.track:
            up_x, up_y, up_z = quaternion_matrix(p.quat)[2]  # the world's up in the torso
            row = [
                m.result.slot if m.result.slot is not None else "",
                f"{p.t - m.start_s:.3f}",
                *(f"{v:.4f}" for v in (p.x, p.y, p.z)),
                *(f"{math.degrees(v):.2f}" for v in (p.yaw, p.tilt)),
                f"{math.degrees(math.atan2(-up_x, up_z)):.2f}",
                f"{math.degrees(math.atan2(up_y, up_z)):.2f}",
                " ".join(p.touching),
                *(f"{v:.4f}" for v in p.com),
                "" if p.com_margin is None else f"{p.com_margin * 1000:.1f}",
            ]
            for angles in (p.angles, p.targets):
                row += [f"{math.degrees(angles[j]):.2f}" if j in angles else "" for j in joints]
            yield [str(v) for v in row]


def trace_csv(run: SimulationRun) -> str:
    """:func:`trace_rows` as CSV text."""
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerows(trace_rows(run))
    return out.getvalue()
