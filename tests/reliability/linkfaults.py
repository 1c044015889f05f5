"""Link faults that rcb4hv.transport.faults does not inject: duplicated and split replies, a
request split around the board's frame timeout, a short delay, and a real disconnect by the
peer (the TCP server drops the connection).

:class:`LinkFaults` is a :class:`~rcb4hv.transport.Transport` wrapper used *inside* a
:class:`~rcb4hv.transport.FaultyTransport`, so both kinds of faults run on one link. Faults are
scripted (:meth:`LinkFaults.inject`), one per transaction (a transaction starts at ``write``).
"""

from __future__ import annotations

import enum
import select
import socket
import time
from collections import deque
from typing import Final, Protocol

from rcb4hv.errors import TransportError
from rcb4hv.transport import Transport

__all__ = ["LinkFault", "LinkFaults", "set_nodelay"]

SPLIT_GAP: Final = 0.004
"""Seconds between the bytes of a split reply."""
SHORT_DELAY: Final = 0.08
"""Seconds a DELAY_SHORT reply is held back (well inside the suite's call timeout)."""
DUPLICATE_AFTER: Final = 0.003


def set_nodelay(transport: Transport) -> None:
    """TCP_NODELAY on a ``socket://`` port. pyserial leaves Nagle on, so a request written in
    two parts leaves in two segments ~40 ms apart (Nagle + delayed ACK), past the board's 20 ms
    frame timeout; a split-request scenario must test the board, not Nagle."""
    port = getattr(transport, "port", None)
    sock = getattr(port, "_socket", None)
    if isinstance(sock, socket.socket):
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)


class LinkFault(enum.Enum):
    DUPLICATE_REPLY = "duplicate_reply"
    """The reply arrives twice (the copy a few ms later): the call succeeds."""
    SPLIT_REPLY = "split_reply"
    """The reply trickles in byte by byte, SPLIT_GAP apart: the call succeeds."""
    SPLIT_REQUEST = "split_request"
    """The request leaves in two parts, a tenth of a frame timeout apart: the call succeeds."""
    SPLIT_REQUEST_LONG = "split_request_long"
    """SIZE and CMD, then three frame timeouts of silence, then the rest: the board NAKs the
    partial frame (spec 13 #12), so the call raises NakError."""
    DELAY_SHORT = "delay_short"
    """The reply is held back SHORT_DELAY seconds: the call succeeds."""
    PEER_DISCONNECT = "peer_disconnect"
    """The TCP server drops the connection (another client connects): TransportError."""


class _HasAddress(Protocol):
    @property
    def address(self) -> tuple[str, int]: ...


_PREFETCH: Final = (LinkFault.DUPLICATE_REPLY, LinkFault.SPLIT_REPLY, LinkFault.DELAY_SHORT)


class LinkFaults(Transport):
    """Wrap ``inner`` (a ``socket://`` SerialTransport for PEER_DISCONNECT, whose ``server``
    is the TcpServer) and apply scripted :class:`LinkFault` faults."""

    def __init__(
        self, inner: Transport, *, frame_timeout: float, server: _HasAddress | None = None
    ) -> None:
        self.inner = inner
        self.url = f"linkfaults:{inner.url}"
        self.frame_timeout = frame_timeout
        self.server = server
        self.history: list[LinkFault] = []
        self._script: deque[LinkFault | None] = deque()
        self._active: LinkFault | None = None
        self._prefetched = False
        self._rx = bytearray()
        self._held: deque[tuple[float, bytes]] = deque()
        set_nodelay(inner)

    def inject(self, *faults: LinkFault | None) -> None:
        self._script.extend(faults)

    def clear(self) -> None:
        self._script.clear()

    @property
    def is_open(self) -> bool:
        return self.inner.is_open

    def write(self, data: bytes) -> None:
        fault = self._script.popleft() if self._script else None
        self._active, self._prefetched = fault, False
        if fault is not None:
            self.history.append(fault)
        if fault is LinkFault.SPLIT_REQUEST and len(data) > 1:
            half = len(data) // 2
            self.inner.write(data[:half])
            time.sleep(self.frame_timeout / 10)
            self.inner.write(data[half:])
        elif fault is LinkFault.SPLIT_REQUEST_LONG and len(data) > 2:
            self.inner.write(data[:2])
            time.sleep(self.frame_timeout * 3)
            self.inner.write(data[2:])
        elif fault is LinkFault.PEER_DISCONNECT:
            self._make_peer_drop()
            self.inner.write(data)
        else:
            self.inner.write(data)

    def _make_peer_drop(self) -> None:
        """Connect a second client: the server (one connection at a time) drops ours. Wait
        until our socket sees the EOF so the fault cannot race the request."""
        if self.server is None:
            raise TransportError("PEER_DISCONNECT needs the TcpServer")
        fd = getattr(self.inner, "_fd", None)
        with socket.create_connection(self.server.address, timeout=2.0):
            if isinstance(fd, int):
                select.select([fd], [], [], 1.0)

    def _read_reply(self, deadline: float) -> bytes:
        head = self.inner.read(1, deadline)
        if not head:
            return b""
        return head + self.inner.read(max(head[0] - 1, 0), deadline)

    def _release(self) -> None:
        now = time.monotonic()
        while self._held and self._held[0][0] <= now:
            self._rx += self._held.popleft()[1]

    def read(self, size: int, deadline: float) -> bytes:
        if self._active in _PREFETCH and not self._prefetched:
            self._prefetched = True
            reply = self._read_reply(deadline)
            now = time.monotonic()
            if self._active is LinkFault.DUPLICATE_REPLY:
                self._held.append((now, reply))
                self._held.append((now + DUPLICATE_AFTER, reply))
            elif self._active is LinkFault.SPLIT_REPLY:
                for i, b in enumerate(reply):
                    self._held.append((now + i * SPLIT_GAP, bytes((b,))))
            else:
                self._held.append((now + SHORT_DELAY, reply))
        while True:
            self._release()
            if len(self._rx) >= size:
                break
            now = time.monotonic()
            if now >= deadline:
                break
            if self._held:
                time.sleep(max(0.0, min(deadline, self._held[0][0]) - now))
                continue
            self._rx += self.inner.read(size - len(self._rx), deadline)
        out = bytes(self._rx[:size])
        del self._rx[:size]
        return out

    def reset_input(self) -> None:
        self.inner.reset_input()
        self._release()
        self._rx.clear()

    def close(self) -> None:
        self.inner.close()

    def reopen(self) -> None:
        self._rx.clear()
        self._held.clear()
        self.inner.reopen()
        set_nodelay(self.inner)
