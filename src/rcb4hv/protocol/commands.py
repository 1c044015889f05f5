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
:mod:`.servocmds`. Each owns its codec; :mod:`.registry` is the one table of them. Import
them from :mod:`rcb4hv.protocol`; this module holds the two codec functions.
"""

from __future__ import annotations

from typing import cast

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.frame import check_frame
from rcb4hv.protocol.registry import DECODERS, Command

__all__ = ["decode_command", "encode_command"]


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
