"""The typed client: one method per command of the reference, one transaction at a time.

One source, two faces: ``src/rcb4hv/aio/client.py`` (asyncio) is the only source of the
client, and ``tools/unasync.py`` writes ``src/rcb4hv/client/core.py`` (blocking) from it
(coroutines become functions, awaits go, the asyncio lock becomes a threading lock, the
``Async`` prefix of the class names goes); ``make test`` fails when the two differ. Both
faces share the sans-I/O reply hunt (:class:`~rcb4hv.client.exchange.ReplyMatcher`) and the
RAM/ROM transfer plans (:mod:`rcb4hv.client.plans`); only the waiting differs.
"""

from __future__ import annotations

import logging
import time
from asyncio import Lock
from collections.abc import Iterable
from types import TracebackType
from typing import Final, TypeVar

from rcb4hv.aio.client_commands import AsyncRcb4Commands
from rcb4hv.aio.transport import AsyncTransport, open_async_transport
from rcb4hv.client import exchange
from rcb4hv.client.args import check_link_args, closed_error
from rcb4hv.client.exchange import RAM_READS, ReplyMatcher, check_timeout, ram_read_frame
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
    ChecksumError,
    CommandNotAllowedError,
    FrameError,
    NakError,
    ProtocolError,
    Rcb4TimeoutError,
    TransportError,
)
from rcb4hv.protocol import (
    MAX_REPLY_SIZE,
    NEED_DATA,
    RAM_SIZE,
    AcknowledgeCheck,
    Command,
    CommunicateDevice,
    FrameDecoder,
    GetVersionInfo,
    Nak,
    Reply,
    VersionReply,
    decode_reply,
    reply_length,
)
from rcb4hv.protocol.frame import sum_ok
from rcb4hv.protocol.replies import ACK_BYTE, NAK_BYTE
from rcb4hv.transport import BAUD_RATES, DEFAULT_BAUD

__all__ = [
    "DEFAULT_TIMEOUT",
    "MAX_READ",
    "MAX_WRITE",
    "ROM_WRITE_CHUNK",
    "AsyncRcb4Client",
    "Progress",
]

log = logging.getLogger(__name__)

T = TypeVar("T")

DEFAULT_TIMEOUT: Final = 0.5


def _name(command: Command) -> str:
    return type(command).__name__


class AsyncRcb4Client(AsyncRcb4Commands):
    """A connection to one board speaking the RCB-4HV protocol.

    ``async with await AsyncRcb4Client.open("rcb4emu://") as rcb: await rcb.acknowledge_check()``

    Methods map one to one onto the commands of Kondo's command reference (``move``, ``and_``,
    ... ``acknowledge_check``); each returns a typed result or raises a typed error:
    :class:`~rcb4hv.errors.NakError` (the board refused), :class:`~rcb4hv.errors.Rcb4TimeoutError`
    (no complete reply in time), :class:`~rcb4hv.errors.ChecksumError` (the reply arrived
    damaged), :class:`~rcb4hv.errors.FrameError` (a reply of the wrong shape) or
    :class:`~rcb4hv.errors.TransportError` (the link failed). Bad arguments raise
    ``ValueError`` before any byte is sent.

    One transaction at a time, under a lock (callers from several threads or tasks are
    serialised). Bytes that arrive before the reply and cannot start it (stray bytes, late
    replies to earlier requests) are discarded and logged; a call cancelled, interrupted or
    timed out leaves the client usable: the next call waits out the reply its request still
    gets (:meth:`_settle`), then flushes the input and sends.
    """

    def __init__(
        self,
        transport: AsyncTransport,
        *,
        timeout: float = DEFAULT_TIMEOUT,
        allow_communicate_device: bool = False,
        corrupt_grace: float = 0.02,
    ) -> None:
        check_timeout(timeout)
        self.transport = transport
        self.timeout = timeout
        self.allow_communicate_device = allow_communicate_device
        self.corrupt_grace = corrupt_grace
        self._lock = Lock()
        self._closed = False
        self._decoder = FrameDecoder(max_size=MAX_REPLY_SIZE, resync="byte")
        self._owed = 0
        """Replies still owed to requests sent and then abandoned (the call was cancelled,
        interrupted or timed out): the next call waits them out before it sends."""
        self._owed_wait = timeout
        """How long the next call waits for them at most: the abandoned call's timeout, or
        the client's when that is longer (a reply that missed a short timeout is late)."""

    # ------------------------------------------------------------------ lifecycle

    @classmethod
    async def open(
        cls,
        url: str | None = None,
        *,
        baudrate: int | None = DEFAULT_BAUD,
        timeout: float = DEFAULT_TIMEOUT,
        allow_communicate_device: bool = False,
    ) -> AsyncRcb4Client:
        """Open ``url`` (None: the Kondo adapter found by VID/PID, or ``$RCB4HV_PORT``).

        ``baudrate=None`` detects the rate: an ACK check at 1,250,000, 625,000, then 115,200.
        """
        check_timeout(timeout)
        baudrate = check_link_args(url, baudrate)
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
        self, rates: Iterable[int] = BAUD_RATES, probe_timeout: float = 0.1, tries: int = 2
    ) -> int:
        """Find the rate the board answers at and keep it; ValueError when the link has no
        rate (a transport without :meth:`set_baudrate`). A ``socket://`` link takes every rate
        (the rate is the far end's), so there the checks only confirm the board answers.

        Each rate gets up to ``tries`` ACK checks, and counts only when a second ACK check at
        it answers too. The input is flushed before every check, so an ACK that arrives late
        (a busy host, a slow adapter) is never taken for the answer at the next rate.
        """
        url = self.transport.url
        for rate in rates:
            try:
                self.transport.set_baudrate(rate)
            except TransportError as exc:
                log.debug("%s: cannot use %d baud: %s", url, rate, exc)
                continue
            if await self._acks(probe_timeout, tries) and await self._acks(probe_timeout, tries):
                log.info("%s: board answers at %d baud", url, rate)
                return rate
            log.debug("%s: no ACK at %d baud", url, rate)
        raise TransportError(f"{url}: no answer to an ACK check at any baud rate")

    async def _acks(self, timeout: float, tries: int) -> bool:
        """Whether one of ``tries`` ACK checks, each after a flush of the input, is answered."""
        for _ in range(max(1, tries)):
            self.transport.reset_input()
            self._owed = 0  # a probe's late reply is the second check's business, not a wait
            try:
                await self.acknowledge_check(timeout=timeout)
            except (Rcb4TimeoutError, ProtocolError, NakError):
                continue
            return True
        return False

    async def close(self) -> None:
        """Close the link after the call in progress (if any); later calls raise
        :class:`~rcb4hv.errors.TransportError` ("the client is closed") until reconnect()."""
        self._closed = True
        async with self._lock:
            await self.transport.close()

    async def reconnect(self) -> None:
        """Reopen the transport (after a disconnect, or after :meth:`close`)."""
        async with self._lock:
            await self.transport.reopen()
            self._owed = 0  # a new link: nothing is on its way on it
            self._closed = False

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
        return f"<{type(self).__name__} {self.transport.url!r}>"

    # ------------------------------------------------------------------ transactions

    async def transact(self, command: Command, timeout: float | None = None) -> Reply:
        """Send ``command`` and return its reply (Ack, DataReply or VersionReply).

        A NAK raises :class:`NakError`; see the class docstring for the other errors.
        """
        if isinstance(command, CommunicateDevice) and not self.allow_communicate_device:
            raise CommandNotAllowedError(
                "ICS communication (0Eh) is documented as 'must not be used'; "
                "create the client with allow_communicate_device=True to send it"
            )
        frame = command.encode()
        raw = await self._roundtrip(
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

    async def _ack(self, frame: bytes, cmd: int, name: str, timeout: float | None = None) -> None:
        """Send a command ``frame`` answered by an ACK (fast path of :meth:`transact`)."""
        raw = await self._roundtrip(
            frame, cmd, 4, name, self.timeout if timeout is None else timeout
        )
        if raw[2] != ACK_BYTE:
            if raw[2] == NAK_BYTE:
                raise NakError(f"board answered NAK to {name}", cmd)
            raise FrameError(f"bad reply to {name}: expected ACK or NAK, got {raw.hex(' ')}")

    async def _roundtrip(
        self, frame: bytes, cmd: int, expected: int, name: str, timeout: float
    ) -> bytes:
        """Send ``frame``; return the reply frame (whole, checksum checked, CMD byte ``cmd``).

        ``expected`` is the length of the successful reply. Fast path: the first read brings
        exactly that frame. Anything else (a NAK, a reply in pieces, stray bytes before it, a
        damaged reply) goes through the hunt of :class:`~rcb4hv.client.exchange.ReplyMatcher`.
        """
        check_timeout(timeout)
        transport = self.transport
        async with self._lock:
            if self._closed:
                raise closed_error(transport.url)
            if self._owed:
                await self._settle()
            deadline = time.monotonic() + timeout
            transport.reset_input()
            transport.write(frame)
            self._owed += 1
            self._owed_wait = max(timeout, self.timeout)
            chunk = await transport.read_some(expected, deadline)
            if (
                len(chunk) == expected
                and chunk[0] == expected
                and chunk[1] == cmd
                and sum_ok(chunk)
            ):
                self._owed -= 1
                return chunk
            matcher = ReplyMatcher(self._decoder, cmd, expected, name, self.corrupt_grace)
            try:
                while True:
                    raw = matcher.feed(chunk, time.monotonic())
                    if raw is not None:
                        self._owed -= 1
                        return raw
                    chunk = await transport.read(matcher.need, matcher.until(deadline))
                    if not chunk:
                        error = matcher.timeout_error(timeout)
                        if isinstance(error, ChecksumError):
                            self._owed -= 1  # the reply came, damaged: none is owed
                        raise error
            finally:
                matcher.report()  # the stray bytes of the whole exchange, in one line

    async def settle(self) -> None:
        """Wait out the replies still owed to abandoned requests now (the next call would
        first): a no-op when none is, so a timing can leave that wait out."""
        async with self._lock:
            if self._owed:
                await self._settle()

    async def _settle(self) -> None:
        """Wait out the replies owed to abandoned requests before the next one is sent.

        A call cancelled, interrupted or timed out after its request went out leaves the
        board's reply on its way; flushing the input before the next request does not stop
        it arriving after the flush, where it would be taken for the next reply (and that
        one's for the call after: wrong data, call after call). So the owed frames are read
        and dropped first, waiting at most the abandoned call's timeout (or the client's, if
        longer): what has not come by then is not expected any more. So the first call after
        a reply that never comes (a dropped frame, a board gone) takes up to that much
        longer; a call after one that was only cancelled waits for its reply, milliseconds."""
        transport = self.transport
        deadline = time.monotonic() + self._owed_wait
        decoder = FrameDecoder(max_size=MAX_REPLY_SIZE, resync="byte")
        dropped = 0
        try:
            while self._owed and (chunk := await transport.read(4, deadline)):
                dropped += len(chunk)
                decoder.receive_data(chunk)
                while self._owed:
                    try:
                        frame = decoder.next_frame()
                    except ProtocolError:
                        continue  # a damaged or stray byte: the decoder has dropped it
                    if frame is NEED_DATA:
                        break
                    self._owed -= 1
        finally:
            self._owed = 0
        if dropped:
            log.info("dropped %d byte(s) of replies to abandoned requests", dropped)

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
        frame = _ACK_LONG if long_form else _ACK_SHORT
        await self._ack(frame, AcknowledgeCheck.cmd, "AcknowledgeCheck", timeout)

    # ------------------------------------------------------------------ memory helpers

    async def read_ram(self, address: int, size: int) -> bytes:
        """Read ``size`` bytes of RAM (any size; 128 bytes per frame)."""
        if (
            type(address) is int
            and type(size) is int
            and 0 < size <= MAX_READ
            and 0 <= address <= RAM_SIZE - size
        ):  # fast path: one frame, arguments known good
            frame = RAM_READS.get((address, size)) or ram_read_frame(address, size)
            raw = await self._roundtrip(frame, 0x00, size + 3, "Move", self.timeout)
            if len(raw) == size + 3:
                return raw[2:-1]
            return exchange.data_reply_error(raw, 0x00, size, "Move")
        return await self.run_plan(read_memory("RAM", address, size))

    async def write_ram(self, address: int, data: bytes) -> None:
        """Write ``data`` to RAM (any size; 121 bytes per frame)."""
        await self.run_plan(write_ram_plan(address, data))

    async def read_rom(self, address: int, size: int, progress: Progress | None = None) -> bytes:
        """Read ``size`` bytes of ROM, 128 bytes per frame; ``progress(done, total)``."""
        return await self.run_plan(read_memory("ROM", address, size, progress))

    async def write_rom(
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
        await self.run_plan(write_rom_plan(address, data, verify, progress))

    async def run_plan(self, plan: Plan[T]) -> T:
        """Run a multi-frame :mod:`~rcb4hv.client.plans` operation over this link: each command
        it yields is sent and its reply sent back in; returns the plan's result."""
        try:
            command = next(plan)
            while True:
                command = plan.send(await self.transact(command))
        except StopIteration as stop:
            return stop.value  # type: ignore[no-any-return]


_ACK_SHORT: Final = AcknowledgeCheck().encode()
_ACK_LONG: Final = AcknowledgeCheck(long_form=True).encode()
