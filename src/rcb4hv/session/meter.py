"""A transport wrapper that counts the bytes and the wire time of everything it carries."""

from __future__ import annotations

import threading
import time

from rcb4hv.transport import Transport

__all__ = ["MeteredTransport", "wire_seconds"]

BITS_PER_BYTE = 11
"""The RCB-4HV link's 8E1 framing: start bit, eight data bits, even parity, stop bit."""


def wire_seconds(n_bytes: int, baudrate: int) -> float:
    """Seconds ``n_bytes`` occupy a serial line at ``baudrate`` (8E1, 11 bits a byte)."""
    if baudrate <= 0:
        raise ValueError("baudrate must be > 0")
    return n_bytes * BITS_PER_BYTE / baudrate


class MeteredTransport(Transport):
    """Wraps ``inner`` and counts bytes written and read (both directions share the half-duplex
    wire). ``last_write`` is the :func:`time.perf_counter` time of the latest write.

    ``inner`` is exposed under that name, as :class:`~rcb4hv.transport.FaultyTransport` does, so
    the client's baud-rate detection reaches the serial port.
    """

    def __init__(self, inner: Transport) -> None:
        self.inner = inner
        self.url = inner.url
        self.bytes_written = 0
        self.bytes_read = 0
        self.writes = 0
        self.last_write = 0.0
        self._lock = threading.Lock()

    @property
    def total_bytes(self) -> int:
        return self.bytes_written + self.bytes_read

    def snapshot(self) -> tuple[int, int]:
        """(bytes written, bytes read) so far."""
        with self._lock:
            return self.bytes_written, self.bytes_read

    def write(self, data: bytes) -> None:
        self.inner.write(data)
        with self._lock:
            self.bytes_written += len(data)
            self.writes += 1
            self.last_write = time.perf_counter()

    def read(self, size: int, deadline: float) -> bytes:
        data = self.inner.read(size, deadline)
        with self._lock:
            self.bytes_read += len(data)
        return data

    def reset_input(self) -> None:
        self.inner.reset_input()

    def close(self) -> None:
        self.inner.close()

    @property
    def is_open(self) -> bool:
        return self.inner.is_open

    def reopen(self) -> None:
        self.inner.reopen()

    def set_baudrate(self, baudrate: int) -> None:
        self.inner.set_baudrate(baudrate)
