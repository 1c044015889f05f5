"""Asyncio links to a board: the same contract as :class:`rcb4hv.transport.Transport`
(bounded reads with an absolute ``time.monotonic()`` deadline, every failure a
:class:`~rcb4hv.errors.TransportError`), with coroutines.

* :class:`StreamTransport` — an asyncio protocol fed by the event loop: ``socket://`` via
  :meth:`asyncio.loop.create_connection` (asyncio sets TCP_NODELAY), serial device paths
  (and the emulator's pty) via ``pyserial-asyncio-fast``, which watches the port's file
  descriptor;
* :class:`PolledTransport` — pyserial ports without a file descriptor (``rcb4emu://`` in
  process, ``loop://``, ``rfc2217://``), read without blocking and polled every millisecond.

:func:`open_async_transport` picks one for a URL.
"""

from __future__ import annotations

import abc
import asyncio
import contextlib
import logging
import time
import urllib.parse
from typing import Final

import serial

from rcb4hv.errors import TransportError
from rcb4hv.transport import DEFAULT_BAUD, resolve_port
from rcb4hv.transport.serial_port import (
    OPEN_ERRORS,
    PORT_ERRORS,
    check_url,
    leave_pty_armed,
    link_error,
    open_error,
    set_port_rate,
)

__all__ = ["AsyncTransport", "PolledTransport", "StreamTransport", "open_async_transport"]

log = logging.getLogger(__name__)

POLL_INTERVAL: Final = 0.001
"""Seconds between two polls of a port without a file descriptor."""
CLOSE_TIMEOUT: Final = 2.0
"""Seconds a close waits for bytes still queued to leave (the blocking face's write timeout);
then they are dropped and the port closed at once."""


class AsyncTransport(abc.ABC):
    """A bidirectional byte link to one board, for asyncio."""

    url: str = ""

    @abc.abstractmethod
    def write(self, data: bytes) -> None:
        """Queue ``data`` for sending (the whole of it)."""

    @abc.abstractmethod
    async def read(self, size: int, deadline: float) -> bytes:
        """Return as soon as ``size`` bytes have arrived, or with fewer (maybe none) at
        ``deadline`` (``time.monotonic()`` seconds)."""

    async def read_some(self, size: int, deadline: float) -> bytes:
        """Return what has arrived, up to ``size`` bytes, as soon as there is something; or
        nothing at ``deadline`` (as :meth:`rcb4hv.transport.Transport.read_some`)."""
        return await self.read(min(size, 4), deadline)

    @abc.abstractmethod
    def reset_input(self) -> None:
        """Discard every byte received but not read yet."""

    @abc.abstractmethod
    async def close(self) -> None:
        """Release the link; idempotent."""

    @property
    @abc.abstractmethod
    def is_open(self) -> bool:
        """Whether the link is usable."""

    def set_baudrate(self, baudrate: int) -> None:
        """Change the line rate (serial ports only)."""
        raise ValueError(f"{self.url}: baud detection needs a serial port")

    async def reopen(self) -> None:
        """Open the link again after a failure (default: not supported)."""
        raise TransportError(f"{type(self).__name__} cannot be reopened")

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.url!r}>"


class _LinkProtocol(asyncio.Protocol):
    """Collects received bytes and wakes the reader."""

    def __init__(self) -> None:
        self.buffer = bytearray()
        self.arrived = asyncio.Event()
        self.lost: str | None = None
        self.closed = asyncio.Event()  # connection_lost ran: the port or socket is closed
        self.transport: asyncio.BaseTransport | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self.transport = transport

    def data_received(self, data: bytes) -> None:
        self.buffer += data
        self.arrived.set()

    def eof_received(self) -> bool | None:
        self.lost = "the peer closed the connection"
        self.arrived.set()
        return None

    def connection_lost(self, exc: Exception | None) -> None:
        if self.lost is None:
            self.lost = f"connection lost: {exc}" if exc else "connection closed"
        self.arrived.set()
        self.closed.set()


class StreamTransport(AsyncTransport):
    """A link whose bytes the event loop delivers (TCP socket or serial file descriptor)."""

    def __init__(
        self,
        transport: asyncio.Transport,
        protocol: _LinkProtocol,
        url: str,
        port: serial.Serial | None = None,
    ) -> None:
        self._transport = transport
        self._protocol = protocol
        self._port = port
        self.url = url

    @property
    def is_open(self) -> bool:
        return self._protocol.lost is None and not self._transport.is_closing()

    def _check(self) -> None:
        if self._protocol.lost is not None:
            raise TransportError(f"{self.url}: {self._protocol.lost}")
        if self._transport.is_closing():
            raise TransportError(f"{self.url}: port closed")

    def write(self, data: bytes) -> None:
        self._check()
        try:
            self._transport.write(data)
        except (OSError, RuntimeError, serial.SerialException) as exc:
            raise link_error(self.url, "write failed", exc) from exc

    async def _wait(self, count: int, deadline: float) -> None:
        """Until ``count`` bytes are buffered, or ``deadline``."""
        proto = self._protocol
        while len(proto.buffer) < count:
            self._check()
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return
            proto.arrived.clear()
            with contextlib.suppress(asyncio.TimeoutError):
                await asyncio.wait_for(proto.arrived.wait(), remaining)

    def _take(self, size: int) -> bytes:
        buffer = self._protocol.buffer
        out = bytes(buffer[:size])
        del buffer[:size]
        return out

    async def read(self, size: int, deadline: float) -> bytes:
        await self._wait(size, deadline)
        return self._take(size)

    async def read_some(self, size: int, deadline: float) -> bytes:
        await self._wait(1, deadline)
        return self._take(size)

    def reset_input(self) -> None:
        self._check()
        self._protocol.buffer.clear()
        if self._port is not None:
            try:
                self._port.reset_input_buffer()
            except PORT_ERRORS as exc:
                raise link_error(self.url, "cannot flush input", exc) from exc

    def set_baudrate(self, baudrate: int) -> None:
        if self._port is None:
            # socket://: the rate is the far end's (as pyserial's socket:// port, which the
            # blocking client uses, takes any rate), so baud detection runs its ACK checks
            log.debug("%s: %d baud is the far end's setting", self.url, baudrate)
            return
        set_port_rate(self._port, baudrate, self.url)

    async def close(self) -> None:
        """Return once the port (or socket) is closed: the event loop closes it after the
        bytes still queued have left (a serial port's in an executor thread), then tells the
        protocol, last."""
        transport, closed = self._transport, self._protocol.closed
        if not transport.is_closing():
            if self._port is not None and self._port.is_open:
                leave_pty_armed(self._port)
            transport.close()
        with contextlib.suppress(asyncio.TimeoutError):
            await asyncio.wait_for(closed.wait(), CLOSE_TIMEOUT)
            return
        if transport.get_write_buffer_size():  # stuck: drop them (else the close is under way)
            log.warning(
                "%s: %d byte(s) not sent at close", self.url, transport.get_write_buffer_size()
            )
            transport.abort()
        await closed.wait()

    async def reopen(self) -> None:
        await self.close()
        port = self._port
        if port is None:
            fresh: AsyncTransport = await _open_socket(self.url, "reopen")
        else:
            fresh = await _open_serial(self.url, int(port.baudrate), "reopen")
        if not isinstance(fresh, StreamTransport):  # pragma: no cover - the fd went away
            await fresh.close()
            raise TransportError(f"cannot reopen {self.url}: the port has no file descriptor")
        self._transport, self._protocol, self._port = fresh._transport, fresh._protocol, fresh._port


class PolledTransport(AsyncTransport):
    """A pyserial port without a file descriptor, opened with ``timeout=0`` and polled."""

    def __init__(self, port: serial.Serial, url: str) -> None:
        self._port = port
        self.url = url

    @property
    def is_open(self) -> bool:
        return bool(self._port.is_open)

    def write(self, data: bytes) -> None:
        try:
            self._port.write(data)
        except PORT_ERRORS as exc:
            raise link_error(self.url, "write failed", exc) from exc

    async def read(self, size: int, deadline: float) -> bytes:
        buf = b""
        try:
            while True:
                buf += self._port.read(size - len(buf))
                if len(buf) >= size:
                    return buf
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return buf
                await asyncio.sleep(min(POLL_INTERVAL, remaining))
        except (OSError, ValueError, TypeError, serial.SerialException) as exc:
            raise link_error(self.url, "read failed", exc) from exc

    def reset_input(self) -> None:
        try:
            self._port.reset_input_buffer()
        except PORT_ERRORS as exc:
            raise link_error(self.url, "cannot flush input", exc) from exc

    def set_baudrate(self, baudrate: int) -> None:
        set_port_rate(self._port, baudrate, self.url)

    async def close(self) -> None:
        with contextlib.suppress(OSError, serial.SerialException):
            self._port.close()

    async def reopen(self) -> None:
        await self.close()
        try:
            self._port.open()
        except OPEN_ERRORS as exc:
            raise open_error(self.url, exc, "reopen") from exc


def _has_fd(port: serial.Serial) -> bool:
    try:
        return int(port.fileno()) >= 0
    except (AttributeError, OSError, ValueError, TypeError, serial.SerialException):
        return False


async def _open_socket(url: str, verb: str = "open") -> StreamTransport:
    check_url(url)  # the blocking face's rule: a host, and a port within 1..65535
    parts = urllib.parse.urlsplit(url)
    host, port = parts.hostname, parts.port
    assert host is not None and port is not None  # check_url saw to it
    loop = asyncio.get_running_loop()
    try:
        transport, protocol = await loop.create_connection(_LinkProtocol, host, port)
    except OSError as exc:
        raise open_error(url, exc, verb) from exc
    return StreamTransport(transport, protocol, url)


async def _open_serial(url: str, baudrate: int, verb: str = "open") -> AsyncTransport:
    # Import here: the package is only needed for serial devices. pyserial-asyncio-fast
    # watches the port's file descriptor with the event loop (no thread, no polling).
    import serial_asyncio_fast

    from rcb4hv.transport import serial_port  # registers the rcb4emu:// handler

    loop = asyncio.get_running_loop()

    try:
        port = await loop.run_in_executor(None, serial_port.open_8e1, url, baudrate, 0)
    except OPEN_ERRORS as exc:  # as the blocking face (a bad fault:// spec...)
        raise open_error(url, exc, verb) from exc
    if not _has_fd(port):
        return PolledTransport(port, url)
    # pyserial-asyncio-fast sets timeout = write_timeout = 0, which pyserial applies with a
    # second tcsetattr; at custom rates such as 1,250,000 some drivers (ptys included) refuse
    # it. The port was opened with both at 0 already, so skip that no-op reconfiguration.
    setattr(port, "_reconfigure_port", lambda *args, **kwargs: None)  # noqa: B010
    try:
        transport, protocol = await serial_asyncio_fast.connection_for_serial(
            loop, _LinkProtocol, port
        )
    except PORT_ERRORS as exc:
        port.close()
        raise open_error(url, exc, "use") from exc
    finally:
        delattr(port, "_reconfigure_port")
    assert isinstance(protocol, _LinkProtocol)
    return StreamTransport(transport, protocol, url, port)


async def open_async_transport(
    url: str | None = None, baudrate: int = DEFAULT_BAUD
) -> AsyncTransport:
    """Open ``url`` (None: ``$RCB4HV_PORT`` or the Kondo adapter, as the blocking client) at
    8E1 and ``baudrate`` (ignored by ``socket://`` and ``rcb4emu://``)."""
    url = resolve_port(url)
    if baudrate <= 0:
        raise ValueError(f"baud rate {baudrate} must be positive")
    if url.lower().startswith("socket://"):
        return await _open_socket(url)
    transport = await _open_serial(url, baudrate)
    log.debug("opened %s (%s)", url, type(transport).__name__)
    return transport
