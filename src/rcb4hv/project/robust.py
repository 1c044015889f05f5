"""How likely is a motion to fall on a robot like mine: many physics runs with the chosen
(unmeasured) constants drawn from documented ranges (:data:`RANGES`, docs/gait.md).

Each trial draws one :class:`~rcb4hv.physics.PhysicsOptions` from its own generator
(``numpy.random.SeedSequence(seed).spawn(trials)``: trial ``i`` draws the same numbers
whichever process or machine runs it) and plays the motions with
:func:`~rcb4hv.project.run.run_motions`. The trials run in a process pool
(:class:`concurrent.futures.ProcessPoolExecutor`) or as Ray tasks (``ray_address``); both
give the same numbers. Per motion: the fall probability with a Wilson 95 % interval and the
quartiles of displacement and turn.
"""

from __future__ import annotations

import math
import os
import signal
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np

from rcb4hv.physics import PhysicsOptions
from rcb4hv.robot.model import RobotModel
from rcb4hv.rom.layout import MotionLayout

__all__ = [
    "DEADBAND_MAX_DEG",
    "RANGES",
    "TILT_MAX_DEG",
    "Trial",
    "draw",
    "robust",
    "summarise",
    "wilson",
]

T = TypeVar("T")
R = TypeVar("R")

RANGES: Mapping[str, tuple[float, float]] = {
    "friction": (0.6, 1.4),
    "stiffness": (0.7, 1.3),
    "speed_cap": (0.8, 1.2),
    "armature": (0.7, 1.5),
    "mass": (0.9, 1.1),
}
"""Uniform ranges of the PhysicsOptions factors a trial draws (documented in docs/gait.md:
friction of a table or floor, the servo figures read off Kondo's data sheets, the model
masses estimated from parts)."""
TILT_MAX_DEG = 2.0
"""A trial's floor slopes 0..2 degrees, toward any direction (uniform)."""
DEADBAND_MAX_DEG = 0.5
"""A trial's servo dead band, 0..0.5 degrees (uniform): a documented choice (about four
position counts; Kondo sets the ICS dead band in the servo, its angle is not published)."""
Z95 = 1.959963984540054


def draw(rng: np.random.Generator) -> PhysicsOptions:
    """One trial's constants."""
    values = {k: float(rng.uniform(lo, hi)) for k, (lo, hi) in RANGES.items()}
    tilt = float(rng.uniform(0.0, TILT_MAX_DEG))
    direction = float(rng.uniform(0.0, 360.0))
    band = float(rng.uniform(0.0, DEADBAND_MAX_DEG))
    return PhysicsOptions(
        **values, floor_tilt_deg=tilt, floor_tilt_dir_deg=direction, deadband_deg=band
    )


@dataclass(frozen=True)
class Trial:
    """What one trial needs (picklable: sent to a worker process or a Ray task)."""

    image: bytes
    slots: tuple[int, ...]
    layout: MotionLayout
    robot: RobotModel
    seed: np.random.SeedSequence
    index: int


def run_trial(t: Trial) -> list[dict[str, Any]]:
    """Play the motions under one draw: per motion fell, dx_m, dy_m, dyaw_deg."""
    from rcb4hv.project.run import run_motions

    opts = draw(np.random.default_rng(t.seed))
    run = run_motions(t.image, list(t.slots), motion_layout=t.layout, robot=t.robot, options=opts)
    out = []
    for m in run.motions:
        o = m.outcome
        if o is None:
            raise RuntimeError(f"motion {m.result.slot}: a physics run without an outcome")
        out.append({"slot": m.result.slot, "fell": bool(o.fell), "dx_m": o.dx_m,
                    "dy_m": o.dy_m, "dyaw_deg": o.dyaw_deg})  # fmt: skip
    return out


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of ``k`` successes in ``n`` trials."""
    if n <= 0:
        return (0.0, 1.0)
    p = k / n
    d = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / d
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    lo = 0.0 if k == 0 else max(0.0, centre - half)
    hi = 1.0 if k == n else min(1.0, centre + half)
    return (lo, hi)


def _quartiles(xs: Sequence[float]) -> dict[str, float]:
    q1, med, q3 = np.percentile(np.asarray(xs, dtype=np.float64), [25, 50, 75])
    return {"median": float(med), "q1": float(q1), "q3": float(q3)}


def summarise(results: Sequence[Sequence[Mapping[str, Any]]]) -> list[dict[str, Any]]:
    """Per motion, over the trials: fall probability, its interval, displacement quartiles."""
    out = []
    for rows in zip(*results, strict=True):
        falls = sum(1 for r in rows if r["fell"])
        n = len(rows)
        lo, hi = wilson(falls, n)
        out.append(
            {
                "slot": rows[0]["slot"],
                "trials": n,
                "falls": falls,
                "fall_probability": falls / n,
                "ci": [lo, hi],
                "dx_m": _quartiles([r["dx_m"] for r in rows]),
                "dy_m": _quartiles([r["dy_m"] for r in rows]),
                "dyaw_deg": _quartiles([r["dyaw_deg"] for r in rows]),
            }
        )
    return out


def trials_of(
    image: bytes, slots: Sequence[int], layout: MotionLayout, robot: RobotModel, trials: int,
    seed: int,
) -> list[Trial]:  # fmt: skip
    seeds = np.random.SeedSequence(seed).spawn(trials)
    return [Trial(image, tuple(slots), layout, robot, s, i) for i, s in enumerate(seeds)]


def robust(
    image: bytes,
    slots: Sequence[int],
    *,
    layout: MotionLayout,
    robot: RobotModel,
    trials: int,
    seed: int = 0,
    workers: int | None = None,
    ray_address: str | None = None,
    use_ray: bool = False,
    progress: Callable[[int], object] | None = None,
) -> list[dict[str, Any]]:
    """Run ``trials`` draws of ``slots`` and summarise them per motion (module docstring).
    ``workers``: processes (default: the machine's cores; 1 runs in this process);
    ``use_ray``: Ray tasks instead, on ``ray_address`` (None: a local Ray)."""
    if trials < 1:
        raise ValueError("robust needs at least one trial")
    jobs = trials_of(image, slots, layout, robot, trials, seed)
    if use_ray:
        from rcb4hv.project.robust_ray import run_ray

        results = run_ray(run_trial, jobs, ray_address, progress)
    else:
        results = _run_pool(run_trial, jobs, workers or os.cpu_count() or 1, progress)
    return summarise(results)


def _ignore_sigint() -> None:
    """A pool process leaves Ctrl-C to its parent, which stops the pool (a terminal sends
    SIGINT to every process of the group: an idle worker printed a KeyboardInterrupt
    traceback)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _run_pool(
    fn: Callable[[T], R],
    jobs: Sequence[T],
    workers: int,
    progress: Callable[[int], object] | None,
) -> list[R]:
    """``fn`` of each job, in order: in this process (``workers`` 1) or a process pool."""
    out: list[R] = []
    if workers <= 1:
        for j in jobs:
            out.append(fn(j))
            if progress is not None:
                progress(1)
        return out
    pool = ProcessPoolExecutor(max_workers=workers, initializer=_ignore_sigint)
    try:
        for r in pool.map(fn, jobs):
            out.append(r)
            if progress is not None:
                progress(1)
    finally:  # an exception (Ctrl-C): the queued trials are dropped, the processes joined
        pool.shutdown(wait=True, cancel_futures=True)
    return out
