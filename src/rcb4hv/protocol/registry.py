"""The one command table: every command class with its command byte, mnemonic and decoder.

Each command class owns its codec (``encode()`` and the ``from_frame`` parser, in
:mod:`.datacmds`, :mod:`.branches` and :mod:`.servocmds`). This table is the only place
that lists the classes; everything keyed by command is derived from it:

* :func:`~rcb4hv.protocol.commands.decode_command` looks the decoder up by command byte
  (:data:`DECODERS`);
* :mod:`rcb4hv.protocol.describe` takes a binary operation's operator (``&=``) from here;
* the assembler and disassembler (:mod:`rcb4hv.asm`) take every mnemonic from here;
* the emulator's interpreter builds its dispatch, keyed by class, from :data:`COMMANDS`
  (and its ALU is indexed by the command byte).

``tests/protocol/test_registry.py`` checks that every command class is here exactly once
and that nothing else holds a copy.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Final

from rcb4hv.protocol.branches import Call, CommunicateDevice, Jump, Return
from rcb4hv.protocol.datacmds import (
    Add,
    And,
    Div,
    Mod,
    Move,
    Mul,
    Not,
    Or,
    Shift,
    Sub,
    Xor,
)
from rcb4hv.protocol.servocmds import (
    AcknowledgeCheck,
    GetVersionInfo,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
)

__all__ = [
    "BINARY_OPS",
    "BY_MNEMONIC",
    "COMMANDS",
    "DECODERS",
    "SPECS",
    "Command",
    "CommandSpec",
    "Decoder",
    "spec_of",
]

Command = (
    Move
    | And
    | Or
    | Xor
    | Not
    | Shift
    | Add
    | Sub
    | Mul
    | Div
    | Mod
    | Jump
    | Call
    | Return
    | CommunicateDevice
    | RunSingleServo
    | RunConstFrameServo
    | RunSeriesServo
    | SetStretch
    | SetSpeed
    | GetVersionInfo
    | AcknowledgeCheck
)

Decoder = Callable[[bytes], object]
"""A frame (checksum already checked) -> its command; ``ProtocolError``/``ValueError`` if bad."""


@dataclass(frozen=True, slots=True)
class CommandSpec:
    """One row of the command table."""

    cls: type
    opcode: int
    """The command byte (CMD field of the frame)."""
    mnemonic: str
    """The assembler mnemonic (``SHIFT`` is also written ``SHL``/``SHR``)."""
    symbol: str | None
    """For the binary operations AND..MOD: the operator (``&=``), else None."""
    decode: Decoder
    """The class's own frame parser (``cls.from_frame``)."""


def _spec(cls: type, mnemonic: str, symbol: str | None = None) -> CommandSpec:
    return CommandSpec(cls, cls.cmd, mnemonic, symbol, cls.from_frame)  # type: ignore[attr-defined]


COMMANDS: Final[tuple[CommandSpec, ...]] = (
    _spec(Move, "MOVE"),
    _spec(And, "AND", "&="),
    _spec(Or, "OR", "|="),
    _spec(Xor, "XOR", "^="),
    _spec(Not, "NOT"),
    _spec(Shift, "SHIFT"),
    _spec(Add, "ADD", "+="),
    _spec(Sub, "SUB", "-="),
    _spec(Mul, "MUL", "*="),
    _spec(Div, "DIV", "/="),
    _spec(Mod, "MOD", "%="),
    _spec(Jump, "JUMP"),
    _spec(Call, "CALL"),
    _spec(Return, "RETURN"),
    _spec(CommunicateDevice, "ICSCOMM"),
    _spec(RunSingleServo, "SERVO"),
    _spec(RunConstFrameServo, "SERVOS"),
    _spec(RunSeriesServo, "SERIES"),
    _spec(SetStretch, "STRETCH"),
    _spec(SetSpeed, "SPEED"),
    _spec(GetVersionInfo, "VERSION"),
    _spec(AcknowledgeCheck, "ACKCHECK"),
)
"""Every command, in command-byte order."""

SPECS: Final[Mapping[type, CommandSpec]] = {s.cls: s for s in COMMANDS}
"""The table keyed by class."""

BY_MNEMONIC: Final[Mapping[str, CommandSpec]] = {s.mnemonic: s for s in COMMANDS}
"""The table keyed by assembler mnemonic."""

BINARY_OPS: Final[tuple[CommandSpec, ...]] = tuple(s for s in COMMANDS if s.symbol is not None)
"""The binary operations AND..MOD (``dst op= src``)."""


def _decoders() -> dict[int, Decoder]:
    out: dict[int, Decoder] = {}
    for s in COMMANDS:
        known = out.setdefault(s.opcode, s.decode)
        # two classes share a command byte only if they share its parser (12h: SetStretch
        # and SetSpeed, told apart by the sub-command byte)
        same = getattr(known, "__func__", known) is getattr(s.decode, "__func__", s.decode)
        assert same, f"command byte {s.opcode:02X}h has two decoders"
    return out


DECODERS: Final[Mapping[int, Decoder]] = _decoders()
"""Command byte -> decoder."""


def spec_of(cls: type) -> CommandSpec:
    """The table row of command class ``cls`` (KeyError for anything else)."""
    return SPECS[cls]
