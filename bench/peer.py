"""The peer library, PyPI ``rcb4`` 0.1.6, driven the way its users drive it.

``make bench`` installs it with the ``bench`` extra (``pip install -e '.[bench]'``). Nothing
here copies its code: every peer figure calls its public :class:`RCB4Interface` methods
(``servo_angle_vector``, ``write_move_ram_to_com_command``, ``check_ack``, ``angle_vector``).

For the host-only figures both libraries talk to an in-memory link that answers the canned
reply at once: ours a :class:`~rcb4hv.transport.Transport`, the peer's a stand-in for its
``serial.Serial`` object (``flushInput``, ``write``, ``in_waiting``, ``read``), so each call
runs the library's whole code path (argument handling, frame building, framing and checking
the reply) without an operating-system call.
"""

from __future__ import annotations

import contextlib
import io
from typing import Any

from rcb4hv.transport import Transport

PEER = "rcb4"
PEER_VERSION = "0.1.6"


def available() -> str | None:
    """None if rcb4 0.1.6 imports, else why not."""
    try:
        from importlib.metadata import version

        got = version(PEER)
        import rcb4.rcb4interface  # noqa: F401
    except Exception as exc:  # any import failure means: no peer rows
        return f"{PEER} {PEER_VERSION} not importable ({exc}); pip install -e '.[bench]'"
    if got != PEER_VERSION:
        return f"{PEER} {got} installed, the bench compares with {PEER_VERSION}"
    return None


class CannedTransport(Transport):
    """Our side of the in-memory link: every read returns (the rest of) ``reply``."""

    url = "canned://"

    def __init__(self, reply: bytes) -> None:
        self.reply = reply
        self._left = b""

    def write(self, data: bytes) -> None:
        self._left = self.reply

    def read(self, size: int, deadline: float) -> bytes:
        out, self._left = self._left[:size], self._left[size:]
        return out

    def read_some(self, size: int, deadline: float) -> bytes:
        return self.read(size, deadline)  # all of it at once, as a POSIX port's buffer

    def reset_input(self) -> None:
        self._left = b""

    def close(self) -> None:
        pass

    @property
    def is_open(self) -> bool:
        return True


class CannedSerial:
    """The peer's side of the in-memory link: the pyserial calls ``RCB4Interface`` makes."""

    def __init__(self, reply: bytes) -> None:
        self.reply = reply
        self._left = b""

    def flushInput(self) -> None:
        self._left = b""

    def write(self, data: bytes) -> int:
        self._left = self.reply
        return len(data)

    @property
    def in_waiting(self) -> int:
        return len(self._left)

    def read(self, size: int = 1) -> bytes:
        out, self._left = self._left[:size], self._left[size:]
        return out

    def close(self) -> None:
        pass


def canned_peer(reply: bytes) -> Any:
    """An ``RCB4Interface`` whose port is a :class:`CannedSerial` answering ``reply``.

    Its port is marked as a pyftdi one, so it polls ``read()`` instead of ``select()``-ing a
    file descriptor the stand-in does not have; every servo is marked held, so
    ``servo_angle_vector`` sends what it is given (as after ``hold()``).
    """
    from rcb4.rcb4interface import RCB4Interface

    ri = RCB4Interface()
    ri.serial = CannedSerial(reply)
    ri._serial_is_ftdi = True
    ri.servo_on_states_dict = dict.fromkeys(range(36), True)
    return ri


def quiet() -> contextlib.redirect_stdout[io.StringIO]:
    """The peer prints progress; keep the bench output readable."""
    return contextlib.redirect_stdout(io.StringIO())
