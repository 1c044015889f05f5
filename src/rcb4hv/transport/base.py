"""The transport interface: a byte pipe with bounded reads (after python-can's bus interface)."""

from __future__ import annotations

import abc
from types import TracebackType

from rcb4hv.errors import TransportError


class Transport(abc.ABC):
    """A bidirectional byte link to one board.

    Every read takes an absolute deadline (``time.monotonic()`` seconds), so no call can
    block past it. Implementations raise :class:`~rcb4hv.errors.TransportError` (chained with
    ``raise ... from``) for every failure of the underlying link, never a foreign exception.
    """

    url: str = ""

    @abc.abstractmethod
    def write(self, data: bytes) -> None:
        """Send ``data`` (the whole of it)."""

    @abc.abstractmethod
    def read(self, size: int, deadline: float) -> bytes:
        """Return as soon as ``size`` bytes have arrived, or with fewer (maybe none) at
        ``deadline``."""

    def read_some(self, size: int, deadline: float) -> bytes:
        """Return what has arrived, up to ``size`` bytes, as soon as there is something; or
        nothing at ``deadline``. The default reads up to 4 bytes with :meth:`read` (no reply
        frame is shorter, so it never waits for bytes a reply does not have); ports that can
        take whatever is buffered in one call override it."""
        return self.read(min(size, 4), deadline)

    @abc.abstractmethod
    def reset_input(self) -> None:
        """Discard every byte received but not read yet."""

    @abc.abstractmethod
    def close(self) -> None:
        """Release the link; idempotent."""

    @property
    @abc.abstractmethod
    def is_open(self) -> bool:
        """Whether the link is usable."""

    def reopen(self) -> None:
        """Open the link again after a failure (default: not supported)."""
        raise TransportError(f"{type(self).__name__} cannot be reopened")

    def set_baudrate(self, baudrate: int) -> None:
        """Change the line rate (serial ports only; ValueError on other links)."""
        raise ValueError(f"{self.url}: baud detection needs a serial port")

    def __enter__(self) -> Transport:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.url!r}>"
