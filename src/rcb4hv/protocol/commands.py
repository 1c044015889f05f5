"""One frozen dataclass per command of the RCB-4HV command reference, with encode/decode.

Every class validates its fields on construction (``ValueError`` for anything out of range),
:func:`encode_command` turns a command into its frame and :func:`decode_command` turns a frame
back into a command, raising :class:`~rcb4hv.errors.ProtocolError` for anything that is not a
valid command frame. ``decode_command(encode_command(c)) == c`` and
``encode_command(decode_command(f)) == f`` hold for every command and every valid frame.

Operands of the data commands (spec section 4) are small typed objects: :class:`Ram`,
:class:`Ics`, :class:`Rom` and :class:`Com` as destinations, :class:`Ram`, :class:`Ics`,
:class:`Rom` and :class:`Data` (literal bytes carried in the frame) as sources.

The classes live by what they do: operands and sizes in :mod:`.operands`, the data commands
in :mod:`.datacmds`, control flow in :mod:`.branches`, servo and system commands in
:mod:`.servocmds`. Each owns its codec; :mod:`.registry` is the one table of them. This
module is the stable import point for all of it.
"""

from __future__ import annotations

from typing import cast

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.branches import ALWAYS, Call, CommunicateDevice, Condition, Jump, Return
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
from rcb4hv.protocol.frame import check_frame
from rcb4hv.protocol.operands import (
    ICS_COUNT,
    KIND_COM,
    KIND_ICS,
    KIND_RAM,
    KIND_ROM,
    MAX_LITERAL,
    POSITION_FREE,
    POSITION_HOLD,
    POSITION_MAX,
    POSITION_MIN,
    RAM_SIZE,
    ROM_SIZE,
    Com,
    Data,
    Destination,
    Ics,
    Op,
    Ram,
    Rom,
    Source,
    is_valid_position,
)
from rcb4hv.protocol.registry import DECODERS, Command
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
    "ALWAYS",
    "ICS_COUNT",
    "KIND_COM",
    "KIND_ICS",
    "KIND_RAM",
    "KIND_ROM",
    "MAX_LITERAL",
    "POSITION_FREE",
    "POSITION_HOLD",
    "POSITION_MAX",
    "POSITION_MIN",
    "RAM_SIZE",
    "ROM_SIZE",
    "AcknowledgeCheck",
    "Add",
    "And",
    "Call",
    "Com",
    "Command",
    "CommunicateDevice",
    "Condition",
    "Data",
    "Destination",
    "Div",
    "GetVersionInfo",
    "Ics",
    "Jump",
    "Mod",
    "Move",
    "Mul",
    "Not",
    "Op",
    "Or",
    "Ram",
    "Return",
    "Rom",
    "RunConstFrameServo",
    "RunSeriesServo",
    "RunSingleServo",
    "SetSpeed",
    "SetStretch",
    "Shift",
    "Source",
    "Sub",
    "Xor",
    "decode_command",
    "encode_command",
    "is_valid_position",
]


def encode_command(cmd: Command) -> bytes:
    """The frame of ``cmd``."""
    return cmd.encode()


def decode_command(frame: bytes | bytearray | memoryview) -> Command:
    """Decode one whole command frame; raise ProtocolError if it is not a valid command."""
    frame = bytes(frame)
    check_frame(frame)
    decoder = DECODERS.get(frame[1])
    if decoder is None:
        raise ProtocolError(f"unknown command byte {frame[1]:02X}")
    try:
        return cast(Command, decoder(frame))
    except ValueError as exc:
        raise ProtocolError(f"invalid {frame[1]:02X}h command: {exc}") from exc
