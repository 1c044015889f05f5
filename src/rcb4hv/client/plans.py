"""RAM and ROM transfers as *plans*: generators that yield the command frames to send and are
sent each reply (``reply = yield command``), so a client of any kind (the asyncio one, a test
driver) runs the same chunking and verifying without owning a link.

Both clients run these plans (:meth:`rcb4hv.client.Rcb4Client.run_plan`); the chunk sizes
:data:`MAX_WRITE` and :data:`ROM_WRITE_CHUNK` are defined here (a read takes
:data:`rcb4hv.protocol.MAX_READ` bytes a frame).
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from typing import Final, TypeVar

from rcb4hv.errors import ArgumentError, ArgumentTypeError, FrameError, VerifyError
from rcb4hv.protocol import (
    MAX_READ,
    RAM_SIZE,
    ROM_SIZE,
    Com,
    Command,
    Data,
    DataReply,
    Move,
    Ram,
    Reply,
    Rom,
)
from rcb4hv.protocol.operands import MAX_LITERAL
from rcb4hv.values import as_index, plain

__all__ = [
    "MAX_READ",
    "Plan",
    "check_span",
    "data_of",
    "read_memory",
    "write_ram",
    "write_rom",
]

T = TypeVar("T")
Plan = Generator[Command, Reply, T]
"""A multi-frame operation: yields each command, is sent its reply, returns the result."""

MAX_WRITE: Final = MAX_LITERAL
"""Literal bytes one MOVE can carry in a 128-byte command frame."""
ROM_WRITE_CHUNK: Final = 64
"""ROM writes go in 64-byte chunks aligned on 64-byte boundaries: one chunk fits a MOVE literal
(at most 121 bytes) and never straddles an EEPROM write page (64 or 128 bytes on the parts
used in this board family), so no page write ever wraps around inside its page."""

Progress = Callable[[int, int], None]
"""Progress callback: ``progress(done_bytes, total_bytes)``."""


def check_span(kind: str, address: object, size: object, limit: int) -> None:
    """ArgumentTypeError unless ``address`` and ``size`` are ints (numpy integers too, not
    bools); ArgumentError (a ValueError) unless the span is 1 byte or more inside 0..limit-1."""
    a, n = as_index(address), as_index(size)
    if a is None or n is None:
        raise ArgumentTypeError(
            f"{kind} address and size must be ints, not {plain(address)} and {plain(size)}"
        )
    if n < 1:
        raise ArgumentError(f"{kind} size {n} must be at least 1")
    if a < 0 or a + n > limit:
        raise ArgumentError(f"{kind} {a:#x}+{n} runs outside 0..{limit - 1:#x}")


def data_bytes(kind: str, data: object) -> bytes:
    """``data`` to write as bytes: bytes, bytearray, memoryview or a sequence of ints 0..255.
    An int (``bytes(5)`` would be five zero bytes), a str or anything else is an
    ArgumentTypeError; an item outside 0..255 an ArgumentError."""
    if isinstance(data, bytes | bytearray | memoryview):
        return bytes(data)
    if isinstance(data, str | int) or not hasattr(data, "__iter__"):
        raise ArgumentTypeError(f"{kind} data must be bytes, not {plain(data)}")
    try:
        return bytes(data)
    except TypeError:
        raise ArgumentTypeError(f"{kind} data must be bytes or ints 0..255") from None
    except ValueError:
        raise ArgumentError(f"{kind} data: every byte is 0..255") from None


def data_of(reply: Reply, command: Command) -> bytes:
    """The data of a data reply; FrameError for any other reply."""
    if not isinstance(reply, DataReply):
        raise FrameError(f"expected a data reply to {type(command).__name__}, got {reply}")
    return reply.data


def read_memory(
    kind: str, address: int, size: int, progress: Progress | None = None
) -> Plan[bytes]:
    """Read ``size`` bytes of ``"RAM"`` or ``"ROM"`` in 128-byte MOVEs to COM."""
    rom = kind == "ROM"
    check_span(kind, address, size, ROM_SIZE if rom else RAM_SIZE)
    out = bytearray()
    for a in range(address, address + size, MAX_READ):
        n = min(MAX_READ, address + size - a)
        command = Move(Com(), Rom(a) if rom else Ram(a), n)
        out += data_of((yield command), command)
        if progress is not None:
            progress(len(out), size)
    return bytes(out)


def write_ram(address: int, data: bytes) -> Plan[None]:
    """Write ``data`` to RAM, 121 bytes per MOVE literal."""
    data = data_bytes("RAM", data)
    check_span("RAM", address, len(data), RAM_SIZE)
    for i in range(0, len(data), MAX_WRITE):
        yield Move(Ram(address + i), Data(data[i : i + MAX_WRITE]))


def write_rom(
    address: int, data: bytes, verify: bool = True, progress: Progress | None = None
) -> Plan[None]:
    """Write ``data`` to ROM in page-aligned 64-byte chunks, reading each back if ``verify``."""
    data = data_bytes("ROM", data)
    check_span("ROM", address, len(data), ROM_SIZE)
    total, done, a = len(data), 0, address
    while done < total:
        n = min(ROM_WRITE_CHUNK - a % ROM_WRITE_CHUNK, total - done)
        chunk = data[done : done + n]
        yield Move(Rom(a), Data(chunk))
        if verify:
            command = Move(Com(), Rom(a), n)
            back = data_of((yield command), command)
            if back != chunk:
                bad = next(i for i in range(n) if back[i] != chunk[i])
                raise VerifyError(
                    f"ROM {a + bad:06X}: wrote {chunk[bad]:02X}, read back {back[bad]:02X}",
                    a + bad,
                )
        done += n
        a += n
        if progress is not None:
            progress(done, total)
