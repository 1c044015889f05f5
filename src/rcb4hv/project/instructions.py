"""What the simulator says about instructions and boot failures, in words.

* :func:`input_names` / :func:`ics_operands`: which inputs (RAM the program does not own) and
  which ICS operands a data command reads - used to classify waiting loops and command errors.
* :func:`boot_cause`: why the boot program of a HeartToHeart4 2.2 image stopped, e.g.
  ``"startup motion 0FB80h: slot 31 holds no motion; ROMERR ..."``.
* :func:`instruction_at`: the instruction at a ROM address and its disassembly;
  :func:`stop_reason`: why the board's program stopped, in the simulator's words.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.asm import format_command
from rcb4hv.emulator import Board, Stop
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
from rcb4hv.protocol.memory import AD_CHANNELS, ADDR, SERVO, TIMERS
from rcb4hv.rom import layout

__all__ = [
    "boot_cause",
    "ics_operands",
    "input_names",
    "instruction_at",
    "slot_problem",
    "stop_reason",
]

# RAM that changes from outside the program: (first, last, name)
_INPUTS: Final = (
    (ADDR.AD_VALUES, ADDR.AD_VALUES + AD_CHANNELS.size - 1, "AD"),
    (ADDR.PIO_DATA, ADDR.PIO_DATA + 1, "PIO"),
    (ADDR.TIMERS[0], ADDR.TIMERS[0] + TIMERS.size - 1, "timer"),
    (ADDR.BUTTONS, ADDR.BUTTONS + 1, "buttons"),
    (ADDR.PA[0], ADDR.PA[-1], "PA"),
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
            if op.offset in (SERVO.MEASURED, SERVO.MEASURED + 1):
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
                last = min(ADDR.AD_COUNT - 1, (a1 - lo) // 2)
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


# Decoded instructions by their exact frame bytes (pure: the same bytes always decode alike).
_DECODED: dict[bytes, tuple[Command | None, str]] = {}

_STOP_WORDS: Final[dict[str, str]] = {
    "romerr": "ROMERR (checksum error in ROM)",
    "stack-underflow": "call-stack underflow (RETURN on an empty stack)",
    "stack-overflow": "call-stack overflow (17th nested CALL)",
    "suspended": "stopped by the host (ROM_F cleared)",
}
"""How a :class:`~rcb4hv.project.simresult.MotionResult` names the board's stop kinds
(:class:`rcb4hv.emulator.Stop`)."""


def instruction_at(rom: bytes | bytearray, pc: int) -> tuple[Command | None, str]:
    """The instruction at ``pc`` of ``rom`` (None if it does not decode) and its disassembly
    (``.byte ...`` for bytes that are no instruction)."""
    try:
        frame = frame_at(rom, pc)
    except ProtocolError:
        return None, f".byte {bytes(rom[pc : pc + 16]).hex(' ')}"
    known = _DECODED.get(frame)
    if known is not None:
        return known
    try:
        cmd = decode_command(frame)
    except ProtocolError:
        result: tuple[Command | None, str] = (None, f".byte {frame[:16].hex(' ')}")
    else:
        result = (cmd, format_command(cmd))
    if len(_DECODED) < 4096:
        _DECODED[frame] = result
    return result


def stop_reason(board: Board, before: Stop | None) -> tuple[str, int, str]:
    """(kind, PC, disassembly) of the instruction that stopped ``board``'s program.

    The one place the stop reason is read: the board's own record
    (:attr:`rcb4hv.emulator.Board.last_stop`), in the simulator's words. A stop the board did
    not record since ``before`` (the program cleared ROM_F itself) is a plain "program
    stopped".
    """
    stop = board.last_stop
    if stop is None or stop is before or not stop.halted:
        pc = board.pc
        return "program stopped (ROM_F cleared)", pc, instruction_at(board.rom, pc)[1]
    pc = stop.where
    text = instruction_at(board.rom, pc)[1]
    kind = _STOP_WORDS.get(stop.what)
    if kind is not None:
        return kind, pc, text
    reason = stop.why
    if stop.instruction is not None:
        reason = reason.removesuffix(f": {stop.instruction}")
        return f"command error: {reason}", pc, text
    return f"invalid instruction ({reason})", pc, text
