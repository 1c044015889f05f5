"""Search the gait parameters that make a walk least likely to fall (``rcb4hv gait tune``).

CMA-ES (Hansen's ``cma`` package, the ``[scale]`` extra) over the foot lift, the step time,
the double-support share and the feet's width, each in a documented range (:data:`BOUNDS`)
around the robot's defaults; the stride (or turn) and the steps are the user's command and
stay fixed. Each candidate walk is played in :func:`rcb4hv.project.robust.robust` trials
(the same seeds for every candidate, on the same local or Ray back end) and scored

    fall probability + SHORTFALL_WEIGHT * max(0, 1 - median progress / commanded)

so a walk that stands still by taking no step does not win.

:func:`tune` reports each evaluated candidate to an optional ``progress`` callback
(:class:`TuneProgress`) and, on Ctrl-C (a :class:`KeyboardInterrupt` anywhere in the search,
the callback included), stops and returns what it has: the best so far, in a
:class:`TuneResult` marked ``interrupted``.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from rcb4hv.errors import ScaleError
from rcb4hv.gait.generate import walk
from rcb4hv.gait.motion import walk_motion
from rcb4hv.gait.pattern import GaitParams
from rcb4hv.hth4.keyframes import add_motion
from rcb4hv.hth4.newproject import new_project, set_output_period
from rcb4hv.robot.model import RobotModel

__all__ = [
    "BOUNDS",
    "POPSIZE",
    "SHORTFALL_WEIGHT",
    "Candidate",
    "TuneProgress",
    "TuneResult",
    "planned",
    "progress_of",
    "score",
    "tune",
]

log = logging.getLogger(__name__)

BOUNDS: dict[str, tuple[float, float]] = {
    "lift": (0.5, 1.8),
    "step_time": (0.6, 1.6),
    "double_support": (0.1, 0.5),
    "width": (1.0, 1.6),
}
"""Searched ranges: lift, step time and width as factors of the robot's defaults, the
double-support share as itself. Documented choices (wide enough to matter, narrow enough
that every candidate is a walk the IK reaches)."""
SHORTFALL_WEIGHT = 0.5
POPSIZE = 4
"""Candidates CMA-ES asks for at a time (one generation)."""


@dataclass(frozen=True)
class Candidate:
    params: GaitParams
    fall_probability: float
    progress: float
    score: float


@dataclass(frozen=True)
class TuneProgress:
    """What :func:`tune` tells its ``progress`` callback after each evaluated candidate."""

    done: int
    """Candidates evaluated so far (1, 2, ...)."""
    total: int
    """Candidates planned: :func:`planned` of the budget (CMA-ES may stop sooner)."""
    best: Candidate
    """The best (lowest score) so far."""
    latest: Candidate
    """The candidate just evaluated."""


@dataclass(frozen=True)
class TuneResult:
    """What :func:`tune` found."""

    best: Candidate | None
    """The lowest score tried (the first of equals); None only when interrupted before any
    candidate was evaluated."""
    tried: list[Candidate]
    """Every candidate evaluated, in order."""
    interrupted: bool
    """The search was stopped by a :class:`KeyboardInterrupt` (Ctrl-C), not by its budget or
    CMA-ES's own criteria."""
    planned: int
    """Candidates planned (:func:`planned` of the budget)."""


def planned(evaluations: int) -> int:
    """The candidates a budget of ``evaluations`` plays: whole generations of :data:`POPSIZE`."""
    return -(-evaluations // POPSIZE) * POPSIZE


def _params(base: GaitParams, x: Sequence[float]) -> GaitParams:
    lift, step_time, ds, width = x
    return replace(
        base, lift=base.lift * lift, step_time=base.step_time * step_time,
        double_support=ds, width=base.width * width,
    )  # fmt: skip


def progress_of(direction: str, row: dict[str, Any]) -> float:
    """The median travel (m) or turn (degrees) along the commanded direction."""
    sign = -1.0 if direction in ("back", "right", "turn-right") else 1.0
    key = (
        "dyaw_deg"
        if direction.startswith("turn")
        else "dy_m"
        if direction in ("left", "right")
        else "dx_m"
    )
    return sign * float(row[key]["median"])


def score(fall: float, progress: float, commanded: float) -> float:
    return fall + SHORTFALL_WEIGHT * max(0.0, 1.0 - progress / commanded if commanded else 0.0)


def tune(
    model: RobotModel,
    base: GaitParams,
    *,
    trials: int,
    evaluations: int,
    seed: int = 0,
    period_ms: int = 15,
    run: Callable[..., list[dict[str, Any]]] | None = None,
    progress: Callable[[TuneProgress], object] | None = None,
    **backend: Any,
) -> TuneResult:
    """Search ``evaluations`` walks (whole generations of :data:`POPSIZE`; fewer if CMA-ES
    converges), each in ``trials`` trials, played at the output period ``period_ms``, the
    target project's; ``backend``: ``workers``, ``use_ray``, ``ray_address``. ``run`` stands
    in for :func:`rcb4hv.project.robust.robust` (tests).

    ``progress``, if given, is called after each evaluated candidate with a
    :class:`TuneProgress` (done, total, best so far). A :class:`KeyboardInterrupt` (Ctrl-C,
    or raised by ``progress``) stops the search: the trials of the candidate in play are
    stopped (the pool drops its queued trials and joins its processes; Ray's tasks not yet
    done are cancelled) and the result holds every candidate evaluated before, its ``best``
    (None if there was none) and ``interrupted=True``; the interrupt is not re-raised."""
    try:
        import cma
    except ImportError as exc:
        raise ScaleError("gait tune needs cma: pip install 'rcb4hv[scale]'") from exc
    from rcb4hv.project.relocate import project_image
    from rcb4hv.project.robust import robust

    go = run or robust
    lo = [BOUNDS[k][0] for k in BOUNDS]
    hi = [BOUNDS[k][1] for k in BOUNDS]
    x0 = [1.0, 1.0, base.double_support, 1.0]
    es = cma.CMAEvolutionStrategy(
        x0, 0.2, {"bounds": [lo, hi], "seed": seed + 1, "popsize": POPSIZE, "verbose": -9}
    )
    total = planned(evaluations)
    tried: list[Candidate] = []
    best: Candidate | None = None
    try:
        while len(tried) < evaluations and not es.stop():
            xs = es.ask()
            scores = []
            for x in xs:
                p = _params(base, x)
                w = walk(model, p, period_ms / 1000.0)
                motion = walk_motion(model, w, slot=2, name="tune", period=period_ms).motion
                project = set_output_period(new_project(model), period_ms)
                image, layout = project_image(add_motion(project, motion))
                (row,) = go(
                    image, [2], layout=layout, robot=model, trials=trials, seed=seed, **backend
                )
                prog = progress_of(p.direction, row)
                fall = row["fall_probability"]
                c = Candidate(p, fall, prog, score(fall, prog, p.commanded))
                log.info("candidate %s: %.3f", x, c.score)
                tried.append(c)
                scores.append(c.score)
                if best is None or c.score < best.score:
                    best = c
                if progress is not None:
                    progress(TuneProgress(len(tried), total, best, c))
            es.tell(xs, scores)
    except KeyboardInterrupt:
        log.info("the search was interrupted after %d of %d evaluations", len(tried), total)
        return TuneResult(best, tried, True, total)
    if len(tried) < evaluations:  # CMA-ES stopped: its criteria met (a flat score, say)
        log.warning(
            "the search stopped after %d of %d evaluations: %s",
            len(tried), evaluations, ", ".join(f"{k} {v:g}" for k, v in es.stop().items()),
        )  # fmt: skip
    return TuneResult(best, tried, False, total)
