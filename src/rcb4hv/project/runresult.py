"""What a run of motions reports (:func:`rcb4hv.project.run.run_motions`), with or without
physics: :class:`MotionRun` per motion and :class:`SimulationRun` for the whole run, and the one
JSON vocabulary of ``project simulate --json`` (:meth:`SimulationRun.to_dict`)."""

from __future__ import annotations

from dataclasses import dataclass

from rcb4hv.project.physicsresult import PhysicsOutcome, PhysicsSetup, ShapeFrame, TrackPoint
from rcb4hv.project.simresult import MotionResult
from rcb4hv.robot.stride import Stride

__all__ = ["MotionRun", "SimulationRun"]


@dataclass(frozen=True)
class MotionRun:
    """One motion of a run: how it played (``result``), the board time it started at
    (``start_s``) and, with physics, what it did to the robot (``outcome``) and, with
    ``track``, the robot's path and pictures from the motion's start until it has settled
    after its end."""

    result: MotionResult
    outcome: PhysicsOutcome | None = None
    track: tuple[TrackPoint, ...] = ()
    frames: tuple[ShapeFrame, ...] = ()
    start_s: float = 0.0
    stride: Stride | None = None

    def to_dict(self) -> dict[str, object]:
        d = self.result.to_dict()
        d["start_s"] = round(self.start_s, 6)
        if self.outcome is not None:
            d["physics"] = self.outcome.to_dict()
        if self.stride is not None:
            d["stride"] = self.stride.to_dict()
        return d


@dataclass(frozen=True)
class SimulationRun:
    """A run: the (first) boot, each motion, the virtual seconds simulated in all (board time,
    boots and settling included) and the wall seconds it took; ``physics`` None without."""

    boot: MotionResult
    motions: tuple[MotionRun, ...]
    virtual_s: float
    wall_s: float = 0.0
    physics: PhysicsSetup | None = None

    @property
    def results(self) -> list[MotionResult]:
        return [m.result for m in self.motions]

    def summary(self) -> dict[str, int]:
        """How many motions ended in each status."""
        out: dict[str, int] = {}
        for r in self.results:
            out[r.status] = out.get(r.status, 0) + 1
        return out

    def to_dict(self) -> dict[str, object]:
        """``project simulate --json``: ``boot``, ``motions``, ``summary``, ``virtual_s``,
        ``wall_s`` and, with physics, ``physics`` (the set-up; each motion then has its
        ``physics`` outcome)."""
        d: dict[str, object] = {
            "boot": self.boot.to_dict(),
            "motions": [m.to_dict() for m in self.motions],
            "summary": self.summary(),
            "virtual_s": round(self.virtual_s, 6),
            "wall_s": round(self.wall_s, 3),
        }
        if self.physics is not None:
            d["physics"] = self.physics.to_dict()
        return d
