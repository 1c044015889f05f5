"""pyserial URL handler for ``icsemu://``: the ICS bus emulator, in process, without a pty.

``serial_for_url("icsemu://?ids=0,1&baud=115200")`` builds an
:class:`~rcb4hv.ics.EmulatedBus` of default servos on a :class:`~rcb4hv.emulator.RealClock`
and serves it inside ``write()`` / ``read()`` exactly as ``rcb4emu://`` serves a board (this
class reuses that handler's data path). Options:

* ``ids=0,1,...`` the servo IDs on the bus (default ``0``: one servo, as ID commands need);
* ``baud=B``      the servos' EEPROM baud rate (115200 default, 625000, 1250000);
* ``speed=S``     clock speed factor (default 1: EEPROM writes answer after 0.35 s);
* ``version=3.5`` servos that do not answer the ICS 3.6 position read (default 3.6);
* ``bus=N``       serve a bus registered with :func:`ics_emulator_url` (tests inspect it).

In process the port's baud rate is the host's: a servo whose EEPROM says another rate stays
silent, as on a real wire. Parity means nothing here (nor on a pty).
"""

from __future__ import annotations

import urllib.parse
from typing import Any

from serial.serialutil import SerialException

from rcb4hv.emulator.clock import RealClock
from rcb4hv.emulator.protocol_rcb4emu import Serial as _EmulatorSerial
from rcb4hv.emulator.protocol_rcb4emu import emulator_url, registered_device
from rcb4hv.emulator.urlquery import query_settings
from rcb4hv.ics import EmulatedBus, IcsSettings, parse_ids
from rcb4hv.ics.codec import BAUD_RATES

__all__ = ["Serial", "ics_emulator_url"]

SCHEME = "icsemu"


def ics_emulator_url(bus: EmulatedBus) -> str:
    """Register ``bus`` (weakly: keep a reference) and return an ``icsemu://?bus=N`` URL."""
    return emulator_url(bus).replace("rcb4emu://?board=", f"{SCHEME}://?bus=")


class Serial(_EmulatorSerial):
    """A pyserial port whose far end is an in-process emulated ICS bus."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self._ids: tuple[int, ...] = (0,)
        self._bus_baud = 115200
        self._version = "3.6"
        super().__init__(*args, **kwargs)

    def open(self) -> None:
        if self.is_open:
            raise SerialException("port is already open")
        if self.port is None:
            raise SerialException("port must be configured before it can be used")
        self._parse_ics_url(str(self.port))
        if self._board_id is not None:
            bus = registered_device(self._board_id)
            if not isinstance(bus, EmulatedBus):
                raise SerialException(f"no ICS bus registered as {self._board_id}")
            self.board, self._own_board = bus, False
        else:
            settings = IcsSettings(version="3.5" if self._version == "3.5" else "3.6")
            self.board = EmulatedBus.with_ids(
                self._ids, clock=RealClock(self._speed), settings=settings, baud=self._bus_baud
            )
            self._own_board = True
        self._latency = self.board.config.min_reply_latency_s
        self._pending.clear()
        self._rx.clear()
        self.is_open = True
        self._reconfigure_port()

    def _parse_ics_url(self, url: str) -> None:
        parts = urllib.parse.urlsplit(url)
        if parts.scheme.lower() != SCHEME:
            raise SerialException(f"expected {SCHEME}://[?ids=0,1&baud=B], got {url!r}")
        self._speed, self._board_id = 1.0, None
        try:
            for key, value in query_settings(parts.query).items():
                if key == "ids":
                    self._ids = parse_ids(value)
                elif key == "baud":
                    self._bus_baud = int(value)
                    if self._bus_baud not in BAUD_RATES:
                        raise ValueError(f"baud must be one of {BAUD_RATES}")
                elif key == "speed":
                    self._speed = float(value)
                    if not self._speed > 0:
                        raise ValueError("speed must be > 0")
                elif key == "version":
                    if value not in ("3.5", "3.6"):
                        raise ValueError("version must be 3.5 or 3.6")
                    self._version = value
                elif key == "bus":
                    self._board_id = int(value)
                else:
                    raise ValueError(f"unknown option {key!r}")
        except ValueError as exc:
            raise SerialException(f"bad {SCHEME}:// URL {url!r}: {exc}") from exc

    def _reconfigure_port(self) -> None:
        """The host's baud rate is visible in process: servos at another rate stay silent."""
        bus = getattr(self, "board", None)
        if isinstance(bus, EmulatedBus):
            bus.host_baud = int(self.baudrate)
