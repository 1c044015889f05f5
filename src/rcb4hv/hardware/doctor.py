"""``rcb4hv doctor``: check a setup step by step, from the USB adapter to the servos.

Each check gives one :class:`Check` with a status (``ok``, ``warn``, ``fail`` or ``skip``),
what it found, and when it did not pass, the fix to apply. Later checks that need the link
are skipped when an earlier one failed. :func:`run_doctor` returns them all;
:func:`all_passed` is the exit status rule (every check ``ok`` or ``skip``).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Iterator
from dataclasses import asdict, dataclass
from typing import Literal

from rcb4hv.client import Rcb4Client, Robot
from rcb4hv.errors import NakError, Rcb4Error
from rcb4hv.hardware.host import LATENCY_GOAL_MS, Host, latency_command
from rcb4hv.protocol import POSITION_MAX, POSITION_MIN, SERVO, Com, Ics
from rcb4hv.protocol.memory import read_u16
from rcb4hv.transport import BAUD_RATES, KONDO_PIDS, KONDO_VID, SerialTransport
from rcb4hv.transport.serial_port import PORT_ENV

__all__ = ["Check", "Status", "all_passed", "run_doctor"]

log = logging.getLogger(__name__)

Status = Literal["ok", "warn", "fail", "skip"]

LOW_BATTERY_V = 8.0
"""Below this the servos of a KHR-3HV/KXR (9-12 V HV servos) lose torque: warn."""


@dataclass(frozen=True)
class Check:
    name: str
    status: Status
    detail: str
    fix: str = ""

    def line(self) -> str:
        text = f"[{self.status:>4}] {self.name}: {self.detail}"
        return f"{text}\n       fix: {self.fix}" if self.fix else text

    def to_json(self) -> dict[str, str]:
        return asdict(self)


def all_passed(checks: list[Check]) -> bool:
    return all(c.status in ("ok", "skip") for c in checks)


def _is_device(url: str) -> bool:
    return "://" not in url


_IDS = f"USB VID {KONDO_VID:04X}, PID " + " or ".join(f"{p:04X}" for p in KONDO_PIDS)


def _ports(host: Host, port: str | None) -> Iterator[Check]:
    ports = host.ports()
    kondo = [p for p in ports if p.is_kondo]
    listing = ", ".join(p.describe() for p in ports) or "none"
    if kondo or port:
        note = "" if kondo or not _is_device(port or "") else " (using the port given)"
        yield Check("serial ports", "ok", f"{len(kondo)} Kondo adapter(s){note}; ports: {listing}")
    else:
        yield Check(
            "serial ports",
            "fail",
            f"no Kondo adapter ({_IDS}) among: {listing}",
            "plug in the Kondo USB adapter (Linux: `lsusb | grep -i 165c`; the kernel's ftdi_sio "
            "driver does not know these IDs by itself: install `rcb4hv udev-rule`), or give "
            f"--port / ${PORT_ENV}",
        )


def _choose(host: Host, port: str | None) -> str | None:
    if port:
        return port
    env = os.environ.get(PORT_ENV)
    if env:
        return env
    kondo = host.kondo_ports()
    return kondo[0].device if kondo else None


def _local(host: Host, url: str) -> Iterator[Check]:
    """Permission and latency checks of a device node."""
    if not _is_device(url):
        yield Check("permissions", "skip", f"{url} is not a device node")
        yield Check("latency timer", "skip", f"{url} is not a USB serial adapter")
        return
    if not os.path.exists(url):
        yield Check("permissions", "fail", f"{url} does not exist", "check the port name")
        return
    if host.can_open(url):
        yield Check("permissions", "ok", f"{url} opens read/write for this user")
    else:
        group = host.group_of(url) or "dialout"
        yield Check(
            "permissions",
            "fail",
            f"{url} is not readable and writable by this user (group {group})",
            f"sudo usermod -aG {group} $USER, then log out and in (or install `rcb4hv udev-rule`)",
        )
    tty = host.tty_name(url)
    ms = host.latency_ms(url)
    if ms is None:
        yield Check(
            "latency timer", "skip", f"{tty} has no FTDI latency timer (not an FTDI USB adapter)"
        )
    elif ms > LATENCY_GOAL_MS:
        yield Check(
            "latency timer",
            "warn",
            f"{tty}: {ms} ms (every reply may wait up to {ms} ms in the adapter)",
            f"{latency_command(tty)}   (permanently: `rcb4hv udev-rule`)",
        )
    else:
        yield Check("latency timer", "ok", f"{tty}: {ms} ms")


def _board(url: str, timeout: float) -> Iterator[Check]:
    try:
        transport = SerialTransport.open(url)
    except Rcb4Error as exc:
        fix = "close HeartToHeart4 or any other program using the port; check the name"
        if "ermission" in str(exc):
            fix = "join the group owning the port (see permissions) and log in again"
        yield Check("open", "fail", str(exc), fix)
        return
    client = Rcb4Client(transport, timeout=timeout)
    with client:
        yield Check("open", "ok", f"{url} opened at 8E1")
        yield from _talk(client, url)


def _talk(client: Rcb4Client, url: str) -> Iterator[Check]:
    if _is_device(url):
        try:
            rate = client.detect_baudrate(BAUD_RATES, probe_timeout=0.15)
        except Rcb4Error:
            yield Check(
                "baud rate",
                "fail",
                "no ACK at " + ", ".join(f"{r:,}" for r in BAUD_RATES) + " baud",
                "switch the board on (battery connected, LED lit), plug the adapter into the "
                "board's COM connector, close HeartToHeart4",
            )
            return
        yield Check("baud rate", "ok", f"the board ACKs at {rate:,} baud (8E1)")
    else:
        try:
            client.acknowledge_check()
        except Rcb4Error as exc:
            yield Check("baud rate", "fail", f"no ACK: {exc}", "is the emulator or server up?")
            return
        yield Check("baud rate", "ok", "the board ACKs (baud rate not used by this link)")
    robot = Robot(client)
    try:
        yield Check("version", "ok", repr(client.get_version_info().text))
        yield _system(robot)
        yield _battery(robot)
        yield _servos(robot, client)
    except Rcb4Error as exc:
        yield Check("link", "fail", f"the board stopped answering: {exc}", "check the cable")


def _system(robot: Robot) -> Check:
    reg = robot.system_register()
    state = "ROM program running" if reg.rom_run else "ROM program stopped"
    detail = f"{reg.to_word():04X}h: {state}, output period {reg.frame_period_ms:g} ms"
    if reg.rom_error:
        return Check(
            "system register",
            "fail",
            detail + ", ROMERR set (the ROM program hit a bad instruction)",
            "upload the project again (`rcb4hv project upload`), then power-cycle the board",
        )
    if not reg.rom_run:
        return Check(
            "system register",
            "warn",
            detail,
            "`rcb4hv motion stop` restarts the main loop (or power-cycle the board)",
        )
    return Check("system register", "ok", detail)


def _battery(robot: Robot) -> Check:
    volts = robot.battery_voltage()
    if volts < LOW_BATTERY_V:
        return Check(
            "battery",
            "warn",
            f"{volts:.2f} V (AD0)",
            f"charge or connect the battery (servos need more than {LOW_BATTERY_V:g} V)",
        )
    return Check("battery", "ok", f"{volts:.2f} V (AD0)")


def _servos(robot: Robot, client: Rcb4Client) -> Check:
    try:
        robot.wait_ready(timeout=3.0)
    except Rcb4Error:
        log.info("ROM program not in its main loop; reading the servo table as it is")
    table = robot.allocation_table()
    allocated = [k for k, a in enumerate(table) if a is not None and k < 35]
    servos = [s.ics for s in robot.discover_servos()]
    silent = []
    for k in servos:
        try:
            raw = client.move(Com(), Ics(SERVO.MEASURED, k), 2) or bytes(2)
        except NakError:
            silent.append(k)
            continue
        if not POSITION_MIN <= read_u16(raw, 0) <= POSITION_MAX:
            silent.append(k)
    detail = (
        f"{len(allocated)} ICS numbers allocated, {len(servos)} servo blocks, "
        f"{len(servos) - len(silent)} reporting a position"
    )
    if not servos:
        return Check(
            "servos",
            "fail",
            detail,
            "no servo in the allocation table: write a project (`rcb4hv project upload`)",
        )
    if silent:
        return Check(
            "servos",
            "warn",
            detail + f"; no position from ICS {silent}",
            "check those servos' cables, IDs and SIO ports against the project",
        )
    return Check("servos", "ok", detail + f" (ICS {servos})")


def run_doctor(
    port: str | None = None, *, host: Host | None = None, timeout: float = 0.5
) -> list[Check]:
    """Run every check against ``port`` (None: ``$RCB4HV_PORT`` or the Kondo adapter)."""
    host = host or Host()
    checks = list(_ports(host, port))
    url = _choose(host, port)
    if url is None:
        checks.append(Check("port", "fail", "no port to check", "give --port URL"))
        return checks
    checks.append(Check("port", "ok", url))
    checks.extend(_local(host, url))
    if any(c.status == "fail" for c in checks[1:]):
        checks.append(Check("board", "skip", "not reached: fix the failures above first"))
        return checks
    checks.extend(_board(url, timeout))
    return checks
