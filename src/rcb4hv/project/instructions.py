"""What the simulator says about instructions and boot failures, in words.

* :func:`input_names` / :func:`ics_operands`: which inputs (RAM the program does not own) and
  which ICS operands a data command reads - used to classify waiting loops and command errors.
* :func:`boot_cause`: why the boot program of a HeartToHeart4 2.2 image stopped, e.g.
  ``"startup motion 0FB80h: slot 31 holds no motion; ROMERR ..."``.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol import (
    Add,
    And,
    Call,
    Command,
    Div,
    Ics,
    Mod,
    Move,
    Mul,
    Not,
    Or,
    Ram,
    Shift,
    Sub,
    Xor,
    decode_command,
    frame_at,
)
from rcb4hv.rom import layout

__all__ = ["boot_cause", "ics_operands", "input_names", "slot_problem"]

# RAM that changes from outside the program: (first, last, name)
_INPUTS: Final = (
    (0x0022, 0x0037, "AD"),
    (0x003A, 0x003B, "PIO"),
    (0x003C, 0x0043, "timer"),
    (0x0350, 0x0351, "buttons"),
    (0x0352, 0x0355, "PA"),
)

_DATA: Final = (Move, And, Or, Xor, Add, Sub, Mul, Div, Mod, Not, Shift)


def _operands(cmd: Command) -> list[object]:
    ops: list[object] = []
    for attr in ("dst", "src"):
        v = getattr(cmd, attr, None)
        if v is not None:
            ops.append(v)
    return ops


def ics_operands(cmd: Command) -> list[int]:
    """ICS numbers a data command addresses through ``ICS(offset, n)`` operands."""
    if not isinstance(cmd, _DATA):
        return []
    return [o.ics for o in _operands(cmd) if isinstance(o, Ics)]


def input_names(cmd: Command) -> list[str]:
    """Inputs (RAM the program does not own) a data command reads."""
    if not isinstance(cmd, _DATA):
        return []
    size = cmd.nbytes
    names: list[str] = []
    for op in _operands(cmd):
        if isinstance(op, Ics):
            if op.offset in (4, 5):
                names.append(f"ICS {op.ics} measured value")
            continue
        if not isinstance(op, Ram):
            continue
        a0, a1 = op.address, op.address + size - 1
        for lo, hi, kind in _INPUTS:
            if a0 > hi or a1 < lo:
                continue
            if kind == "AD":
                first = max(0, (a0 - lo) // 2)
                last = min(10, (a1 - lo) // 2)
                names += [f"AD{n}" for n in range(first, last + 1)]
            elif kind == "PA":
                names += [f"PA{n - lo + 1}" for n in range(max(a0, lo), min(a1, hi) + 1)]
            else:
                names.append(kind)
    return names


def slot_problem(rom: bytes | bytearray, address: int) -> str | None:
    """Why no motion starts at ``address`` of a 2.2 image, in words, or None if one does."""
    if address >= layout.ROM_SIZE:
        return "past the 256 KB ROM"
    slot = layout.motion_number(address)
    if slot is None:
        return None if address == layout.STARTUP_STUB else "outside the motion slots"
    start = layout.motion_address(slot)
    if rom[start] == layout.ERASED:
        return f"slot {slot} holds no motion"
    if address != start:
        return f"inside slot {slot}, not at its start"
    return None


def boot_cause(rom: bytes | bytearray, error: str, pc: int | None) -> str:
    """The boot failure ``error`` (stopped at ``pc``) with its cause in words."""
    try:
        start = decode_command(frame_at(rom, layout.STARTUP_CALL))
    except ProtocolError:
        start = None
    if pc is not None and pc < layout.STARTUP_CALL:
        return f"boot code: {error}"
    if pc is not None and layout.MAIN_LOOP <= pc < layout.MOTIONS:
        return f"main loop: {error}"
    if not isinstance(start, Call):
        return f"startup: {error}"
    target = start.address
    problem = slot_problem(rom, target)
    if problem is not None:
        return f"startup motion {target:05X}h: {problem}; {error}"
    slot = layout.motion_number(target)
    where = f" (slot {slot})" if slot is not None else ""
    return f"startup motion {target:05X}h{where}: {error}"
