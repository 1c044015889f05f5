"""End to end: ``rcb4hv emulate-ics`` in a subprocess, driven over a pty and over TCP by our
own client (``rcb4hv ics``, :class:`rcb4hv.ics.IcsBus`) and by the peer rcb4 0.1.6's
``ICSServoController`` (its ``ics.py``, unchanged)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
import serial
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.ics import IcsBus

REPO = Path(__file__).resolve().parents[2]


def start(*args: str) -> tuple[subprocess.Popen[str], str]:
    proc = subprocess.Popen(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "emulate-ics", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=REPO,
    )
    assert proc.stdout is not None
    return proc, proc.stdout.readline().strip()


def stop(proc: subprocess.Popen[str]) -> None:
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err


@pytest.fixture
def pty_bus() -> Iterator[str]:
    proc, line = start("--pty", "--ids", "0,3")
    kind, path = line.split(" ", 1)
    assert kind == "PTY" and os.path.exists(path)
    yield path
    stop(proc)


def test_our_client_over_the_pty(pty_bus: str) -> None:
    with IcsBus.open(pty_bus, 115200) as bus:
        assert bus.scan(range(5)) == [0, 3]
        servo = bus.servo(3)
        assert servo.set_params(stretch=44) == {"stretch": (90, 44)}
        assert servo.stretch() == 44
        assert servo.move(7600) == 7500
        assert servo.eeprom().servo_id == 3


def test_the_cli_over_the_pty(pty_bus: str, tmp_path: Path) -> None:
    runner = CliRunner()

    def ics(*args: str) -> str:
        result = runner.invoke(cli, ["ics", "--port", pty_bus, "--json", *args])
        assert result.exit_code == 0, result.output
        return result.output

    assert json.loads(ics("scan", "--ids", "0-4")) == {"ids": [0, 3]}
    assert json.loads(ics("set", "--id", "0", "speed=100", "reverse=1"))["changed"] == {
        "speed": [127, 100],
        "flags": [6, 7],
        "reverse": [0, 1],
    }
    got = json.loads(ics("get", "--id", "0", "speed", "reverse", "limits"))
    assert (got["speed"], got["reverse"], got["min_pulse"], got["max_pulse"]) == (
        100,
        1,
        3500,
        11500,
    )
    backup = tmp_path / "servo0.json"
    ics("eeprom", "dump", "--id", "0", str(backup))
    assert json.loads(backup.read_text())["fields"]["speed"] == 100
    assert json.loads(ics("eeprom", "restore", "--id", "3", str(backup)))["changed"]["speed"] == [
        127,
        100,
    ]
    assert json.loads(ics("position", "--id", "3", "--move", "8000")) == {"id": 3, "position": 7500}
    # two servos on the bus: an ID read collides (E0h & E3h = E0h reads as 0, which is a
    # servo here): the ID read probes the IDs another servo could have, and says so
    result = runner.invoke(cli, ["ics", "--port", pty_bus, "id"])
    assert result.exit_code == 1
    assert "servos 0, 3 answer" in result.stderr


def test_cli_id_set_with_one_servo() -> None:
    proc, line = start("--pty")
    try:
        path = line.split(" ", 1)[1]
        result = CliRunner().invoke(cli, ["ics", "--port", path, "id", "--set", "7"], input="y\n")
        assert result.exit_code == 0, result.output
        assert "Only ONE servo" in result.output and "servo ID 0 -> 7" in result.output
    finally:
        stop(proc)


def test_usage_errors() -> None:
    proc = subprocess.run(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "emulate-ics"],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=30,
    )
    assert proc.returncode == 2 and "--pty" in proc.stderr


def rcb4_flow(ctrl: object) -> None:
    """What the issue names: read and set ID, stretch, speed and position; plus the EEPROM."""
    c = ctrl
    assert c.get_servo_id() == 0  # type: ignore[attr-defined]
    assert c.set_stretch(40) == 40 and c.get_stretch() == 40  # type: ignore[attr-defined]
    assert c.set_speed(100) == 100 and c.get_speed() == 100  # type: ignore[attr-defined]
    assert c.read_angle() == 7500  # type: ignore[attr-defined]
    assert c.set_angle(7600) == 7500  # type: ignore[attr-defined]
    params, parsed = c.read_param()  # type: ignore[attr-defined]
    assert len(params) == 64 and parsed["servo-id"] == 0 and parsed["stretch-gain"] == 180
    assert c.set_servo_id(5) == 5 and c.get_servo_id() == 5  # type: ignore[attr-defined]


def test_rcb4_ics_controller_over_tcp() -> None:
    from rcb4.ics import ICSServoController

    proc, line = start("--tcp", "127.0.0.1:0")
    try:
        kind, addr = line.split()
        assert kind == "TCP"
        ctrl = ICSServoController(baudrate=115200)
        ctrl.ics = serial.serial_for_url(f"socket://{addr}", baudrate=115200, timeout=ctrl.timeout)
        try:
            rcb4_flow(ctrl)
            ctrl.set_param(ctrl.read_param()[0], 5)  # an EEPROM write: ~0.35 s
        finally:
            ctrl.close_connection()
    finally:
        stop(proc)


@pytest.mark.parametrize("baud", [115200, 1250000])
def test_rcb4_ics_controller_over_a_pty_with_even_parity(baud: int) -> None:
    from rcb4.ics import ICSServoController

    proc, line = start("--pty", "--baud", str(baud))
    try:
        path = line.split(" ", 1)[1]
        ctrl = ICSServoController(baudrate=baud)
        # strict: any EINVAL from a tcsetattr (the open, or a timeout change) fails the test
        ctrl.ics = serial.Serial(path, baud, timeout=ctrl.timeout, parity=serial.PARITY_EVEN)
        try:
            assert ctrl.get_servo_id() == 0
            assert ctrl.set_stretch(40, 0) == 40
            assert ctrl.get_stretch(0) == 40
            assert ctrl.set_speed(100, 0) == 100
            assert ctrl.get_speed(0) == 100
            assert ctrl.read_angle(0) == 7500
            assert ctrl.set_angle(7600, 0) == 7500
            assert ctrl.set_servo_id(5) == 5
            assert ctrl.get_servo_id() == 5
        finally:
            ctrl.close_connection()
    finally:
        stop(proc)
