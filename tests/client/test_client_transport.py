"""Transport edge cases, port auto-detection, plan_reads, the CLI, hardware tests."""

from __future__ import annotations

import json
import re
import time
from pathlib import Path
from types import SimpleNamespace

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import emulator as emu
from rcb4hv.cli.main import cli
from rcb4hv.client import Rcb4Client, Robot, plan_reads
from rcb4hv.emulator import emulator_url
from rcb4hv.errors import Rcb4TimeoutError, TransportError
from rcb4hv.transport import SerialTransport, find_kondo_ports, resolve_port
from rcb4hv.transport import serial_port as sp
from tests.client.conftest import make_board

# ---------------------------------------------------------------------------- transport


def test_open_errors_are_transport_errors() -> None:
    with pytest.raises(TransportError, match="cannot open") as info:
        SerialTransport.open("/dev/definitely-not-a-port")
    assert info.value.__cause__ is not None
    with pytest.raises(TransportError):
        SerialTransport.open("rcb4emu://?speed=-1")
    with pytest.raises(TransportError):
        SerialTransport.open("rcb4emu://?board=999999")


def test_reads_are_bounded_on_a_silent_link() -> None:
    t = SerialTransport.open("loop://")  # nothing ever answers an ACK check on a loopback...
    with Rcb4Client(t, timeout=0.1) as c:
        t0 = time.monotonic()
        with pytest.raises(Rcb4TimeoutError):
            c.get_version_info()  # ...and the echo of 03 FD 00 is no version reply
        # never early; the upper margin is the timeout plus a second of scheduling delay (a
        # loaded CI runner: load 4 on two cores), still far short of an unbounded read
        assert 0.09 < time.monotonic() - t0 < 0.1 + 1.0


def test_closed_port_raises_transport_error() -> None:
    board = make_board()
    url = emulator_url(board)
    c = Rcb4Client.open(url, timeout=0.1)
    c.close()
    with pytest.raises(TransportError):
        c.acknowledge_check()
    c.reconnect()
    c.acknowledge_check()
    c.close()


def test_kondo_autodetect(monkeypatch: pytest.MonkeyPatch) -> None:
    ports = [
        SimpleNamespace(device="/dev/ttyUSB1", vid=0x165C, pid=0x0008),
        SimpleNamespace(device="/dev/ttyUSB0", vid=0x0403, pid=0x6001),
        SimpleNamespace(device="/dev/ttyUSB2", vid=0x165C, pid=0x0007),
    ]
    monkeypatch.setattr(sp.serial.tools.list_ports, "comports", lambda: ports)
    monkeypatch.delenv("RCB4HV_PORT", raising=False)
    assert find_kondo_ports() == ["/dev/ttyUSB1", "/dev/ttyUSB2"]
    assert resolve_port(None) == "/dev/ttyUSB1"
    assert resolve_port("socket://x:1") == "socket://x:1"
    monkeypatch.setenv("RCB4HV_PORT", "rcb4emu://")
    assert resolve_port(None) == "rcb4emu://"
    monkeypatch.delenv("RCB4HV_PORT")
    monkeypatch.setattr(sp.serial.tools.list_ports, "comports", lambda: [])
    with pytest.raises(TransportError, match="no Kondo USB adapter"):
        resolve_port(None)


def test_baud_detection_on_emulator_and_pty() -> None:
    board = make_board()
    with emu.PtyServer(board) as srv:
        c = Rcb4Client.open(str(srv.path), baudrate=None, timeout=0.2)
        try:
            assert c.transport.baudrate == 1250000  # type: ignore[attr-defined]
        finally:
            c.close()
    board.close()


# ---------------------------------------------------------------------------- plan_reads


@settings(max_examples=200)
@given(
    st.lists(st.tuples(st.integers(0x90, 0x400), st.integers(1, 20)), min_size=1, max_size=30),
    st.integers(8, 128),
)
def test_plan_reads_covers_everything_within_the_limit(
    spans: list[tuple[int, int]], limit: int
) -> None:
    reads = plan_reads(spans, limit)
    assert all(1 <= n <= limit for _, n in reads)
    for a, n in spans:
        for byte in range(a, a + n):
            assert any(r <= byte < r + m for r, m in reads)
    # optimal: a greedy sweep over the needed bytes gives the same count
    needed = sorted({b for a, n in spans for b in range(a, a + n)})
    count, end = 0, -1
    for b in needed:
        if b >= end:
            count, end = count + 1, b + limit
    assert len(reads) == count


def test_plan_reads_servo_positions() -> None:
    blocks = [0x90 + 20 * k for k in range(35)]
    assert len(plan_reads((b + 4, 2) for b in blocks)) == 5  # 7 servos per 128-byte read
    assert len(plan_reads((b, 20) for b in blocks)) == 6  # 700 bytes


# ---------------------------------------------------------------------------- CLI


@pytest.fixture
def cli_url() -> object:
    board = make_board()
    url = emulator_url(board)
    with Robot.open(url) as r:
        r.wait_ready()
    yield url
    board.close()


def _run(*args: str) -> tuple[int, str, str]:
    res = CliRunner().invoke(cli, list(args), catch_exceptions=False)
    return res.exit_code, res.stdout, res.stderr


def test_cli_ping_version_info(cli_url: str) -> None:
    code, out, _ = _run("ping", "--port", cli_url, "-n", "3")
    assert code == 0 and "3 ACKs" in out
    code, out, _ = _run("version", "--port", cli_url, "--json")
    assert json.loads(out)["text"].startswith("CB-4")
    code, out, _ = _run("info", "--port", cli_url, "--json")
    data = json.loads(out)
    assert data["servos"] and data["system_register"]["rom_run"] in (True, False)
    code, out, _ = _run("info", "--port", cli_url)
    assert code == 0 and "call depth" in out and "ICS" in out


def test_cli_ram_rom(cli_url: str, tmp_path: Path) -> None:
    assert _run("ram", "write", "--port", cli_url, "0x462", "01 02 03")[0] == 0
    code, out, _ = _run("ram", "read", "--port", cli_url, "462h", "3", "--json")
    assert json.loads(out)["hex"] == "010203"
    img = tmp_path / "img.bin"
    img.write_bytes(bytes(range(100)))
    code, out, _ = _run("rom", "write", "--port", cli_url, "0x3F000", str(img), "--no-progress")
    assert code == 0 and "verified 100 bytes" in out
    out_file = tmp_path / "dump.bin"
    code, out, _ = _run(
        "rom",
        "dump",
        "--port",
        cli_url,
        "-o",
        str(out_file),
        "--start",
        "0x3F000",
        "--size",
        "300",
        "--no-progress",
    )
    assert code == 0 and out_file.read_bytes()[:100] == bytes(range(100))
    code, out, _ = _run("rom", "read", "--port", cli_url, "0x3F000", "16")
    assert out.startswith("03F000  00 01 02")


def test_cli_servo_motion_button(cli_url: str) -> None:
    code, out, _ = _run("servo", "list", "--port", cli_url, "--json")
    servos = json.loads(out)
    k = servos[1]["ics"]
    code, out, _ = _run("servo", "move", "--port", cli_url, "--deg", f"{k}=15", "-d", "0.3")
    assert code == 0, out
    code, out, _ = _run("servo", "list", "--port", cli_url, "--json")
    assert next(s for s in json.loads(out) if s["ics"] == k)["output"] == round(
        7500 + 15 * 8000 / 270
    )
    assert _run("servo", "free", "--port", cli_url, str(k))[0] == 0
    # the table names the free marker (it printed 8000 among the decimal positions)
    code, out, _ = _run("servo", "list", "--port", cli_url)
    row = next(line.split() for line in out.splitlines() if line.split()[:1] == [str(k)])
    assert row[-2:] == ["free", "free"], out
    assert _run("servo", "hold", "--port", cli_url)[0] == 0
    code, out, _ = _run("motion", "play", "--port", cli_url, "1", "--wait")
    assert code == 0 and "ended" in out
    assert _run("motion", "wait", "--port", cli_url)[0] == 0
    assert _run("motion", "stop", "--port", cli_url)[0] == 0
    assert _run("motion", "status", "--port", cli_url)[0] == 0
    code, out, _ = _run("button", "press", "--port", cli_url, "up", "s1", "-d", "0.01")
    assert code == 0 and "UP" in out


def test_cli_ram_write_names_bad_hex(cli_url: str) -> None:
    code, _, err = _run("ram", "write", "--port", cli_url, "0x0462", "GG")
    assert code == 2 and "Invalid value for DATA: not hex bytes" in err


def test_cli_errors_are_one_line(cli_url: str) -> None:
    code, _, err = _run("servo", "move", "--port", cli_url, "0=20000")
    assert code == 1 and err.startswith("error: ") and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    code, _, err = _run("ping", "--port", "fault://drop_reply=1.0@" + cli_url, "--timeout", "0.05")
    assert code == 1 and "Rcb4TimeoutError" in err
    code, _, err = _run("ram", "read", "--port", cli_url, "0x48F", "2")
    assert code == 1 and "error:" in err
    code, _, err = _run("button", "press", "--port", cli_url, "jump")
    assert code == 2 and "unknown button" in err


def test_cli_demo_writes_a_plot(tmp_path: Path) -> None:
    out = tmp_path / "angles.png"
    code, stdout, _ = _run("demo", "--output", str(out), "--speed", "4")
    assert code == 0, stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "servos found" in stdout and str(out.resolve()) in stdout
    # "in 0.8 s ... done after": at --speed 4 the emulator's clock runs 4x the wall's, and the
    # move's time is told on the board's clock (it printed 0.21 s for the 0.8 s move)
    done = re.search(r"done after ([0-9.]+) s on the board's clock \(([0-9.]+) s at x4\)", stdout)
    assert done is not None, stdout
    assert float(done[1]) >= 0.75 and float(done[1]) == pytest.approx(4 * float(done[2]), abs=0.03)


# ---------------------------------------------------------------------------- hardware


@pytest.mark.hardware
def test_hardware_link(hardware_port: str) -> None:
    with Robot.open(hardware_port, baudrate=None) as robot:
        robot.client.acknowledge_check()
        assert robot.version().text
        reg = robot.system_register()
        assert reg.frame_period_ms in (10, 15, 20, 25)
        robot.discover_servos()
        robot.positions()
        assert 0 < robot.battery_voltage() < 25


@pytest.mark.hardware
def test_hardware_ram_round_trip(hardware_port: str) -> None:
    with Robot.open(hardware_port, baudrate=None) as robot:
        old = robot.read_ram(0x048A, 4)  # HeartToHeart4 temporaries
        try:
            robot.write_ram(0x048A, b"\x12\x34\x56\x78")
            assert robot.read_ram(0x048A, 4) == b"\x12\x34\x56\x78"
        finally:
            robot.write_ram(0x048A, old)


def test_cli_rom_dump_with_default_range_reads_the_whole_image(
    cli_url: str, tmp_path: Path
) -> None:
    out_file = tmp_path / "full.bin"
    code, _out, err = _run("rom", "dump", "--port", cli_url, "-o", str(out_file), "--no-progress")
    assert code == 0, err
    image = out_file.read_bytes()
    assert len(image) == 0x40000
    assert image[0x044B:0x044D] == b"\x09\x00"  # the main loop's system-register write


def test_cli_servo_list_on_a_fresh_in_process_board_waits_for_start_up() -> None:
    """Every CLI call makes a new rcb4emu:// board; its servo table exists after start-up."""
    code, out, err = _run("servo", "list", "--port", "rcb4emu://?speed=20", "--json")
    assert code == 0, err
    servos = json.loads(out)
    assert [s["ics"] for s in servos] == [
        0,
        2,
        3,
        4,
        5,
        6,
        7,
        10,
        11,
        12,
        13,
        14,
        15,
        16,
        17,
        18,
        19,
    ]


# ---------------------------------------------------------------------------- raw pty path


def test_pty_reply_in_pieces_after_stray_bytes() -> None:
    """POSIX ports are read straight from the fd (one read of the whole reply when it is
    there); a reply split across reads, after stray bytes, still comes out whole."""
    import os
    import pty
    import threading
    import tty

    master, slave = pty.openpty()
    tty.setraw(slave)
    path = os.ttyname(slave)
    reply = bytes.fromhex("0C 00 01 02 03 04 05 06 07 08 09") + bytes((0x0C + 45,))
    assert sum(reply[:-1]) & 0xFF == reply[-1]

    def board() -> None:
        os.read(master, 64)  # the request
        os.write(master, b"\x55\x06" + reply[:5])
        time.sleep(0.05)
        os.write(master, reply[5:])

    t = threading.Thread(target=board)
    c = Rcb4Client.open(path, timeout=1.0)
    try:
        assert c.transport._raw_fd is not None  # type: ignore[attr-defined]
        t.start()
        assert c.read_ram(0x100, 9) == bytes(range(1, 10))
    finally:
        t.join()
        c.close()
        os.close(master)
        os.close(slave)


@pytest.mark.parametrize(
    ("url", "said"),
    [
        ("socket://127.0.0.1", "needs a port"),
        ("socket://127.0.0.1:port", "socket://HOST:PORT"),
        ("nonsense://x", "a port is a device path"),
    ],
)
def test_a_url_that_cannot_open_says_what_a_port_is(url: str, said: str) -> None:
    """A typed TransportError naming the URL, not pyserial's TypeError or ValueError."""
    from rcb4hv.errors import TransportError
    from rcb4hv.transport import open_transport

    with pytest.raises(TransportError, match=said):
        open_transport(url)
