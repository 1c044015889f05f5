"""How project settings that mean "none" become ROM: the named build options.

HeartToHeart4 stores ROM addresses in a project as .NET ``int`` values, and real projects hold
addresses that point at nothing:

* ``-1`` as a priority check's ``Address``: a check configured (port, comparison, value) with
  no motion chosen.
* ``-1`` as ``LowPowerMotionAddress`` (with ``LowPowerValue`` 0): the older low-battery hook
  switched off. Always "no check": the fixture project pairs ``-1`` with a battery priority
  check of its own, so ``-1`` cannot mean anything else.
* ``StartupMotionAddress`` naming a slot that holds no motion (the address outlives the motion
  it was chosen for: the project stores the address, not the motion).

The evidence for what HeartToHeart4 writes is thin (its programming manual is not public; the
firmware reference and command reference say nothing about priority checks), so each choice is
a named option with the best-supported default:

``priority_none``
    ``"stub"`` (default): the check is written as configured but CALLs the RETURN stub at
    3CB80h, exactly as HeartToHeart4 handles a startup motion of ``-1`` (spec 11.2, the only
    "none" whose ROM form is known): nothing runs when the comparison holds. ``"skip"``: the
    check is left unused (the main-loop slot jumps over itself, as for an entry without a
    value). Both play identically; they differ in the bytes written.
``empty_startup``
    ``"call"`` (default): the boot program CALLs the address as stored, as HeartToHeart4 does
    with any address it holds; on the board this runs whatever the slot holds, and an erased
    slot stops the boot with ROMERR (``project simulate`` reports it, ``project check`` calls it
    an error). ``"stub"``: a startup address where no motion starts is written as "none" (the
    RETURN stub), so the board boots into the main loop.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final, Literal

__all__ = ["DEFAULT_OPTIONS", "EMPTY_STARTUP", "PRIORITY_NONE", "BuildOptions"]

PriorityNone = Literal["stub", "skip"]
EmptyStartup = Literal["call", "stub"]
PRIORITY_NONE: Final = ("stub", "skip")
EMPTY_STARTUP: Final = ("call", "stub")


@dataclass(frozen=True)
class BuildOptions:
    """Named choices for settings that mean "none" (see the module docstring)."""

    priority_none: PriorityNone = "stub"
    empty_startup: EmptyStartup = "call"

    def __post_init__(self) -> None:
        if self.priority_none not in PRIORITY_NONE:
            raise ValueError(f"priority_none must be one of {PRIORITY_NONE}")
        if self.empty_startup not in EMPTY_STARTUP:
            raise ValueError(f"empty_startup must be one of {EMPTY_STARTUP}")


DEFAULT_OPTIONS: Final = BuildOptions()
