"""The exception tree of rcb4hv.

::

    Rcb4Error                      base of everything this package raises on purpose
    ├── ProtocolError              bytes that are not a valid frame / command / reply
    │   ├── FrameError             framing: bad size byte, oversize or truncated frame
    │   └── ChecksumError          a frame whose last byte is not the sum of the others
    ├── NakError                   the board answered NAK (``04 CMD 15 SUM``)
    ├── TransportError             the port failed, closed or disconnected
    └── Rcb4TimeoutError           no (complete) reply in time; also a builtin TimeoutError

Bad arguments given by the caller raise the builtin :class:`ValueError` before any byte is
sent. A ``ProtocolError`` always means "the peer (or a file) sent garbage"; anything else that
escapes is a bug.
"""

from __future__ import annotations

__all__ = [
    "ChecksumError",
    "FrameError",
    "LayoutError",
    "NakError",
    "ProtocolError",
    "Rcb4Error",
    "Rcb4TimeoutError",
    "TransportError",
]


class Rcb4Error(Exception):
    """Base class of every error rcb4hv raises on purpose."""


class ProtocolError(Rcb4Error):
    """Bytes that do not form a valid frame, command or reply."""


class FrameError(ProtocolError):
    """A framing problem: a size byte out of range, an oversize or truncated frame."""


class ChecksumError(ProtocolError):
    """A frame whose checksum byte does not match the sum of its other bytes."""

    def __init__(self, message: str, frame: bytes = b"") -> None:
        super().__init__(message)
        self.frame = frame


class NakError(Rcb4Error):
    """The board answered NAK to a command."""

    def __init__(self, message: str, command: int | None = None) -> None:
        super().__init__(message)
        self.command = command


class TransportError(Rcb4Error):
    """The link failed: the port could not be opened, was closed or disconnected."""


class Rcb4TimeoutError(Rcb4Error, TimeoutError):
    """No complete reply arrived within the timeout."""


class LayoutError(Rcb4Error, ValueError):
    """A project or image does not fit a HeartToHeart4 ROM layout: motions stored for no
    known layout, or a motion that cannot be moved to the layout asked for."""
