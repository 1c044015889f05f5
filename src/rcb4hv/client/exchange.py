"""The sans-I/O half of a transaction, shared by the blocking client and :mod:`rcb4hv.aio`.

A client sends :func:`request_frame`, then feeds whatever bytes arrive to a
:class:`ReplyMatcher` until it returns the reply (or the deadline passes, when
:meth:`ReplyMatcher.timeout_error` says what to raise). :func:`check_reply` turns a NAK into
:class:`~rcb4hv.errors.NakError`.

The multi-frame memory operations (RAM/ROM reads and writes, ROM verify) are *plans*:
generators that yield the commands to send and receive each reply, so both clients run the
same chunking and verifying code (``reply = yield command``).
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Generator
from typing import Final, TypeVar

from rcb4hv.errors import ChecksumError, FrameError, NakError, ProtocolError, Rcb4TimeoutError
from rcb4hv.protocol import (
    MAX_REPLY_SIZE,
    NEED_DATA,
    Com,
    Command,
    CommunicateDevice,
    Data,
    DataReply,
    FrameDecoder,
    Move,
    Nak,
    Ram,
    Reply,
    Rom,
    decode_reply,
    reply_length,
)
from rcb4hv.protocol.commands import RAM_SIZE, ROM_SIZE

__all__ = [
    "MAX_READ",
    "MAX_WRITE",
    "ROM_WRITE_CHUNK",
    "CommandNotAllowedError",
    "Plan",
    "Progress",
    "ReplyMatcher",
    "VerifyError",
    "check_reply",
    "command_name",
    "new_decoder",
    "read_memory",
    "request_frame",
    "write_ram",
    "write_rom",
]

log = logging.getLogger("rcb4hv.client.core")

MAX_READ: Final = 128
"""Bytes one MOVE to COM can read (its reply frame is 131 bytes)."""
MAX_WRITE: Final = 121
"""Literal bytes one MOVE can carry in a 128-byte command frame."""
ROM_WRITE_CHUNK: Final = 64
"""ROM writes go in 64-byte chunks aligned on 64-byte boundaries: one chunk fits a MOVE literal
(at most 121 bytes) and never straddles an EEPROM write page (64 or 128 bytes on the parts
used in this board family), so no page write ever wraps around inside its page."""

Progress = Callable[[int, int], None]
"""Progress callback: ``progress(done_bytes, total_bytes)``."""

T = TypeVar("T")
Plan = Generator[Command, Reply, T]
"""A multi-frame operation: yields each command, is sent its reply, returns the result."""


class CommandNotAllowedError(PermissionError):
    """A command the client refuses unless explicitly enabled (ICS communication, 0Eh)."""


class VerifyError(ProtocolError):
    """Reading back memory just written gave different bytes."""

    def __init__(self, message: str, address: int) -> None:
        super().__init__(message)
        self.address = address


def command_name(command: Command) -> str:
    return type(command).__name__


def new_decoder() -> FrameDecoder:
    """The host's reply decoder: byte resync, so a reply is found after stray bytes."""
    return FrameDecoder(max_size=MAX_REPLY_SIZE, resync="byte")


def request_frame(command: Command, allow_communicate_device: bool) -> bytes:
    """The bytes to send for ``command``; refuses 0Eh unless explicitly allowed."""
    if isinstance(command, CommunicateDevice) and not allow_communicate_device:
        raise CommandNotAllowedError(
            "ICS communication (0Eh) is documented as 'must not be used'; "
            "create the client with allow_communicate_device=True to send it"
        )
    return command.encode()


def check_reply(reply: Reply, command: Command) -> Reply:
    """``reply`` itself, or :class:`NakError` when the board refused ``command``."""
    if isinstance(reply, Nak):
        raise NakError(f"board answered NAK to {command_name(command)}", command.cmd)
    return reply


class ReplyMatcher:
    """Finds the reply to one command in the bytes that arrive after it was sent.

    Bytes that cannot start the expected reply (right size byte, or 4 for a NAK, then the
    command's CMD byte) are discarded and logged. A reply with a bad checksum is remembered
    and shortens the deadline to ``now + corrupt_grace`` (a good copy may still follow).
    """

    def __init__(self, command: Command, decoder: FrameDecoder, corrupt_grace: float) -> None:
        self.command = command
        self.expected = reply_length(command)
        self.decoder = decoder
        self.corrupt_grace = corrupt_grace
        self.corrupt: ChecksumError | None = None
        self.grace_deadline: float | None = None
        self.need = 4
        """How many more bytes to ask the link for."""
        decoder.reset()

    def feed(self, chunk: bytes, now: float) -> Reply | None:
        """Take ``chunk``; return the decoded reply once it is complete, else None."""
        decoder, cmd, expected = self.decoder, self.command.cmd, self.expected
        name = command_name(self.command)
        decoder.receive_data(chunk)
        while True:
            pending = decoder.pending
            skip, n = 0, len(pending)
            while skip < n and not (
                (pending[skip] == expected or pending[skip] == 4)
                and (skip + 1 >= n or pending[skip + 1] == cmd)
            ):
                skip += 1
            if skip:
                log.warning(
                    "discarded %d stray byte(s) before the reply to %s: %s",
                    skip,
                    name,
                    pending[:skip].hex(" "),
                )
                decoder.reset()
                decoder.receive_data(pending[skip:])
                pending = pending[skip:]
            if not pending:
                self.need = 4
                return None
            try:
                frame = decoder.next_frame()
            except ChecksumError as exc:
                log.warning("reply to %s with a bad checksum: %s", name, exc)
                self.corrupt = ChecksumError(
                    f"reply to {name} has a bad checksum: {exc.frame.hex(' ')}", exc.frame
                )
                limit = now + self.corrupt_grace
                if self.grace_deadline is None or limit < self.grace_deadline:
                    self.grace_deadline = limit
                continue
            if frame is NEED_DATA:
                self.need = max(pending[0] - len(pending), 1)
                return None
            assert isinstance(frame, bytes)
            try:
                return decode_reply(frame, self.command)
            except ProtocolError as exc:
                raise FrameError(f"bad reply to {name}: {exc}") from exc

    def timeout_error(self, timeout: float) -> Exception:
        """What to raise when the deadline passed: the checksum error seen, or a timeout."""
        partial = self.decoder.reset()
        if self.corrupt is not None:
            return self.corrupt
        got = f" (incomplete: {partial.hex(' ')})" if partial else ""
        return Rcb4TimeoutError(
            f"no reply to {command_name(self.command)} within {timeout:g} s{got}"
        )


# ---------------------------------------------------------------------- plans


def check_span(kind: str, address: int, size: int, limit: int) -> None:
    if not isinstance(address, int) or not isinstance(size, int):
        raise ValueError(f"{kind} address and size must be ints")
    if size < 1:
        raise ValueError(f"{kind} size {size} must be at least 1")
    if address < 0 or address + size > limit:
        raise ValueError(f"{kind} {address:#x}+{size} runs outside 0..{limit - 1:#x}")


def data_of(reply: Reply, command: Command) -> bytes:
    if not isinstance(reply, DataReply):
        raise FrameError(f"expected a data reply to {command_name(command)}, got {reply}")
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
    data = bytes(data)
    check_span("RAM", address, len(data), RAM_SIZE)
    for i in range(0, len(data), MAX_WRITE):
        yield Move(Ram(address + i), Data(data[i : i + MAX_WRITE]))


def write_rom(
    address: int, data: bytes, verify: bool = True, progress: Progress | None = None
) -> Plan[None]:
    """Write ``data`` to ROM in page-aligned 64-byte chunks, reading each back if ``verify``."""
    data = bytes(data)
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
