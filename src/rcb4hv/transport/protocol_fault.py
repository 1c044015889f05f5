"""pyserial URL handler for ``fault://SPEC@URL``: the link ``URL`` with faults injected.

``serial_for_url("fault://drop_reply=0.1,seed=3@rcb4emu://")`` opens ``URL`` as a
:class:`~rcb4hv.transport.SerialTransport` and wraps it in a
:class:`~rcb4hv.transport.FaultyTransport` configured by ``SPEC`` (see
:func:`~rcb4hv.transport.parse_fault_url`); the port object's :attr:`Serial.faults` is that
wrapper (``faults.inject(...)``, ``faults.history``). Closing and opening the port again (a
client's ``reconnect()``) reopens that same wrapper's link: faults queued with ``inject``, the
history and the RNG's position carry on, and a reference to ``port.faults`` stays good.

pyserial finds this module by name, as it finds ``rcb4emu://``'s
(:mod:`rcb4hv.emulator.protocol_rcb4emu`): :mod:`rcb4hv.transport` adds ``rcb4hv.transport``
to ``serial.protocol_handler_packages``. So every client that opens URLs through pyserial (the
blocking one, and the asyncio one, which polls ports without a file descriptor) takes
``fault://`` links without knowing about them.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any, Final

from serial.serialutil import PortNotOpenError, SerialBase, SerialException

from rcb4hv.transport.faults import FaultyTransport, parse_fault_url
from rcb4hv.transport.serial_port import SerialTransport

if TYPE_CHECKING:
    from typing_extensions import Buffer

__all__ = ["Serial"]

FOREVER: Final = 365 * 24 * 3600.0
"""The deadline of a read with ``timeout=None`` (pyserial: wait until the bytes arrive)."""


class Serial(SerialBase):
    """A pyserial port object over another link, with faults injected (see the module)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.faults: FaultyTransport | None = None
        self._faults_url: str | None = None  # the URL self.faults was made for
        super().__init__(*args, **kwargs)

    def open(self) -> None:
        if self.is_open:
            raise SerialException("port is already open")
        if self.port is None:
            raise SerialException("port must be configured before it can be used")
        url = str(self.port)
        if self.faults is not None and self._faults_url == url:
            self.faults.reopen()  # the same injector: its script, history and RNG go on
            self.faults.set_baudrate(self.baudrate)
        else:
            config, inner = parse_fault_url(url)
            self.faults = FaultyTransport(SerialTransport.open(inner, self.baudrate), config)
            self._faults_url = url
        self.is_open = True

    def close(self) -> None:
        if self.is_open and self.faults is not None:
            self.faults.close()
        self.is_open = False
        super().close()

    def _link(self) -> FaultyTransport:
        if not self.is_open or self.faults is None:
            raise PortNotOpenError()
        return self.faults

    def _reconfigure_port(self) -> None:
        if self.is_open and self.faults is not None:
            self.faults.set_baudrate(self.baudrate)

    @property
    def in_waiting(self) -> int:
        return self._link().pending()

    def write(self, data: Buffer) -> int:
        raw = bytes(data)
        self._link().write(raw)
        return len(raw)

    def read(self, size: int = 1) -> bytes:
        link = self._link()
        timeout = FOREVER if self.timeout is None else self.timeout
        return link.read(size, time.monotonic() + timeout)

    def reset_input_buffer(self) -> None:
        self._link().reset_input()

    def reset_output_buffer(self) -> None:
        pass
