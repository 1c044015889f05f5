"""What a simulated play reports: :class:`MotionResult` and its :data:`Status` (see
:mod:`rcb4hv.project.simulate` for what each status means)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = ["MotionResult", "Status"]

Status = Literal["completed", "waiting", "holding", "stalled", "timeout", "error"]


@dataclass(frozen=True)
class MotionResult:
    """How one motion played (see the module docstring for ``status``)."""

    slot: int | None
    address: int
    name: str
    status: Status
    duration: float
    instructions: int
    error: str | None = None
    pc: int | None = None
    instruction: str | None = None
    loop: tuple[int, int] | None = None
    inputs: tuple[str, ...] = ()
    held: str | None = None

    @property
    def ok(self) -> bool:
        return self.status in ("completed", "waiting", "holding")

    def to_dict(self) -> dict[str, object]:
        return {
            "slot": self.slot,
            "address": f"{self.address:05X}",
            "name": self.name,
            "status": self.status,
            "duration_s": round(self.duration, 6),
            "instructions": self.instructions,
            "error": self.error,
            "pc": None if self.pc is None else f"{self.pc:05X}",
            "instruction": self.instruction,
            "loop": None if self.loop is None else [f"{a:05X}" for a in self.loop],
            "inputs": list(self.inputs),
            "held": self.held,
        }

    @property
    def detail(self) -> str:
        """One line: the error, the waiting loop, or nothing."""
        if self.status == "error":
            where = "" if self.pc is None else f" at {self.pc:05X}h"
            ins = f": {self.instruction}" if self.instruction else ""
            return f"{self.error}{where}{ins}"
        if self.status == "holding" and self.loop is not None:
            sensors = ", ".join(self.inputs)
            return f"loop {self.loop[0]:05X}-{self.loop[1]:05X}h: servos mixed from {sensors}"
        if self.loop is not None:
            what = ", ".join(self.inputs) if self.inputs else "nothing"
            return f"loop {self.loop[0]:05X}-{self.loop[1]:05X}h reads {what}"
        if self.status == "timeout":
            why = "without progress" if self.error == "no progress" else "after the limit"
            return f"PC {self.pc:05X}h {why}" if self.pc is not None else ""
        return ""
