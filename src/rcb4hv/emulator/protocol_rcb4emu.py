"""pyserial URL handler for ``rcb4emu://``: the board emulator, in process, without a pty.

``serial_for_url("rcb4emu://?speed=10&rom=/path/img.bin")`` creates an emulator
:class:`~rcb4hv.emulator.Board` running on a :class:`~rcb4hv.emulator.RealClock` (``speed``
times real time) and serves it synchronously inside ``write()`` / ``read()``: no threads.

Options (query string):

* ``speed=S``   clock speed factor (default 1);
* ``rom=PATH``  boot this ROM image file (created if missing, in a directory that exists;
  written back when the ROM changed);
* ``layout=V``  the default board in HeartToHeart4 layout ``V`` (2.2, 2.1, 2.0, 1.3; with
  ``rom=`` only used when the file does not exist yet);
* ``latency=S`` seconds between a request and its reply (default: the board's
  ``min_reply_latency_s``);
* ``board=N``   serve a Board registered with :func:`emulator_url` instead of a new one
  (tests use this to drive a board on a virtual clock and inspect its RAM);
* ``ics_comm=1``: answer 0Eh from emulated ICS servos (``EmulatorConfig.ics_comm``);
* ``adN=COUNTS`` (N = 1-10, repeatable over channels): the input of ADN, 0..1023
  (``EmulatorConfig.ad_inputs``); the measured register reads it minus the channel's
  reference (spec 10.4);
* ``boot=ready`` (default) or ``boot=live``: a new board first runs its start-up program
  in virtual time, so the port opens on a board whose ROM program has reached its main
  loop (servo table in RAM, servos homed) — a command sent right after opening finds the
  servos, as it would on a board powered on a while ago. ``boot=live`` opens at power-on
  and lets the start-up run in real time, as on a board just switched on.

The handler lives with the emulator it serves. pyserial finds it by name: :mod:`rcb4hv.transport`
adds ``rcb4hv.emulator`` to ``serial.protocol_handler_packages`` on import, and pyserial imports
``rcb4hv.emulator.protocol_rcb4emu`` when a ``rcb4emu://`` URL is opened. The transport layer
itself imports no emulator code (see the architecture notes in ``docs/architecture.md``).
"""

from __future__ import annotations

import itertools
import math
import threading
import time
import urllib.parse
import weakref
from typing import TYPE_CHECKING, Any, Protocol

from serial.serialutil import PortNotOpenError, SerialBase, SerialException

from rcb4hv.emulator.board import Board
from rcb4hv.emulator.boot import BootClock, boot_to_main_loop
from rcb4hv.emulator.config import EmulatorConfig, ad_inputs_from
from rcb4hv.emulator.urlquery import query_settings
from rcb4hv.rom.default import default_image
from rcb4hv.rom.layout import LAYOUTS

if TYPE_CHECKING:
    from typing_extensions import Buffer

__all__ = ["BoardLike", "Serial", "emulator_url", "registered_device"]

SCHEME = "rcb4emu"


class BoardLike(Protocol):
    """The part of the emulator's Board this handler uses."""

    def feed(self, data: bytes) -> bytes: ...

    def tick(self) -> None: ...

    def take_output(self) -> bytes: ...

    def close(self) -> None: ...


_boards: weakref.WeakValueDictionary[int, Any] = weakref.WeakValueDictionary()
_ids = itertools.count(1)
_ids_lock = threading.Lock()


def emulator_url(board: BoardLike) -> str:
    """Register ``board`` and return a ``rcb4emu://?board=N`` URL that serves it.

    The registry holds the board weakly: keep a reference for as long as the URL is used.
    Closing such a port does not close the board (its owner does).
    """
    with _ids_lock:
        n = next(_ids)
    _boards[n] = board
    return f"{SCHEME}://?board={n}"


def registered_device(n: int) -> Any:
    """The device registered as ``n`` by :func:`emulator_url` (None if gone)."""
    return _boards.get(n)


class Serial(SerialBase):
    """A pyserial port object whose far end is an in-process emulated board."""

    BAUDRATES = (115200, 625000, 1250000)

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.board: Any = None
        self._own_board = False
        self._latency: float | None = None
        self._speed = 1.0
        self._rom: str | None = None
        self._board_id: int | None = None
        self._layout: str | None = None
        # (release time, bytes) chunks not yet visible to read()
        self._pending: list[tuple[float, bytes]] = []
        self._rx = bytearray()
        super().__init__(*args, **kwargs)

    # ------------------------------------------------------------------ pyserial plumbing

    def open(self) -> None:
        if self.is_open:
            raise SerialException("port is already open")
        if self.port is None:
            raise SerialException("port must be configured before it can be used")
        self._parse_url(str(self.port))
        if self._board_id is not None:
            board = _boards.get(self._board_id)
            if board is None:
                raise SerialException(f"no emulator board registered as {self._board_id}")
            self.board, self._own_board = board, False
        else:
            try:
                clock = BootClock(self._speed)
                image, lay = None, None
                if self._layout is not None:
                    lay = LAYOUTS[self._layout]
                    image = default_image(lay)
                config = EmulatorConfig(
                    ics_comm=self._ics_comm, ad_inputs=ad_inputs_from(self._ad.items())
                )
                self.board = Board(config, clock=clock, rom_image=image, rom_path=self._rom)
                if self._boot_ready:
                    boot_to_main_loop(self.board, clock, lay)
                clock.go_real()
            except (OSError, ValueError) as exc:
                raise SerialException(f"cannot start the emulator: {exc}") from exc
            self._own_board = True
        if self._latency is None:
            cfg = getattr(self.board, "config", None)
            self._latency = float(getattr(cfg, "min_reply_latency_s", 0.0))
        self._pending.clear()
        self._rx.clear()
        self.is_open = True

    def close(self) -> None:
        """Close the port (and the board it made); a ROM image the board cannot save is a
        :class:`~rcb4hv.errors.RomFileError` here, after the port is closed."""
        board, own = self.board, self._own_board
        if self.is_open:
            self.is_open = False
            self.board = None
        super().close()
        if own and board is not None:
            board.close()

    def _raise_rom_error(self) -> None:
        """The board's failure to save its ROM file, once: the host call that meets it fails
        with a :class:`~rcb4hv.errors.RomFileError` naming the file (before sending)."""
        take = getattr(self.board, "take_rom_error", None)
        err = take() if take is not None else None
        if err is not None:
            raise err

    def _parse_url(self, url: str) -> None:
        parts = urllib.parse.urlsplit(url)
        if parts.scheme.lower() != SCHEME:
            raise SerialException(f"expected {SCHEME}://[?speed=S&rom=PATH&layout=V], got {url!r}")
        self._speed, self._rom, self._latency, self._board_id = 1.0, None, None, None
        self._boot_ready = True
        self._layout = None
        self._ics_comm = False
        self._ad: dict[int, int] = {}
        try:
            for key, value in query_settings(parts.query).items():
                if key == "speed":
                    self._speed = float(value)
                    if not 0 < self._speed < math.inf:
                        raise ValueError(f"speed must be a finite number > 0, not {value!r}")
                elif key == "rom":
                    self._rom = value
                elif key == "layout":
                    if value not in ("2.2", "2.1", "2.0", "1.3"):
                        raise ValueError(f"unknown layout {value!r} (2.2, 2.1, 2.0, 1.3)")
                    self._layout = value
                elif key == "latency":
                    self._latency = float(value)
                    if not 0 <= self._latency < math.inf:
                        raise ValueError(f"latency must be a finite number >= 0, not {value!r}")
                elif key == "ics_comm":
                    if value not in ("0", "1"):
                        raise ValueError("ics_comm must be 0 or 1")
                    self._ics_comm = value == "1"
                elif key.startswith("ad") and key[2:].isdigit():
                    self._ad[int(key[2:])] = int(value)
                    ad_inputs_from(self._ad.items())  # a bad channel or value fails here
                elif key == "board":
                    self._board_id = int(value)
                elif key == "boot":
                    if value not in ("ready", "live"):
                        raise ValueError("boot must be 'ready' or 'live'")
                    self._boot_ready = value == "ready"
                else:
                    raise ValueError(f"unknown option {key!r}")
        except ValueError as exc:
            raise SerialException(f"bad {SCHEME}:// URL {url!r}: {exc}") from exc

    def _reconfigure_port(self) -> None:
        """Baud, parity and the rest mean nothing in process."""

    def _update_break_state(self) -> None:
        pass

    def _update_rts_state(self) -> None:
        pass

    def _update_dtr_state(self) -> None:
        pass

    @property
    def cts(self) -> bool:
        return True

    @property
    def dsr(self) -> bool:
        return True

    @property
    def ri(self) -> bool:
        return False

    @property
    def cd(self) -> bool:
        return True

    # ------------------------------------------------------------------ data

    def _pump(self) -> None:
        """Run the board up to now and move every reply that is due into the read buffer."""
        board = self.board
        if board is None:  # closed by another thread during a call
            raise PortNotOpenError()
        board.tick()
        extra = board.take_output()
        now = time.monotonic()
        if extra:
            self._pending.append((now, bytes(extra)))
        if self._pending:
            while self._pending and self._pending[0][0] <= now:
                self._rx += self._pending.pop(0)[1]

    @property
    def in_waiting(self) -> int:
        if not self.is_open:
            raise PortNotOpenError()
        self._pump()
        return len(self._rx)

    def write(self, data: Buffer) -> int:
        if not self.is_open:
            raise PortNotOpenError()
        data = bytes(data)
        board = self.board
        if board is None:
            raise PortNotOpenError()
        self._raise_rom_error()
        reply = board.feed(data)
        if reply:
            due = time.monotonic() + (self._latency or 0.0)
            self._pending.append((due, bytes(reply)))
        return len(data)

    def read(self, size: int = 1) -> bytes:
        if not self.is_open:
            raise PortNotOpenError()
        timeout = self.timeout
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            self._pump()
            if len(self._rx) >= size:
                break
            now = time.monotonic()
            if deadline is not None and now >= deadline:
                break
            # sleep until the next reply is due (or a short poll for ticks), within the deadline
            wake = self._pending[0][0] if self._pending else now + 0.001
            if deadline is not None:
                wake = min(wake, deadline)
            if wake > now:
                time.sleep(min(wake - now, 0.002))
        out = bytes(self._rx[:size])
        del self._rx[:size]
        return out

    def reset_input_buffer(self) -> None:
        if not self.is_open:
            raise PortNotOpenError()
        self._pump()
        self._rx.clear()
        self._raise_rom_error()

    def reset_output_buffer(self) -> None:
        pass
