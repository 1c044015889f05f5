"""What stops the emulated ROM program.

:class:`Stop` is public (:attr:`~rcb4hv.emulator.Board.last_stop`): hosts and the simulator
read why the program stopped instead of guessing from RAM. The signals the board units raise
live in :mod:`rcb4hv.errors` and never leave the emulator:
:class:`~rcb4hv.errors.EmulatedCommandError` (a command that cannot execute becomes a NAK from
COM or a program stop from ROM) and :class:`~rcb4hv.errors.EmulatedReset` (power-on again).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, Literal, cast, get_args

__all__ = ["STOP_KINDS", "Stop", "StopKind", "stop_kind"]

StopKind = Literal[
    "romerr",  # fetch error: erased ROM, bad SIZE or checksum, PC past the ROM (sets ROMERR)
    "command-error",  # a ROM instruction that is not a command, or that cannot execute
    "stack-overflow",  # a 17th nested CALL (from ROM or a vector package)
    "stack-underflow",  # RETURN on an empty call stack
    "return-to-host",  # RETURN popped the address a host (COM) CALL pushed: the routine ended
    "suspended",  # a host command cleared ROM_F
]


@dataclass(frozen=True, slots=True)
class Stop:
    """Why the ROM program last stopped (or its host-called routine returned).

    ``what`` is the kind, ``where`` the PC of the instruction concerned (for ``suspended``,
    the PC the program was stopped at), ``why`` one line in words that names the
    instruction, and ``instruction`` its text alone (None when ROM holds no instruction
    there). Every kind but ``return-to-host`` clears ROM_F; ``romerr`` also sets ROMERR.
    """

    what: StopKind
    where: int
    why: str
    instruction: str | None = None

    @property
    def halted(self) -> bool:
        """True when the program no longer runs (ROM_F cleared)."""
        return self.what != "return-to-host"


STOP_KINDS: Final = frozenset(get_args(StopKind))


def stop_kind(what: str) -> StopKind:
    """``what`` (the kind an :class:`~rcb4hv.errors.EmulatedCommandError` carries) as a
    :data:`StopKind`; ValueError for anything else."""
    if what not in STOP_KINDS:
        raise ValueError(f"not a stop kind: {what!r}")
    return cast(StopKind, what)
