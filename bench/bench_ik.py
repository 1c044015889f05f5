"""Inverse kinematics: wall time of a walk's leg solve per pose, against the board's output
period.

``rcb4hv.robot.ik.solve_feet`` along a walk-like path (bench.ik_speed.gait: the torso sways
and bobs, one foot lifts 2 cm and steps 3 cm), each pose seeded with the previous one: what
the gait generator does for every output period of a walk. ``wire_us`` is the output period
a generated walk is sampled at (15 ms, HeartToHeart4's default); the target is a solve in a
fifth of it (ratio <= 0.2), so a walk of hundreds of poses takes a second or two. Best of 3.
"""

from __future__ import annotations

from typing import Any

OUTPUT_PERIOD_US = 15_000.0
TARGET = 0.2


def run(quick: bool = False) -> list[dict[str, Any]]:
    from bench.ik_speed import gait
    from rcb4hv.robot.builtin import load_builtin

    rows = []
    for name in ("kxr-l2", "kxr-l2-gripper"):
        model = load_builtin(name)
        best = min(gait(model, steps=5 if quick else 100)[1] for _ in range(1 if quick else 3))
        rows.append(
            {
                "name": f"IK: both legs of a walk pose ({name})",
                "ours_us": best * 1000.0,
                "wire_us": OUTPUT_PERIOD_US,
                "ratio": best * 1000.0 / OUTPUT_PERIOD_US,
                "target": TARGET,
                "note": "solve_feet seeded with the previous pose",
            }
        )
    return rows
