"""Ports opened with pyserial's ``serial_for_url``: device paths, ``socket://``, ``rfc2217://``,
``spy://`` (hex traces), ``loop://`` and the in-process emulator ``rcb4emu://``."""

from __future__ import annotations

import contextlib
import errno
import logging
import os
import select
import socket
import time
import urllib.parse
from typing import Final

import serial
import serial.tools.list_ports

from rcb4hv.errors import TransportError
from rcb4hv.transport.base import Transport

__all__ = [
    "BAUD_RATES",
    "DEFAULT_BAUD",
    "KINDS",
    "KONDO_PIDS",
    "KONDO_VID",
    "OPEN_ERRORS",
    "PORT_ERRORS",
    "SerialTransport",
    "check_url",
    "find_kondo_ports",
    "leave_pty_armed",
    "link_error",
    "open_error",
    "port_errors",
    "resolve_port",
    "set_port_rate",
]

log = logging.getLogger(__name__)

# Kondo's USB IDs. 165C:0008 is the Kondo USB adapter HS, the ID the rcb4 library (iory/rcb4:
# its 99-rcb4-udev.rules and RCB4Interface.from_port) matches to find an RCB-4; 0007 is the
# older adapter named in the working spec (PROTOCOL.md section 1). Linux's ftdi_sio lists only
# 165C:0002 (drivers/usb/serial/ftdi_sio_ids.h), hence the new_id line of `rcb4hv udev-rule`.
KONDO_VID: Final = 0x165C
KONDO_PIDS: Final = (0x0008, 0x0007)
BAUD_RATES: Final = (1250000, 625000, 115200)
DEFAULT_BAUD: Final = 1250000
PORT_ENV: Final = "RCB4HV_PORT"

# Ports without a file descriptor to select() on are read in slices of this many seconds, so
# a read overshoots its deadline by at most this much. (pyserial's timeout is never changed
# after opening: on POSIX that reconfigures the port, and at custom baud rates such as
# 1250000 the second tcsetattr is refused by some drivers, ptys included.)
_SLICE: Final = 0.01


def port_errors() -> tuple[type[BaseException], ...]:
    errors: tuple[type[BaseException], ...] = (serial.SerialException, OSError)
    try:
        import termios  # POSIX only; termios.error is not an OSError

        errors += (termios.error,)
    except ImportError:  # pragma: no cover - Windows
        pass
    return errors


PORT_ERRORS: Final = port_errors()
OPEN_ERRORS: Final[tuple[type[BaseException], ...]] = (*PORT_ERRORS, ValueError)
"""A port's errors and pyserial's ValueError (a URL or a setting it rejects): opening, reopening
and setting the rate catch these."""


def set_port_rate(port: serial.Serial, baudrate: int, url: str) -> None:
    """Set ``port``'s rate (both faces' transports): not again at the rate it has (a second
    tcsetattr at a custom rate is refused by some drivers, ptys included), and every failure
    (termios.error and pyserial's ValueError for a rate it rejects too) a TransportError."""
    if port.baudrate == baudrate:
        return
    try:
        port.baudrate = baudrate
    except OPEN_ERRORS as exc:
        raise TransportError(f"{url}: cannot set {baudrate} baud: {exc}") from exc


_POSIX_SERIAL: Final[type | None] = getattr(getattr(serial, "serialposix", None), "Serial", None)


# pyserial's URL-handler registry, by package name: ``rcb4emu://`` is served by
# rcb4hv.emulator.protocol_rcb4emu and ``fault://`` by rcb4hv.transport.protocol_fault, which
# pyserial imports when such a URL is opened. This layer imports no emulator code; the
# emulator plugs in through pyserial's own extension point.
URL_HANDLER_PACKAGES: Final = ("rcb4hv.emulator", "rcb4hv.transport")


def _register_handlers() -> None:
    for package in URL_HANDLER_PACKAGES:
        if package not in serial.protocol_handler_packages:
            serial.protocol_handler_packages.append(package)


_register_handlers()


def find_kondo_ports() -> list[str]:
    """Device names of every Kondo USB adapter (VID 165C, PID 0008 or 0007) plugged in."""
    found = []
    for info in serial.tools.list_ports.comports():
        if info.vid == KONDO_VID and info.pid in KONDO_PIDS:
            found.append(info.device)
    return sorted(found)


def resolve_port(port: str | None, env: str = PORT_ENV, emulator: str = "rcb4emu://") -> str:
    """The URL to open: ``port`` if given, else ``$RCB4HV_PORT`` (``env``: another variable,
    e.g. the ICS tools' ``RCB4HV_ICS_PORT``), else the one Kondo adapter. ``emulator``: the
    URL the error suggests."""
    if port:
        return port
    value = os.environ.get(env)
    if value:
        return value
    found = find_kondo_ports()
    if not found:
        raise TransportError(
            "no Kondo USB adapter (VID 165C, PID 0008/0007) found; "
            f"give a port (--port URL or ${env}), e.g. /dev/ttyUSB0 or {emulator}"
        )
    if len(found) > 1:
        log.warning("several Kondo adapters found (%s); using %s", ", ".join(found), found[0])
    return found[0]


def open_8e1(url: str, baudrate: int, write_timeout: float) -> serial.Serial:
    """``serial_for_url`` at the board's framing, 8 data bits, even parity, 1 stop bit,
    non-blocking reads (``timeout=0``)."""
    port: serial.Serial = serial.serial_for_url(
        url,
        baudrate=baudrate,
        bytesize=serial.EIGHTBITS,
        parity=serial.PARITY_EVEN,
        stopbits=serial.STOPBITS_ONE,
        timeout=0,
        write_timeout=write_timeout,
    )
    return port


def _disable_nagle(port: object) -> None:
    """pyserial's socket:// leaves Nagle's algorithm on: a frame written in two parts would then
    reach the board ~40 ms apart, past its frame timeout. Send every write at once instead."""
    sock = getattr(port, "_socket", None)
    if isinstance(sock, socket.socket) and sock.family in (socket.AF_INET, socket.AF_INET6):
        with contextlib.suppress(OSError):
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)


KINDS = "a port is a device path, socket://HOST:PORT, rfc2217://, rcb4emu://, spy://DEV or fault://"


def check_url(url: str) -> None:
    """TransportError for a URL pyserial would fail on obscurely (a socket without a host or a
    port, a port past 65535); the rule of both faces (the asyncio one opens sockets itself)."""
    if not url.lower().startswith("socket://"):
        return
    try:
        parts = urllib.parse.urlsplit(url)
        port = parts.port
    except ValueError as exc:
        raise TransportError(f"cannot open {url}: {exc} (socket://HOST:PORT)") from exc
    if port is None or not parts.hostname:
        what = "a port" if parts.hostname else "a host"
        raise TransportError(
            f"cannot open {url}: a socket:// URL needs {what} (socket://HOST:PORT)"
        )


# Linux's Unix98 pty slaves (Documentation/admin-guide/devices.txt: majors 136-143).
PTY_SLAVE_MAJORS: Final = range(136, 144)
# A link that is gone: a pty whose master closed (the emulator stopped), an adapter unplugged.
_GONE_ERRNOS: Final = frozenset({errno.EIO, errno.ENXIO, errno.ENODEV})
_PTY_EINVAL: Final = (
    "a pty cannot store even parity, so it refuses a set-up that changes nothing it holds: if "
    "another client has just set it up, open it again a moment later (`rcb4hv emulate --pty` "
    "re-arms its pty after every set-up; another program's pty may never be), or serve the "
    "board on TCP (`rcb4hv emulate --tcp`, socket://HOST:PORT)"
)


def _errno(exc: BaseException) -> int | None:
    """The errno of ``exc``: an OSError's, a ``termios.error``'s first argument, or that of
    the OSError pyserial turned into a SerialException."""
    for e in (exc, exc.__cause__, exc.__context__):
        if e is None:
            continue
        code = getattr(e, "errno", None)
        if code is None and e.args and isinstance(e.args[0], int):
            code = e.args[0]
        if isinstance(code, int):
            return code
    return None


def _why(exc: BaseException) -> str:
    """``exc``'s message without a "read failed: " or "write failed: " pyserial put in front
    of it already; a ``termios.error`` as an OSError reads."""
    if not isinstance(exc, OSError) and len(exc.args) == 2 and isinstance(exc.args[0], int):
        return f"[Errno {exc.args[0]}] {exc.args[1]}"
    return str(exc).removeprefix("read failed: ").removeprefix("write failed: ")


def _is_pty(path: str) -> bool:
    try:
        return os.major(os.stat(path).st_rdev) in PTY_SLAVE_MAJORS
    except (OSError, ValueError):
        return False


def open_error(url: str, exc: BaseException, verb: str = "open") -> TransportError:
    """The TransportError of a port that would not ``verb`` (open, reopen), both faces."""
    message = f"cannot {verb} {url}: {_why(exc)}"
    if isinstance(exc, ValueError):  # pyserial: "invalid URL, protocol 'x' not known"
        message += f" ({KINDS})"
    elif _errno(exc) == errno.EINVAL and _is_pty(url):
        message += f" ({_PTY_EINVAL})"
    return TransportError(message)


def link_error(url: str, failed: str, exc: BaseException) -> TransportError:
    """The TransportError of a port call that ``failed`` ("read failed", "cannot flush
    input"...), one wording for both faces: a port not open and a link that is gone said so."""
    if isinstance(exc, serial.PortNotOpenError):  # "Attempting to use a port that is not open"
        return TransportError(f"{url}: the port is not open (closed, or its reopen failed)")
    if _errno(exc) in _GONE_ERRNOS:
        return TransportError(
            f"{url}: the link is gone ({failed}: {_why(exc)}): the board's adapter was "
            "unplugged, or the emulator serving the port stopped"
        )
    return TransportError(f"{url}: {failed}: {_why(exc)}")


def leave_pty_armed(port: serial.Serial) -> None:
    """Before a pty is closed: set CSTOPB on it, so that the next open's set-up changes
    ``c_cflag`` however soon it comes. A pty cannot store even parity, and glibc's
    ``tcsetattr`` fails (EINVAL) a set-up that changes nothing the pty holds, which is what
    reopening with the same settings asks for; ``rcb4hv emulate --pty`` re-arms its pty after
    every set-up, but an open right after a close can come first. Other ports: nothing."""
    fd = getattr(port, "fd", None)
    if _POSIX_SERIAL is None or not isinstance(port, _POSIX_SERIAL) or not isinstance(fd, int):
        return
    import termios  # POSIX only, as _POSIX_SERIAL

    try:
        if os.major(os.fstat(fd).st_rdev) not in PTY_SLAVE_MAJORS:
            return
        attrs = termios.tcgetattr(fd)
        if not attrs[2] & termios.CSTOPB:
            attrs[2] |= termios.CSTOPB
            termios.tcsetattr(fd, termios.TCSANOW, attrs)
    except (OSError, termios.error) as exc:
        log.debug("%s: could not leave the pty armed: %s", port.port, exc)


class SerialTransport(Transport):
    """A :class:`Transport` over any pyserial port object, at 8E1."""

    def __init__(self, port: serial.Serial, url: str | None = None) -> None:
        self.port = port
        self.url = url if url is not None else str(port.port)
        self._fd: int | None = None
        self._raw_fd: int | None = None
        self._opened()
        wanted = 0 if self._fd is not None else _SLICE
        try:
            if port.timeout != wanted:
                port.timeout = wanted
        except PORT_ERRORS as exc:
            raise TransportError(f"{self.url}: cannot configure: {exc}") from exc

    @classmethod
    def open(cls, url: str, baudrate: int = DEFAULT_BAUD) -> SerialTransport:
        """Open ``url`` with ``serial_for_url`` at ``baudrate``, 8 data bits, even parity, 1 stop.

        ``socket://`` and ``rcb4emu://`` ignore baud and parity.
        """
        if baudrate <= 0:
            raise ValueError(f"baud rate {baudrate} must be positive")
        check_url(url)
        try:
            port = open_8e1(url, baudrate, write_timeout=2.0)
        except OPEN_ERRORS as exc:
            raise open_error(url, exc) from exc
        log.debug("opened %s at %d baud", url, baudrate)
        try:
            return cls(port, url)
        except BaseException:
            port.close()
            raise

    def _opened(self) -> None:
        """What every open of the port does once pyserial has opened it (:meth:`open` and
        :meth:`reopen` alike, so they cannot drift apart): find the fd, and turn Nagle off."""
        port = self.port
        try:
            self._fd = int(port.fileno())
        except (AttributeError, OSError, ValueError, TypeError, serial.SerialException):
            self._fd = None  # no fd: rcb4emu://, loop://, fault://
        # A POSIX serial port (device, pty) is opened non-blocking by pyserial and keeps no
        # buffer of its own: its fd is read and written directly (one system call each way
        # instead of pyserial's select/read loops).
        self._raw_fd = self._fd if type(port) is _POSIX_SERIAL else None
        _disable_nagle(port)

    @property
    def is_open(self) -> bool:
        return bool(self.port.is_open)

    @property
    def baudrate(self) -> int:
        return int(self.port.baudrate)

    def set_baudrate(self, baudrate: int) -> None:
        set_port_rate(self.port, baudrate, self.url)

    def write(self, data: bytes) -> None:
        fd = self._raw_fd
        if fd is not None:
            try:
                n = os.write(fd, data)
            except BlockingIOError:
                n = 0
            except OSError as exc:
                raise link_error(self.url, "write failed", exc) from exc
            if n == len(data):
                return
            data = data[n:]
        try:
            self.port.write(data)
        except PORT_ERRORS as exc:
            raise link_error(self.url, "write failed", exc) from exc

    def read(self, size: int, deadline: float) -> bytes:
        port, fd = self.port, self._fd
        buf = b""
        try:
            while True:
                buf += port.read(size - len(buf))  # non-blocking (fd) or one slice
                if len(buf) >= size:
                    return buf
                remaining = deadline - time.monotonic()
                if remaining <= 0.0:
                    return buf
                if fd is not None:
                    select.select((fd,), (), (), remaining)
        except (serial.SerialException, OSError, ValueError) as exc:
            raise link_error(self.url, "read failed", exc) from exc
        except TypeError as exc:  # pyserial on a port closed under it (fd None)
            raise TransportError(f"{self.url}: port closed: {exc}") from exc

    def read_some(self, size: int, deadline: float) -> bytes:
        fd = self._raw_fd
        if fd is None:
            return self._read_some_port(size, deadline)
        try:
            while True:
                try:
                    data = os.read(fd, size)
                except BlockingIOError:
                    data = b""
                if data:
                    return data
                remaining = deadline - time.monotonic()
                if remaining <= 0.0:
                    return b""
                select.select((fd,), (), (), remaining)
        except OSError as exc:
            raise link_error(self.url, "read failed", exc) from exc

    def _read_some_port(self, size: int, deadline: float) -> bytes:
        port, fd = self.port, self._fd
        try:
            while True:
                # fd ports have timeout 0 (read returns what is there); the others wait a
                # slice for the bytes asked, so ask for what is buffered (at least one)
                want = size if fd is not None else max(1, min(size, port.in_waiting))
                data = port.read(want)
                if data:
                    if fd is None and len(data) < size:  # the rest that came with it
                        more = min(size - len(data), port.in_waiting)
                        if more:
                            data += port.read(more)
                    return bytes(data)
                remaining = deadline - time.monotonic()
                if remaining <= 0.0:
                    return b""
                if fd is not None:
                    select.select((fd,), (), (), remaining)
        except (serial.SerialException, OSError, ValueError) as exc:
            raise link_error(self.url, "read failed", exc) from exc
        except TypeError as exc:  # pyserial on a port closed under it (fd None)
            raise TransportError(f"{self.url}: port closed: {exc}") from exc

    def reset_input(self) -> None:
        try:
            self.port.reset_input_buffer()
        except PORT_ERRORS as exc:
            raise link_error(self.url, "cannot flush input", exc) from exc

    def close(self) -> None:
        self._raw_fd = None
        port = self.port
        sock = getattr(port, "_socket", None)
        if isinstance(sock, socket.socket):
            # pyserial's socket:// close() leaks the socket when shutdown() fails (peer gone)
            # and then sleeps 0.3 s; close the socket here and mark the port closed instead.
            setattr(port, "_socket", None)  # noqa: B010
            with contextlib.suppress(OSError):
                sock.shutdown(socket.SHUT_RDWR)
            sock.close()
            port.is_open = False
            return
        if port.is_open:
            leave_pty_armed(port)
        try:
            port.close()
        except PORT_ERRORS as exc:
            log.debug("closing %s: %s", self.url, exc)

    def reopen(self) -> None:
        self.close()
        try:
            self.port.open()
        except OPEN_ERRORS as exc:
            raise open_error(self.url, exc, "reopen") from exc
        self._opened()
