"""What stops the emulated ROM program, and the internal signals the board units raise.

:class:`Stop` is public (:attr:`~rcb4hv.emulator.Board.last_stop`): hosts and the simulator
read why the program stopped instead of guessing from RAM. :class:`CommandError` and
:class:`BoardReset` never leave the emulator: a command that cannot execute becomes a NAK
(from COM) or a program stop (from ROM), a reset re-runs power-on.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

__all__ = ["BoardReset", "CommandError", "Stop", "StopKind"]

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


class CommandError(Exception):
    """A command that cannot execute: NAK from COM, program stop from ROM."""

    def __init__(self, why: str, what: StopKind = "command-error") -> None:
        super().__init__(why)
        self.what: StopKind = what


class BoardReset(Exception):
    """The board resets (config ``series_servo="reset"``)."""
