"""``project robust``: trials per second with 1 and 2 worker processes, and the scaling
efficiency (the 2-worker rate over twice the 1-worker rate; target >= 0.8).

Each trial plays a generated one-step forward walk of the built-in KXR-L2 (about 2 s of
robot time) in MuJoCo with drawn constants. ``ours_us`` is the wall time per trial,
``wire_us`` the robot time a trial plays; the efficiency row compares the two rates. On a
machine whose 2 cores are shared with other work, the efficiency says more about the load
than about the pool.
"""

from __future__ import annotations

import time
from typing import Any

TARGET_EFFICIENCY = 0.8


def run(quick: bool = False) -> list[dict[str, Any]]:
    from rcb4hv.gait.generate import default_params, walk
    from rcb4hv.gait.motion import walk_motion
    from rcb4hv.hth4.keyframes import add_motion
    from rcb4hv.hth4.newproject import new_project
    from rcb4hv.project.relocate import project_image
    from rcb4hv.project.robust import robust
    from rcb4hv.robot.builtin import load_builtin

    model = load_builtin("kxr-l2")
    w = walk(model, default_params(model, "forward", steps=1))
    motion = walk_motion(model, w, slot=2, name="walk").motion
    image, layout = project_image(add_motion(new_project(model), motion))
    robot_us = len(w.poses) * 15_000.0
    trials = 2 if quick else 8
    rate: dict[int, float] = {}
    rows = []
    for workers in (1, 2):
        t0 = time.perf_counter()
        robust(image, [2], layout=layout, robot=model, trials=trials, workers=workers)
        per = (time.perf_counter() - t0) / trials
        rate[workers] = 1.0 / per
        rows.append(
            {
                "name": f"robust: one trial, {workers} worker{'s' if workers > 1 else ''}",
                "ours_us": per * 1e6,
                "wire_us": robot_us,
                "ratio": per * 1e6 / robot_us,
                "note": f"{rate[workers]:.2f} trials/s; wall time per trial against the robot "
                "time it plays",
            }
        )
    eff = rate[2] / (2.0 * rate[1])
    rows.append(
        {
            "name": "robust: scaling efficiency of 2 workers",
            "ours_us": 1e6 / rate[2],
            "wire_us": 1e6 / rate[1] / 2.0,
            "ratio": eff,
            "target": TARGET_EFFICIENCY,
            "lower_is_better": False,
            "note": "rate(2) / (2 rate(1))",
        }
    )
    return rows
