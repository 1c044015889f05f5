"""``rcb4hv doctor`` and ``rcb4hv udev-rule``: against the emulator (in process and on a real
pty), with a fake sysfs tree, a fake port list and a fake access check for what only a real
adapter on a real Linux box shows."""

from __future__ import annotations

import json
import os
from collections.abc import Iterator
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.emulator import Board, EmulatorConfig, PtyServer, RealClock, emulator_url
from rcb4hv.hardware import Host, PortInfo, all_passed, install_commands, run_doctor, udev_rule
from rcb4hv.protocol.memory import ADDR, SYS


def _run(*args: str) -> tuple[int, str, str]:
    res = CliRunner().invoke(cli, list(args), catch_exceptions=False)
    return res.exit_code, res.stdout, res.stderr


def _by_name(checks: list) -> dict:  # type: ignore[type-arg]
    return {c.name: c for c in checks}


@pytest.fixture
def pty_board() -> Iterator[str]:
    """A booted emulated board behind a real pty (a device path, like /dev/ttyUSB0)."""
    board = Board(clock=RealClock(speed=20.0))
    with PtyServer(board) as srv:
        yield str(srv.path)
    board.close()


def fake_host(tmp_path: Path, device: str, latency: int | None, **kw: object) -> Host:
    """A Host whose port list shows ``device`` as a Kondo adapter and whose sysfs tree holds
    ``latency`` as the device's FTDI latency timer."""
    sysfs = tmp_path / "sys"
    tty = Host.tty_name(device)
    node = sysfs / "bus" / "usb-serial" / "devices" / tty
    node.mkdir(parents=True)
    if latency is not None:
        (node / "latency_timer").write_text(f"{latency}\n")
    ports = [PortInfo(device, 0x165C, 0x0008, "A1B2C3"), PortInfo("/dev/ttyS0")]
    return Host(sysfs=sysfs, list_ports=lambda: ports, **kw)  # type: ignore[arg-type]


def test_doctor_passes_every_check_on_the_emulator() -> None:
    code, out, _ = _run("doctor", "--port", "rcb4emu://")
    assert code == 0, out
    lines = [ln for ln in out.splitlines() if ln.startswith("[")]
    assert len(lines) == 10
    assert all(ln.startswith(("[  ok]", "[skip]")) for ln in lines)
    assert "CB-4 V1.0" in out and "17 reporting a position" in out and "11.1" in out


def test_doctor_json() -> None:
    code, out, _ = _run("doctor", "--port", "rcb4emu://", "--json")
    data = json.loads(out)
    assert code == 0
    assert [d["name"] for d in data][-5:] == [
        "baud rate",
        "version",
        "system register",
        "battery",
        "servos",
    ]
    assert {d["status"] for d in data} <= {"ok", "skip"}


def test_device_path_detects_baud_and_reads_latency(tmp_path: Path, pty_board: str) -> None:
    host = fake_host(tmp_path, pty_board, latency=1)
    checks = run_doctor(pty_board, host=host)
    by = _by_name(checks)
    assert "1 Kondo adapter(s)" in by["serial ports"].detail
    assert f"{pty_board} [165C:0008] (Kondo adapter)" in by["serial ports"].detail
    assert by["permissions"].status == "ok"
    assert by["latency timer"].status == "ok" and "1 ms" in by["latency timer"].detail
    assert by["baud rate"].status == "ok" and "1,250,000 baud" in by["baud rate"].detail
    assert all_passed(checks), [c.line() for c in checks]


def test_slow_latency_timer_warns_with_the_command(tmp_path: Path, pty_board: str) -> None:
    host = fake_host(tmp_path, pty_board, latency=16)
    checks = run_doctor(pty_board, host=host)
    lat = _by_name(checks)["latency timer"]
    tty = Host.tty_name(pty_board)
    assert lat.status == "warn" and "16 ms" in lat.detail
    assert f"echo 1 | sudo tee /sys/bus/usb-serial/devices/{tty}/latency_timer" in lat.fix
    assert not all_passed(checks)
    assert _by_name(checks)["servos"].status == "ok"  # the board checks still ran


def test_symlinked_port_finds_the_tty_latency(tmp_path: Path, pty_board: str) -> None:
    link = tmp_path / "rcb4-A1B2C3"
    link.symlink_to(pty_board)
    host = fake_host(tmp_path, pty_board, latency=4)
    lat = _by_name(run_doctor(str(link), host=host))["latency timer"]
    assert lat.status == "warn" and Host.tty_name(pty_board) in lat.detail


def test_a_pty_is_named_as_pts_not_by_its_number(tmp_path: Path, pty_board: str) -> None:
    """``/dev/pts/N`` is ``pts/N`` (the skip said "0 has no FTDI latency timer")."""
    assert Host.tty_name("/dev/pts/7") == "pts/7"
    assert Host.tty_name("/dev/ttyUSB0") == "ttyUSB0"
    assert Host.tty_name(pty_board) == pty_board.removeprefix("/dev/")
    host = Host(sysfs=tmp_path / "sys", list_ports=lambda: [])
    lat = _by_name(run_doctor(pty_board, host=host))["latency timer"]
    assert lat.status == "skip"
    tty = pty_board.removeprefix("/dev/")
    assert lat.detail == f"{tty} has no FTDI latency timer (not an FTDI USB adapter)"


def test_permission_denied_names_the_group(tmp_path: Path, pty_board: str) -> None:
    host = fake_host(
        tmp_path, pty_board, latency=1, can_open=lambda p: False, group_of=lambda p: "uucp"
    )
    checks = run_doctor(pty_board, host=host)
    perm = _by_name(checks)["permissions"]
    assert perm.status == "fail" and "group uucp" in perm.detail
    assert "sudo usermod -aG uucp $USER" in perm.fix
    assert checks[-1].name == "board" and checks[-1].status == "skip"
    assert not all_passed(checks)


def test_no_adapter_and_no_port(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("RCB4HV_PORT", raising=False)
    host = Host(sysfs=tmp_path, list_ports=lambda: [PortInfo("/dev/ttyS0")])
    checks = run_doctor(None, host=host)
    assert [c.status for c in checks] == ["fail", "fail"]
    assert "165C" in checks[0].detail and "udev-rule" in checks[0].fix


def test_the_adapter_is_found_by_its_usb_ids(
    tmp_path: Path, pty_board: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("RCB4HV_PORT", raising=False)
    host = fake_host(tmp_path, pty_board, latency=1)
    checks = run_doctor(None, host=host)
    assert _by_name(checks)["port"].detail == pty_board
    assert all_passed(checks)


def test_silent_device_fails_the_baud_check(tmp_path: Path) -> None:
    master, slave = os.openpty()
    try:
        device = os.ttyname(slave)
        host = fake_host(tmp_path, device, latency=1)
        checks = run_doctor(device, host=host, timeout=0.1)
        baud = _by_name(checks)["baud rate"]
        assert baud.status == "fail" and "no ACK at 1,250,000, 625,000, 115,200" in baud.detail
        assert "switch the board on" in baud.fix
        assert "version" not in _by_name(checks)
    finally:
        os.close(master)
        os.close(slave)


def test_missing_device(tmp_path: Path) -> None:
    checks = run_doctor(str(tmp_path / "ttyUSB9"), host=Host(sysfs=tmp_path, list_ports=list))
    assert _by_name(checks)["permissions"].status == "fail"
    code, out, _ = _run("doctor", "--port", str(tmp_path / "ttyUSB9"))
    assert code == 1 and "does not exist" in out


def test_romerr_low_battery_and_no_servos() -> None:
    board = Board(EmulatorConfig(supply_voltage=6.0), clock=RealClock(speed=20.0))
    url = emulator_url(board)
    word = board.ram[0] | board.ram[1] << 8
    board.ram[ADDR.SYSTEM : ADDR.SYSTEM + 2] = ((word | SYS.ROM_ERROR) & ~SYS.ROM_RUN).to_bytes(
        2, "little"
    )
    board.ram[ADDR.ICS_ALLOC : ADDR.ICS_ALLOC + 72] = b"\xff" * 72
    by = _by_name(run_doctor(url, host=Host(list_ports=list)))
    assert by["system register"].status == "fail" and "ROMERR" in by["system register"].detail
    assert by["battery"].status == "warn" and "6.01 V" in by["battery"].detail
    assert by["servos"].status == "fail" and "0 servo blocks" in by["servos"].detail
    board.close()


def test_udev_rule() -> None:
    code, out, err = _run("udev-rule")
    assert code == 0
    rule = out
    for pid in ("0008", "0007"):
        assert f'ATTRS{{idProduct}}=="{pid}"' in rule
        assert f"echo 165c {pid} > /sys/bus/usb-serial/drivers/ftdi_sio/new_id" in rule
    assert rule.count('SYMLINK+="rcb4-$attr{serial}"') == 2
    assert rule.count('ATTR{latency_timer}="1"') == 2
    assert rule.count('GROUP="dialout", MODE="0660"') == 2
    body = [ln for ln in rule.splitlines() if ln and not ln.startswith("#")]
    assert all(ln.startswith('ACTION=="add"') for ln in body)
    assert "sudo tee /etc/udev/rules.d/99-rcb4hv.rules" in err
    assert "udevadm control --reload-rules" in err
    assert 'GROUP="uucp"' in udev_rule("uucp")
    assert install_commands("uucp")[0].startswith("rcb4hv udev-rule --group uucp |")
