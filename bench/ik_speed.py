"""Accuracy and speed of rcb4hv.robot.ik on every built-in model (the table of docs/posing.md).

For each model and hand or foot: targets made by forward kinematics of random in-limit angles
of that limb (so each is reachable), solved from the home pose:

* ``position``: the point only (the sole kept parallel where the leg can);
* ``pose``: position and orientation (all of it for 6 joints, the sole's normal for 5);
  over angles within ±0.6 rad of home (a working range: whole-range orientation targets of a
  5-joint leg have distant local minima; see docs/posing.md).

Then ``gait``: :func:`~rcb4hv.robot.ik.solve_feet` along a walk-like path (the torso sways
±1 cm and bobs 5 mm, one foot lifts 2 cm and steps 3 cm), 100 poses, each seeded with the
previous one: what the gait generator calls per output period.

Usage: ``python -m bench.ik_speed [--samples N] [--markdown]``.
"""

from __future__ import annotations

import argparse
import math
import random
import sys
import time

from rcb4hv.robot import ik
from rcb4hv.robot.builtin import BUILTIN, load_builtin
from rcb4hv.robot.kinematics import apply, compose, forward, link_pose, position, translation
from rcb4hv.robot.model import RobotModel


def limb_targets(
    model: RobotModel, link: str, n: int, spread: float, seed: int
) -> list[dict[str, float]]:
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        angles = dict(model.home)
        for j in ik.limb(model, link):
            home = model.home.get(j.name, 0.0)
            angles[j.name] = rng.uniform(max(j.lower, home - spread), min(j.upper, home + spread))
        out.append(angles)
    return out


def measure(model: RobotModel, link: str, mode: str, n: int) -> tuple[float, int, float]:
    """Worst error (mm), targets missed, mean ms per solve."""
    point = ik.effector_point(model, link)
    spread = math.inf if mode == "position" else 0.6
    worst, missed, spent = 0.0, 0, 0.0
    for angles in limb_targets(model, link, n, spread, seed=1):
        frame = compose(link_pose(model, link, angles), translation(point))
        target = position(frame) if mode == "position" else frame
        t0 = time.perf_counter()
        result = ik.solve(model, link, target, point=point)
        spent += time.perf_counter() - t0
        got = apply(link_pose(model, link, result.angles), point)
        err = math.dist(got, position(frame))
        missed += not result.reached
        if result.reached:
            worst = max(worst, err)
    return worst * 1000, missed, spent / n * 1000


def gait(model: RobotModel, steps: int = 100) -> tuple[float, float, bool]:
    """Worst foot error (mm), mean ms per pose, all reached."""
    home = forward(model, model.home)
    feet = [n for n, kind in ik.effectors(model).items() if kind == "foot"]
    angles = dict(model.home)
    worst, spent, ok = 0.0, 0.0, True
    for k in range(steps):
        phase = 2 * math.pi * k / steps
        torso = translation((0.0, 0.01 * math.sin(phase), -0.01 + 0.005 * math.cos(2 * phase)))
        lift = max(0.0, math.sin(phase))
        targets = {f: home[f] for f in feet}
        targets[feet[0]] = compose(
            translation((0.03 * (1 - math.cos(phase / 2)) / 2, 0.0, 0.02 * lift)), home[feet[0]]
        )
        t0 = time.perf_counter()
        result = ik.solve_feet(model, targets, torso, angles)
        spent += time.perf_counter() - t0
        angles = result.angles
        ok = ok and result.reached
        world = forward(model, angles, torso)
        worst = max(worst, *(math.dist(position(world[f]), position(targets[f])) for f in feet))
    return worst * 1000, spent / steps * 1000, ok


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=50)
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args(argv)
    rows = []
    for name in BUILTIN:
        model = load_builtin(name)
        for link in ik.effectors(model):
            for mode in ("position", "pose"):
                worst, missed, ms = measure(model, link, mode, args.samples)
                rows.append(
                    (name, link, mode, f"{worst:.3f}", f"{missed}/{args.samples}", f"{ms:.1f}")
                )
        worst, ms, ok = gait(model)
        rows.append(
            (name, "both feet", "gait", f"{worst:.3f}", "0/100" if ok else "some", f"{ms:.2f}")
        )
    head = ("model", "link", "target", "worst error mm", "missed", "ms / solve")
    if args.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for r in rows:
            print("| " + " | ".join(r) + " |")
    else:
        for r in (head, *rows):
            print("  ".join(f"{c:>14s}" for c in r))
    return 0


if __name__ == "__main__":
    sys.exit(main())
