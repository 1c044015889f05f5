"""Links to a board: a small :class:`Transport` interface and its implementations.

* :class:`SerialTransport` — any pyserial ``serial_for_url`` port: device paths,
  ``socket://host:port`` (e.g. ``rcb4hv emulate --tcp``), ``rfc2217://``, ``spy://`` (hex
  trace of the traffic) and ``rcb4emu://`` (the emulator in process, no pty needed; its
  handler lives in :mod:`rcb4hv.emulator.protocol_rcb4emu`, found by pyserial by name);
* :class:`FaultyTransport` — wraps another transport and injects faults; ``fault://SPEC@URL``
  opens one through pyserial (its handler: :mod:`rcb4hv.transport.protocol_fault`).
"""

from __future__ import annotations

from rcb4hv.transport.base import Transport
from rcb4hv.transport.faults import (
    Fault,
    FaultConfig,
    FaultyTransport,
    parse_fault_url,
)
from rcb4hv.transport.serial_port import (
    BAUD_RATES,
    DEFAULT_BAUD,
    KONDO_PIDS,
    KONDO_VID,
    SerialTransport,
    find_kondo_ports,
    resolve_port,
)

__all__ = [
    "BAUD_RATES",
    "DEFAULT_BAUD",
    "EMULATOR_URL",
    "KONDO_PIDS",
    "KONDO_VID",
    "Fault",
    "FaultConfig",
    "FaultyTransport",
    "SerialTransport",
    "Transport",
    "find_kondo_ports",
    "open_transport",
    "parse_fault_url",
    "resolve_port",
]

EMULATOR_URL = "rcb4emu://"


def open_transport(url: str | None = None, baudrate: int = DEFAULT_BAUD) -> Transport:
    """Open ``url`` (None: auto-detect the Kondo adapter, see :func:`resolve_port`) with
    pyserial's ``serial_for_url``: device paths, ``socket://``, ``rcb4emu://``, ``fault://``..."""
    return SerialTransport.open(resolve_port(url), baudrate)
