"""The typed client: one method per command of the reference, one transaction at a time."""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Iterable, Mapping
from types import TracebackType
from typing import Final, NoReturn, TypeVar

from rcb4hv.client.exchange import RAM_READS, find_reply, ram_read_frame
from rcb4hv.client.plans import (
    MAX_READ,
    MAX_WRITE,
    ROM_WRITE_CHUNK,
    Plan,
    Progress,
    read_memory,
)
from rcb4hv.client.plans import write_ram as write_ram_plan
from rcb4hv.client.plans import write_rom as write_rom_plan
from rcb4hv.errors import (
    CommandNotAllowedError,
    FrameError,
    NakError,
    ProtocolError,
    Rcb4TimeoutError,
    TransportError,
    VerifyError,
)
from rcb4hv.protocol import (
    ALWAYS,
    MAX_REPLY_SIZE,
    AcknowledgeCheck,
    Add,
    And,
    Call,
    Command,
    CommunicateDevice,
    Condition,
    DataReply,
    Destination,
    Div,
    FrameDecoder,
    GetVersionInfo,
    Jump,
    Mod,
    Move,
    Mul,
    Nak,
    Not,
    Or,
    Reply,
    Return,
    RunSeriesServo,
    SetSpeed,
    SetStretch,
    Shift,
    Source,
    Sub,
    VersionReply,
    Xor,
    decode_reply,
    reply_length,
)
from rcb4hv.protocol.commands import RAM_SIZE
from rcb4hv.protocol.frame import sum_ok
from rcb4hv.protocol.replies import ACK_BYTE, NAK_BYTE
from rcb4hv.protocol.servoframes import const_frame_servo_frame, single_servo_frame
from rcb4hv.transport import (
    BAUD_RATES,
    DEFAULT_BAUD,
    SerialTransport,
    Transport,
    open_transport,
)

__all__ = [
    "DEFAULT_TIMEOUT",
    "MAX_READ",
    "MAX_WRITE",
    "ROM_WRITE_CHUNK",
    "CommandNotAllowedError",
    "Progress",
    "Rcb4Client",
    "VerifyError",
]

log = logging.getLogger(__name__)

T = TypeVar("T")

DEFAULT_TIMEOUT: Final = 0.5


def _name(command: Command) -> str:
    return type(command).__name__


class Rcb4Client:
    """A connection to one board speaking the RCB-4HV protocol.

    Methods map one to one onto the commands of Kondo's command reference (``move``, ``and_``,
    ... ``acknowledge_check``); each returns a typed result or raises a typed error:
    :class:`~rcb4hv.errors.NakError` (the board refused), :class:`~rcb4hv.errors.Rcb4TimeoutError`
    (no complete reply in time), :class:`~rcb4hv.errors.ChecksumError` (the reply arrived
    damaged), :class:`~rcb4hv.errors.FrameError` (a reply of the wrong shape) or
    :class:`~rcb4hv.errors.TransportError` (the link failed). Bad arguments raise
    ``ValueError`` before any byte is sent.

    The client is thread-safe: one transaction at a time under a lock. Bytes that arrive
    before the reply and cannot start it (stray bytes, late replies to earlier requests) are
    discarded and logged.
    """

    def __init__(
        self,
        transport: Transport,
        *,
        timeout: float = DEFAULT_TIMEOUT,
        allow_communicate_device: bool = False,
        corrupt_grace: float = 0.02,
    ) -> None:
        if not timeout > 0:
            raise ValueError("timeout must be > 0")
        self.transport = transport
        self.timeout = timeout
        self.allow_communicate_device = allow_communicate_device
        self.corrupt_grace = corrupt_grace
        self._lock = threading.Lock()
        self._decoder = FrameDecoder(max_size=MAX_REPLY_SIZE, resync="byte")

    # ------------------------------------------------------------------ lifecycle

    @classmethod
    def open(
        cls,
        url: str | None = None,
        *,
        baudrate: int | None = DEFAULT_BAUD,
        timeout: float = DEFAULT_TIMEOUT,
        allow_communicate_device: bool = False,
    ) -> Rcb4Client:
        """Open ``url`` (None: the Kondo adapter found by VID/PID, or ``$RCB4HV_PORT``).

        ``baudrate=None`` detects the rate: an ACK check at 1,250,000, 625,000, then 115,200.
        """
        transport = open_transport(url, baudrate or DEFAULT_BAUD)
        client = cls(transport, timeout=timeout, allow_communicate_device=allow_communicate_device)
        if baudrate is None:
            try:
                client.detect_baudrate()
            except BaseException:
                client.close()
                raise
        return client

    def detect_baudrate(self, rates: Iterable[int] = BAUD_RATES, probe_timeout: float = 0.1) -> int:
        """Find the rate the board answers at (ACK check at each) and keep it."""
        transport = self.transport
        inner = getattr(transport, "inner", transport)
        if not isinstance(inner, SerialTransport):
            raise ValueError("baud detection needs a serial port")
        for rate in rates:
            if inner.baudrate != rate:
                try:
                    inner.set_baudrate(rate)
                except TransportError as exc:
                    log.debug("%s: cannot use %d baud: %s", inner.url, rate, exc)
                    continue
            try:
                self.acknowledge_check(timeout=probe_timeout)
            except (Rcb4TimeoutError, ProtocolError, NakError):
                log.debug("%s: no ACK at %d baud", inner.url, rate)
                continue
            log.info("%s: board answers at %d baud", inner.url, rate)
            return rate
        raise TransportError(f"{inner.url}: no answer to an ACK check at any baud rate")

    def close(self) -> None:
        self.transport.close()

    def reconnect(self) -> None:
        """Reopen the transport (after a disconnect)."""
        with self._lock:
            self.transport.reopen()

    def __enter__(self) -> Rcb4Client:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<Rcb4Client {self.transport.url!r}>"

    # ------------------------------------------------------------------ transactions

    def transact(self, command: Command, timeout: float | None = None) -> Reply:
        """Send ``command`` and return its reply (Ack, DataReply or VersionReply).

        A NAK raises :class:`NakError`; see the class docstring for the other errors.
        """
        if isinstance(command, CommunicateDevice) and not self.allow_communicate_device:
            raise CommandNotAllowedError(
                "ICS communication (0Eh) is documented as 'must not be used'; "
                "create the client with allow_communicate_device=True to send it"
            )
        frame = command.encode()
        raw = self._roundtrip(
            frame,
            command.cmd,
            reply_length(command),
            _name(command),
            self.timeout if timeout is None else timeout,
        )
        try:
            reply = decode_reply(raw, command)
        except ProtocolError as exc:
            raise FrameError(f"bad reply to {_name(command)}: {exc}") from exc
        if isinstance(reply, Nak):
            raise NakError(f"board answered NAK to {_name(command)}", command.cmd)
        return reply

    def _ack(self, frame: bytes, cmd: int, name: str, timeout: float | None = None) -> None:
        """Send a command ``frame`` answered by an ACK (fast path of :meth:`transact`)."""
        raw = self._roundtrip(frame, cmd, 4, name, self.timeout if timeout is None else timeout)
        if raw[2] != ACK_BYTE:
            if raw[2] == NAK_BYTE:
                raise NakError(f"board answered NAK to {name}", cmd)
            raise FrameError(f"bad reply to {name}: expected ACK or NAK, got {raw.hex(' ')}")

    def _roundtrip(self, frame: bytes, cmd: int, expected: int, name: str, timeout: float) -> bytes:
        """Send ``frame``; return the reply frame (whole, checksum checked, CMD byte ``cmd``).

        ``expected`` is the length of the successful reply. Fast path: the first read brings
        exactly that frame. Anything else (a NAK, a reply in pieces, stray bytes before it, a
        damaged reply) goes through :func:`~rcb4hv.client.exchange.find_reply`.
        """
        transport = self.transport
        with self._lock:
            deadline = time.monotonic() + timeout
            transport.reset_input()
            transport.write(frame)
            chunk = transport.read_some(expected, deadline)
            if (
                len(chunk) == expected
                and chunk[0] == expected
                and chunk[1] == cmd
                and sum_ok(chunk)
            ):
                return chunk
            return find_reply(
                transport,
                self._decoder,
                chunk,
                cmd,
                expected,
                name,
                deadline,
                timeout,
                self.corrupt_grace,
            )

    def _data_reply(self, frame: bytes, cmd: int, size: int, name: str) -> bytes:
        """Send a command ``frame`` answered by ``size`` data bytes; return them."""
        raw = self._roundtrip(frame, cmd, size + 3, name, self.timeout)
        if len(raw) == size + 3:
            return raw[2:-1]
        return self._data_reply_error(raw, cmd, size, name)

    @staticmethod
    def _data_reply_error(raw: bytes, cmd: int, size: int, name: str) -> NoReturn:
        if len(raw) == 4 and raw[2] == NAK_BYTE:
            raise NakError(f"board answered NAK to {name}", cmd)
        raise FrameError(f"bad reply to {name}: expected {size} data bytes, got {raw.hex(' ')}")

    # ------------------------------------------------------------------ data commands

    def move(self, dst: Destination, src: Source, size: int | None = None) -> bytes | None:
        """00h MOVE: ``dst <- src``. Returns the bytes read when ``dst`` is ``Com()``."""
        reply = self.transact(Move(dst, src, size))
        return reply.data if isinstance(reply, DataReply) else None

    def _data(self, command: Command) -> bytes:
        reply = self.transact(command)
        if not isinstance(reply, DataReply):
            raise FrameError(f"expected a data reply to {_name(command)}, got {reply}")
        return reply.data

    def and_(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """01h AND; returns the result bytes."""
        return self._data(And(dst, src, size, no_write))

    def or_(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """02h OR; returns the result bytes."""
        return self._data(Or(dst, src, size, no_write))

    def xor(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """03h XOR; returns the result bytes."""
        return self._data(Xor(dst, src, size, no_write))

    def not_(self, dst: Destination, size: int, no_write: bool = False) -> bytes:
        """04h NOT; returns the result bytes."""
        return self._data(Not(dst, size, no_write))

    def shift(self, dst: Destination, size: int, count: int, no_write: bool = False) -> bytes:
        """05h SHIFT (count 1-127 right, 128-255 left by 256 - count); returns the result."""
        return self._data(Shift(dst, size, no_write, count))

    def add(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """06h ADD (1 or 2 bytes); returns the result as an unsigned int."""
        return int.from_bytes(self._data(Add(dst, src, size, no_write)), "little")

    def sub(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """07h SUB (1 or 2 bytes); returns the result as an unsigned int."""
        return int.from_bytes(self._data(Sub(dst, src, size, no_write)), "little")

    def multiply(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """08h MUL (1 or 2 bytes, low bytes kept); returns the result."""
        return int.from_bytes(self._data(Mul(dst, src, size, no_write)), "little")

    def division(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """09h DIV (1 or 2 bytes, unsigned); returns the quotient."""
        return int.from_bytes(self._data(Div(dst, src, size, no_write)), "little")

    def modulo(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """0Ah MOD (1 or 2 bytes, unsigned); returns the remainder."""
        return int.from_bytes(self._data(Mod(dst, src, size, no_write)), "little")

    # ------------------------------------------------------------------ control flow

    def jump(self, address: int, condition: Condition = ALWAYS) -> None:
        """0Bh JUMP: set the ROM program counter (if ``condition`` holds)."""
        self.transact(Jump(address, condition))

    def call(self, address: int, condition: Condition = ALWAYS) -> None:
        """0Ch CALL: push the PC and jump (how a host starts a motion)."""
        self.transact(Call(address, condition))

    def return_(self) -> None:
        """0Dh RETURN: pop the PC."""
        self.transact(Return())

    def communicate_device(self, ics: int, tx_count: int, tx_address: int, rx_address: int) -> None:
        """0Eh ICS communication. Refused (CommandNotAllowedError) unless the client was created
        with ``allow_communicate_device=True``: the reference says it must not be used."""
        self.transact(CommunicateDevice(ics, tx_count, tx_address, rx_address))

    # ------------------------------------------------------------------ servo commands

    def run_single_servo(
        self, ics: int, speed: int, position: int, set_update_flag: bool = True
    ) -> None:
        """0Fh: one servo to ``position`` in ``speed`` output periods (any 7-bit ICS number,
        speed and 16-bit position: the wire layer takes what the board takes)."""
        self._ack(single_servo_frame(ics, speed, position, set_update_flag), 0x0F, "RunSingleServo")

    def run_const_frame_servo(
        self,
        speed: int,
        positions: Mapping[int, int] | Iterable[tuple[int, int]],
        set_update_flag: bool = True,
    ) -> None:
        """10h: several servos, one speed; ``positions`` maps ICS number to position."""
        frame = const_frame_servo_frame(speed, positions, set_update_flag)
        self._ack(frame, 0x10, "RunConstFrameServo")

    def run_series_servo(
        self, moves: Iterable[tuple[int, int, int]], set_update_flag: bool = True
    ) -> None:
        """11h: several servos, each ``(ics, speed, position)``. One report says it resets a
        real RCB-4HV; HeartToHeart4 never sends it."""
        self.transact(RunSeriesServo(moves, set_update_flag))

    def set_speed(self, values: Mapping[int, int] | Iterable[tuple[int, int]]) -> None:
        """12h sub 02: servo speed parameter per ICS number (any byte; documented 1-127,
        which :meth:`Robot.set_speed` checks)."""
        self.transact(SetSpeed(values))

    def set_stretch(self, values: Mapping[int, int] | Iterable[tuple[int, int]]) -> None:
        """12h sub 01: servo stretch (holding gain) per ICS number (any byte; documented
        1-127, which :meth:`Robot.set_stretch` checks)."""
        self.transact(SetStretch(values))

    # ------------------------------------------------------------------ system

    def get_version_info(self, timeout: float | None = None) -> VersionReply:
        """FDh: the 32-byte version string (``.text`` is its printable part)."""
        reply = self.transact(GetVersionInfo(), timeout)
        if not isinstance(reply, VersionReply):
            raise FrameError(f"expected a version reply, got {reply}")
        return reply

    def acknowledge_check(self, long_form: bool = False, timeout: float | None = None) -> None:
        """FEh: link check; returns when the board ACKs, raises otherwise."""
        frame = _ACK_LONG if long_form else _ACK_SHORT
        self._ack(frame, AcknowledgeCheck.cmd, "AcknowledgeCheck", timeout)

    # ------------------------------------------------------------------ memory helpers

    def read_ram(self, address: int, size: int) -> bytes:
        """Read ``size`` bytes of RAM (any size; 128 bytes per frame)."""
        if (
            type(address) is int
            and type(size) is int
            and 0 < size <= MAX_READ
            and 0 <= address <= RAM_SIZE - size
        ):  # fast path: one frame, arguments known good
            frame = RAM_READS.get((address, size)) or ram_read_frame(address, size)
            raw = self._roundtrip(frame, 0x00, size + 3, "Move", self.timeout)
            if len(raw) == size + 3:
                return raw[2:-1]
            return self._data_reply_error(raw, 0x00, size, "Move")
        return self.run_plan(read_memory("RAM", address, size))

    def write_ram(self, address: int, data: bytes) -> None:
        """Write ``data`` to RAM (any size; 121 bytes per frame)."""
        self.run_plan(write_ram_plan(address, data))

    def read_rom(self, address: int, size: int, progress: Progress | None = None) -> bytes:
        """Read ``size`` bytes of ROM, 128 bytes per frame; ``progress(done, total)``."""
        return self.run_plan(read_memory("ROM", address, size, progress))

    def write_rom(
        self,
        address: int,
        data: bytes,
        *,
        verify: bool = True,
        progress: Progress | None = None,
    ) -> None:
        """Write ``data`` to ROM in 64-byte page-aligned chunks (see :data:`ROM_WRITE_CHUNK`),
        reading each chunk back when ``verify`` (raises :class:`VerifyError` on a mismatch).
        ``progress(done, total)`` counts bytes written (and verified)."""
        self.run_plan(write_rom_plan(address, data, verify, progress))

    def run_plan(self, plan: Plan[T]) -> T:
        """Run a multi-frame :mod:`~rcb4hv.client.plans` operation over this link: each command
        it yields is sent and its reply sent back in; returns the plan's result."""
        try:
            command = next(plan)
            while True:
                command = plan.send(self.transact(command))
        except StopIteration as stop:
            return stop.value  # type: ignore[no-any-return]


_ACK_SHORT: Final = AcknowledgeCheck().encode()
_ACK_LONG: Final = AcknowledgeCheck(long_form=True).encode()
