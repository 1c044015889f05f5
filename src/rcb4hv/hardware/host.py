"""What the host knows about its serial ports: which are Kondo adapters, who may open a device
node, and the FTDI latency timer. Everything that touches the machine goes through
:class:`Host`, so tests substitute a fake sysfs tree, a fake port list and a fake access check.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import serial.tools.list_ports

from rcb4hv.transport import KONDO_PIDS, KONDO_VID

__all__ = ["Host", "PortInfo", "latency_command"]

LATENCY_GOAL_MS = 1
"""The latency timer we want: an FTDI chip holds received bytes up to this many ms before it
sends a short USB packet. The default 16 ms adds up to 16 ms to every reply."""


@dataclass(frozen=True)
class PortInfo:
    """One serial port pyserial lists."""

    device: str
    vid: int | None = None
    pid: int | None = None
    serial_number: str | None = None
    description: str = ""

    @property
    def is_kondo(self) -> bool:
        """A Kondo USB adapter: USB VID 165C with PID 0008 (adapter HS) or 0007 (older)."""
        return self.vid == KONDO_VID and self.pid in KONDO_PIDS

    def describe(self) -> str:
        ids = f" [{self.vid:04X}:{self.pid:04X}]" if self.vid is not None and self.pid else ""
        kondo = " (Kondo adapter)" if self.is_kondo else ""
        return f"{self.device}{ids}{kondo}"


def _system_ports() -> list[PortInfo]:
    return [
        PortInfo(p.device, p.vid, p.pid, p.serial_number, p.description or "")
        for p in serial.tools.list_ports.comports()
    ]


def _group_of(path: str) -> str | None:
    """The group owning the device node (``dialout``, ``uucp``...), None if unknown."""
    try:
        gid = os.stat(path).st_gid
    except OSError:
        return None
    try:
        import grp  # POSIX only

        return grp.getgrgid(gid).gr_name
    except (ImportError, KeyError):
        return str(gid)


def latency_command(tty: str, value: int = LATENCY_GOAL_MS) -> str:
    return f"echo {value} | sudo tee /sys/bus/usb-serial/devices/{tty}/latency_timer"


@dataclass
class Host:
    """The machine as the doctor sees it (every part replaceable for tests)."""

    sysfs: Path = Path("/sys")
    list_ports: Callable[[], Sequence[PortInfo]] = _system_ports
    can_open: Callable[[str], bool] = field(default=lambda path: os.access(path, os.R_OK | os.W_OK))
    group_of: Callable[[str], str | None] = _group_of
    platform: str = os.name

    def ports(self) -> list[PortInfo]:
        return sorted(self.list_ports(), key=lambda p: p.device)

    def kondo_ports(self) -> list[PortInfo]:
        return [p for p in self.ports() if p.is_kondo]

    @staticmethod
    def tty_name(device: str) -> str:
        """``ttyUSB0`` for ``/dev/ttyUSB0`` or for a symlink to it (``/dev/rcb4-A1B2``): the
        path below ``/dev``, so a pty is ``pts/0``, not ``0``."""
        real = Path(os.path.realpath(device))
        dev = Path("/dev")
        return str(real.relative_to(dev)) if real.is_relative_to(dev) else real.name

    def latency_path(self, device: str) -> Path:
        devices = self.sysfs / "bus" / "usb-serial" / "devices"
        return devices / self.tty_name(device) / "latency_timer"

    def latency_ms(self, device: str) -> int | None:
        """The FTDI latency timer of ``device`` in ms, or None when it has none (not a
        usb-serial device, or not Linux)."""
        try:
            return int(self.latency_path(device).read_text().strip())
        except (OSError, ValueError):
            return None
