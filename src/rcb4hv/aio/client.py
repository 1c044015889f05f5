"""The asyncio twin of :class:`rcb4hv.client.Rcb4Client`.

Same commands, same typed errors, same no-hang deadlines: the reply hunt is the blocking
client's sans-I/O :class:`~rcb4hv.client.exchange.ReplyMatcher`, and RAM/ROM transfers are the
plans of :mod:`rcb4hv.client.plans`; only the waiting differs. Calls from concurrent tasks are
serialised by an :class:`asyncio.Lock`, one transaction at a time.
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Iterable, Mapping
from types import TracebackType
from typing import TypeVar

from rcb4hv.aio.transport import AsyncTransport, open_async_transport
from rcb4hv.client import plans
from rcb4hv.client.core import DEFAULT_TIMEOUT, CommandNotAllowedError, Progress
from rcb4hv.client.exchange import ReplyMatcher
from rcb4hv.client.plans import Plan
from rcb4hv.errors import FrameError, NakError, ProtocolError, Rcb4TimeoutError, TransportError
from rcb4hv.protocol import (
    ALWAYS,
    MAX_REPLY_SIZE,
    Ack,
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
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
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
from rcb4hv.transport import BAUD_RATES, DEFAULT_BAUD

__all__ = ["AsyncRcb4Client"]

log = logging.getLogger(__name__)

T = TypeVar("T")


class AsyncRcb4Client:
    """A connection to one board for asyncio code.

    ``async with await AsyncRcb4Client.open("socket://127.0.0.1:4000") as rcb: ...``

    Every method of :class:`~rcb4hv.client.Rcb4Client` exists here as a coroutine with the
    same arguments, results and exceptions (:class:`~rcb4hv.errors.NakError`,
    :class:`~rcb4hv.errors.Rcb4TimeoutError`, :class:`~rcb4hv.errors.ChecksumError`,
    :class:`~rcb4hv.errors.FrameError`, :class:`~rcb4hv.errors.TransportError`; ``ValueError``
    before any byte is sent). A call cancelled while waiting leaves the client usable: the
    next call flushes the input before it sends.
    """

    def __init__(
        self,
        transport: AsyncTransport,
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
        self._lock = asyncio.Lock()
        self._decoder = FrameDecoder(max_size=MAX_REPLY_SIZE, resync="byte")

    @classmethod
    async def open(
        cls,
        url: str | None = None,
        *,
        baudrate: int | None = DEFAULT_BAUD,
        timeout: float = DEFAULT_TIMEOUT,
        allow_communicate_device: bool = False,
    ) -> AsyncRcb4Client:
        """Open ``url`` as :meth:`Rcb4Client.open` does (``baudrate=None`` detects the rate).

        ``socket://`` uses asyncio streams; device paths use pyserial-asyncio-fast;
        ``rcb4emu://`` runs the emulator in process (it waits for the board's start-up).
        """
        if not timeout > 0:
            raise ValueError("timeout must be > 0")
        transport = await open_async_transport(url, baudrate or DEFAULT_BAUD)
        client = cls(transport, timeout=timeout, allow_communicate_device=allow_communicate_device)
        if baudrate is None:
            try:
                await client.detect_baudrate()
            except BaseException:
                await client.close()
                raise
        return client

    async def detect_baudrate(
        self, rates: Iterable[int] = BAUD_RATES, probe_timeout: float = 0.1
    ) -> int:
        """Find the rate the board answers at (ACK check at each) and keep it."""
        url = self.transport.url
        for rate in rates:
            try:
                self.transport.set_baudrate(rate)
            except TransportError as exc:
                log.debug("%s: cannot use %d baud: %s", url, rate, exc)
                continue
            try:
                await self.acknowledge_check(timeout=probe_timeout)
            except (Rcb4TimeoutError, ProtocolError, NakError):
                log.debug("%s: no ACK at %d baud", url, rate)
                continue
            log.info("%s: board answers at %d baud", url, rate)
            return rate
        raise TransportError(f"{url}: no answer to an ACK check at any baud rate")

    async def close(self) -> None:
        await self.transport.close()

    async def __aenter__(self) -> AsyncRcb4Client:
        return self

    async def __aexit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        await self.close()

    def __repr__(self) -> str:
        return f"<AsyncRcb4Client {self.transport.url!r}>"

    # ------------------------------------------------------------------ transactions

    async def transact(self, command: Command, timeout: float | None = None) -> Reply:
        """Send ``command`` and return its reply (Ack, DataReply or VersionReply).

        The reply is found by the blocking client's own hunt
        (:class:`~rcb4hv.client.exchange.ReplyMatcher`); only the waiting is asyncio's.
        """
        if isinstance(command, CommunicateDevice) and not self.allow_communicate_device:
            raise CommandNotAllowedError(
                "ICS communication (0Eh) is documented as 'must not be used'; "
                "create the client with allow_communicate_device=True to send it"
            )
        frame = command.encode()
        name = type(command).__name__
        limit = self.timeout if timeout is None else timeout
        transport = self.transport
        async with self._lock:
            deadline = time.monotonic() + limit
            matcher = ReplyMatcher(
                self._decoder, command.cmd, reply_length(command), name, self.corrupt_grace
            )
            transport.reset_input()
            transport.write(frame)
            chunk = b""
            while True:
                raw = matcher.feed(chunk, time.monotonic())
                if raw is not None:
                    break
                chunk = await transport.read(matcher.need, matcher.until(deadline))
                if not chunk:
                    raise matcher.timeout_error(limit)
        try:
            reply = decode_reply(raw, command)
        except ProtocolError as exc:
            raise FrameError(f"bad reply to {name}: {exc}") from exc
        if isinstance(reply, Nak):
            raise NakError(f"board answered NAK to {name}", command.cmd)
        return reply

    async def _run(self, plan: Plan[T]) -> T:
        try:
            command = next(plan)
            while True:
                command = plan.send(await self.transact(command))
        except StopIteration as done:
            result: T = done.value
            return result

    async def _data(self, command: Command) -> bytes:
        return plans.data_of(await self.transact(command), command)

    # ------------------------------------------------------------------ data commands

    async def move(self, dst: Destination, src: Source, size: int | None = None) -> bytes | None:
        """00h MOVE: ``dst <- src``. Returns the bytes read when ``dst`` is ``Com()``."""
        reply = await self.transact(Move(dst, src, size))
        return reply.data if isinstance(reply, DataReply) else None

    async def and_(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """01h AND; returns the result bytes."""
        return await self._data(And(dst, src, size, no_write))

    async def or_(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """02h OR; returns the result bytes."""
        return await self._data(Or(dst, src, size, no_write))

    async def xor(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """03h XOR; returns the result bytes."""
        return await self._data(Xor(dst, src, size, no_write))

    async def not_(self, dst: Destination, size: int, no_write: bool = False) -> bytes:
        """04h NOT; returns the result bytes."""
        return await self._data(Not(dst, size, no_write))

    async def shift(self, dst: Destination, size: int, count: int, no_write: bool = False) -> bytes:
        """05h SHIFT (count 1-127 right, 128-255 left by 256 - count); returns the result."""
        return await self._data(Shift(dst, size, no_write, count))

    async def _int(self, command: Command) -> int:
        return int.from_bytes(await self._data(command), "little")

    async def add(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """06h ADD (1 or 2 bytes); returns the result as an unsigned int."""
        return await self._int(Add(dst, src, size, no_write))

    async def sub(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """07h SUB (1 or 2 bytes); returns the result as an unsigned int."""
        return await self._int(Sub(dst, src, size, no_write))

    async def multiply(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """08h MUL (1 or 2 bytes, low bytes kept); returns the result."""
        return await self._int(Mul(dst, src, size, no_write))

    async def division(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """09h DIV (1 or 2 bytes, unsigned); returns the quotient."""
        return await self._int(Div(dst, src, size, no_write))

    async def modulo(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """0Ah MOD (1 or 2 bytes, unsigned); returns the remainder."""
        return await self._int(Mod(dst, src, size, no_write))

    # ------------------------------------------------------------------ control flow

    async def jump(self, address: int, condition: Condition = ALWAYS) -> None:
        """0Bh JUMP: set the ROM program counter (if ``condition`` holds)."""
        await self.transact(Jump(address, condition))

    async def call(self, address: int, condition: Condition = ALWAYS) -> None:
        """0Ch CALL: push the PC and jump (how a host starts a motion)."""
        await self.transact(Call(address, condition))

    async def return_(self) -> None:
        """0Dh RETURN: pop the PC."""
        await self.transact(Return())

    async def communicate_device(
        self, ics: int, tx_count: int, tx_address: int, rx_address: int
    ) -> None:
        """0Eh ICS communication; refused unless ``allow_communicate_device=True``."""
        await self.transact(CommunicateDevice(ics, tx_count, tx_address, rx_address))

    # ------------------------------------------------------------------ servo commands

    async def run_single_servo(
        self, ics: int, speed: int, position: int, set_update_flag: bool = True
    ) -> None:
        """0Fh: one servo to ``position`` in ``speed`` output periods."""
        await self.transact(RunSingleServo(ics, speed, position, set_update_flag))

    async def run_const_frame_servo(
        self,
        speed: int,
        positions: Mapping[int, int] | Iterable[tuple[int, int]],
        set_update_flag: bool = True,
    ) -> None:
        """10h: several servos, one speed; ``positions`` maps ICS number to position."""
        await self.transact(RunConstFrameServo(speed, positions, set_update_flag))

    async def run_series_servo(
        self, moves: Iterable[tuple[int, int, int]], set_update_flag: bool = True
    ) -> None:
        """11h: several servos, each ``(ics, speed, position)``."""
        await self.transact(RunSeriesServo(moves, set_update_flag))

    async def set_speed(self, values: Mapping[int, int] | Iterable[tuple[int, int]]) -> None:
        """12h sub 02: servo speed parameter 1-127 per ICS number."""
        await self.transact(SetSpeed(values))

    async def set_stretch(self, values: Mapping[int, int] | Iterable[tuple[int, int]]) -> None:
        """12h sub 01: servo stretch (holding gain) 1-127 per ICS number."""
        await self.transact(SetStretch(values))

    # ------------------------------------------------------------------ system

    async def get_version_info(self, timeout: float | None = None) -> VersionReply:
        """FDh: the 32-byte version string (``.text`` is its printable part)."""
        reply = await self.transact(GetVersionInfo(), timeout)
        if not isinstance(reply, VersionReply):
            raise FrameError(f"expected a version reply, got {reply}")
        return reply

    async def acknowledge_check(
        self, long_form: bool = False, timeout: float | None = None
    ) -> None:
        """FEh: link check; returns when the board ACKs, raises otherwise."""
        reply = await self.transact(AcknowledgeCheck(long_form), timeout)
        if not isinstance(reply, Ack):
            raise FrameError(f"expected an ACK, got {reply}")

    # ------------------------------------------------------------------ memory helpers

    async def read_ram(self, address: int, size: int) -> bytes:
        """Read ``size`` bytes of RAM (any size; 128 bytes per frame)."""
        return await self._run(plans.read_memory("RAM", address, size))

    async def write_ram(self, address: int, data: bytes) -> None:
        """Write ``data`` to RAM (any size; 121 bytes per frame)."""
        await self._run(plans.write_ram(address, data))

    async def read_rom(self, address: int, size: int, progress: Progress | None = None) -> bytes:
        """Read ``size`` bytes of ROM, 128 bytes per frame; ``progress(done, total)``."""
        return await self._run(plans.read_memory("ROM", address, size, progress))

    async def write_rom(
        self,
        address: int,
        data: bytes,
        *,
        verify: bool = True,
        progress: Progress | None = None,
    ) -> None:
        """Write ``data`` to ROM in 64-byte page-aligned chunks, verified when ``verify``."""
        await self._run(plans.write_rom(address, data, verify, progress))
