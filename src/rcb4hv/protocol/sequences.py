"""Host command sequences that drive the ROM program: pure functions returning the commands.

One place for the spec 11.4 play sequence and its relatives. Each function takes the current
system register word (read it with :func:`system_query`) and returns the commands to send in
order; nothing here does I/O, so the client (:class:`rcb4hv.client.Robot`), the simulator
(:mod:`rcb4hv.project.simulate`) and the uploader (:mod:`rcb4hv.project.upload`) send the same
frames.

``main_loop`` is the ROM address of the image's main loop
(:attr:`rcb4hv.rom.layout.MotionLayout.main_loop`: 0044Bh for HeartToHeart4 2.2, 003FDh for
older images).
"""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol.branches import ALWAYS, Call
from rcb4hv.protocol.datacmds import Move
from rcb4hv.protocol.memory import ADDR, SYS, program_reset, system_word_bytes
from rcb4hv.protocol.operands import Com, Data, Ram
from rcb4hv.protocol.registry import Command

__all__ = [
    "PLAY_FLAGS",
    "play_motion",
    "reset_program",
    "restart_program",
    "resume_program",
    "set_system",
    "stop_program",
    "suspend_program",
    "system_query",
]

PLAY_FLAGS: Final = SYS.ICS_OUTPUT | SYS.ROM_RUN | SYS.VECTOR_JUMP
"""The flags a play clears while it sets the program up and sets again to run it."""


def system_query() -> Move:
    """Read the system register word (2 bytes from RAM 0000h)."""
    return Move(Com(), Ram(ADDR.SYSTEM), 2)


def set_system(word: int) -> Move:
    """Write the system register word."""
    return Move(Ram(ADDR.SYSTEM), Data(system_word_bytes(word)))


def reset_program(pc: int) -> Move:
    """Point the program at ``pc`` with an empty call stack and no update flags
    (10 bytes at RAM 0002h; spec 11.4 step 2)."""
    return Move(Ram(ADDR.PC), Data(program_reset(pc)))


def play_motion(
    word: int,
    address: int,
    main_loop: int,
    *,
    vector: bool = True,
    clear_rom_error: bool = False,
) -> list[Command]:
    """Spec 11.4: suspend (ICS_F, ROM_F, VEC_F cleared), reset the program to ``main_loop``,
    CALL ``address``, resume with ICS_F and ROM_F set (and VEC_F unless ``vector=False``).

    ``clear_rom_error`` also clears ROMERR in both system register writes (the simulator's
    choice, so a play after a failed one starts clean).
    """
    base = word & ~(PLAY_FLAGS | (SYS.ROM_ERROR if clear_rom_error else 0))
    flags = SYS.ICS_OUTPUT | SYS.ROM_RUN | (SYS.VECTOR_JUMP if vector else 0)
    return [
        set_system(base),
        reset_program(main_loop),
        Call(address, ALWAYS),
        set_system(base | flags),
    ]


def suspend_program(word: int) -> list[Command]:
    """Pause the ROM program where it is (ROM_F cleared)."""
    return [set_system(word & ~SYS.ROM_RUN)]


def resume_program(word: int) -> list[Command]:
    """Let the ROM program run on (ROM_F set)."""
    return [set_system(word | SYS.ROM_RUN)]


def stop_program(word: int, main_loop: int, *, reset: bool = True) -> list[Command]:
    """Stop what the program does. With ``reset`` the PC goes back to ``main_loop`` and the
    program runs on there (the board's idle state); without it the program is paused."""
    if not reset:
        return suspend_program(word)
    return [*suspend_program(word), reset_program(main_loop), *resume_program(word)]


def restart_program(word: int, pc: int = 0) -> list[Command]:
    """Run the image from ``pc`` (default 000000h, power-on) with ROMERR cleared: the end
    of an upload. The program should be suspended first (:func:`suspend_program`)."""
    return [reset_program(pc), set_system((word & ~SYS.ROM_ERROR) | SYS.ROM_RUN)]
