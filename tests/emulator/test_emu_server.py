"""End to end over a real pty and TCP: golden vectors, reopen with parity E, CLI, no fd leaks."""

from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import termios
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
import serial

from rcb4hv import protocol as p
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, server
from rcb4hv.emulator.server import PtyServer, TcpServer
from tests.emulator.test_emu_vectors import VERSION_REPLY

REPO = Path(__file__).resolve().parents[2]

VECTORS = [
    ("03 FE 01", "04 FE 06 08"),
    ("04 FE 06 08", "04 FE 06 08"),
    ("04 FE 15 17", "04 FE 15 17"),
    ("03 FD 00", VERSION_REPLY),
    ("09 00 02 00 00 00 02 80 8D", "04 00 06 0A"),
    ("0A 00 20 00 00 00 00 00 02 2C", "05 00 02 80 87"),
    ("09 00 02 00 00 00 00 80 8B", "04 00 06 0A"),  # ROM_F off again (not a spec vector)
    ("0A 00 32 80 0B 00 03 0D 10 E7", "04 00 06 0A"),
    ("0B 00 23 00 00 00 80 0B 00 04 BD", None),
    ("07 0C 80 0B 00 00 9E", "04 0C 06 16"),
    ("03 0D 10", "04 0D 06 17"),
    ("09 06 02 62 04 00 05 00 7C", "05 06 05 00 10"),
    ("09 07 82 50 03 00 00 01 E6", None),
    ("08 01 02 3A 00 00 0F 54", "04 01 00 05"),
    ("0A 04 00 62 04 00 00 00 02 76", "05 04 FA FF 02"),
    ("0A 05 00 62 04 00 00 01 02 78", "05 05 FD 7F 86"),
    ("0A 05 00 62 04 00 00 FF 02 76", "05 05 FA FF 03"),
    ("07 0F 02 1E 4C 1D 9F", "04 0F 06 19"),
    ("07 0F 02 01 00 80 99", "04 0F 06 19"),
    ("0D 10 01 02 00 00 00 0A 4C 1D 40 1F F2", "04 10 06 1A"),
    ("0E 11 08 00 00 00 01 05 B0 1D 06 14 1E 32", "04 11 06 1B"),
    ("0B 12 01 02 00 00 00 02 64 3C C2", "04 12 06 1C"),
]


def fds() -> set[str]:
    return set(os.listdir("/proc/self/fd"))


@pytest.fixture
def fd_guard() -> Iterator[None]:
    before = fds()
    yield
    for _ in range(50):
        if fds() <= before:
            break
        time.sleep(0.02)
    assert fds() <= before, "leaked file descriptors"


def exchange(port: serial.Serial, req: str) -> bytes:
    port.reset_input_buffer()
    port.write(bytes.fromhex(req))
    head = port.read(1)
    assert head, f"no reply to {req}"
    return head + port.read(head[0] - 1)


def test_golden_vectors_byte_exact_over_a_pty(fd_guard: None) -> None:
    loop = bytes.fromhex("07 0B 00 00 00 00 12")  # JUMP 0: a program that changes nothing
    board = Board(EmulatorConfig(power_on_system_register=0), clock=RealClock(), rom_image=loop)
    with PtyServer(board) as srv:
        port = serial.Serial(srv.path, 1250000, parity="E", timeout=2)
        try:
            for req, rep in VECTORS:
                got = exchange(port, req)
                if rep is not None:
                    assert got == bytes.fromhex(rep), req
                else:
                    assert got[1] == bytes.fromhex(req)[1] and len(got) == got[0]
        finally:
            port.close()
    board.close()


@pytest.mark.parametrize("baud", [115200, 625000, 1250000])
def test_pty_reopen_many_times_with_even_parity(fd_guard: None, baud: int) -> None:
    board = Board(clock=RealClock())
    with PtyServer(board) as srv:
        for _ in range(15):
            port = serial.Serial(srv.path, baud, parity="E", timeout=2)
            try:
                assert exchange(port, "03 FE 01") == bytes.fromhex("04 FE 06 08")
            finally:
                port.close()
        # and once without writing anything in between
        serial.Serial(srv.path, baud, parity="E", timeout=1).close()
        time.sleep(0.3)
        serial.Serial(srv.path, baud, parity="E", timeout=1).close()
    board.close()


def wait_armed(path: str, within: float = 5.0) -> bool:
    """Whether the slave at ``path`` is armed (CSTOPB) within ``within`` seconds."""
    fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
    try:
        deadline = time.monotonic() + within
        while not termios.tcgetattr(fd)[2] & termios.CSTOPB:
            if time.monotonic() > deadline:
                return False
            time.sleep(0.001)
        return True
    finally:
        os.close(fd)


@pytest.mark.parametrize("baud", [115200, 1250000])
def test_pty_is_rearmed_as_soon_as_a_client_has_set_it_up(
    fd_guard: None, baud: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The kernel reports each client set-up (packet mode, EXTPROC) and the server re-arms at
    once, not only when the client sends (or every PTY_REARM, turned off here): a client that
    closes without sending (pyserial leaves the pty as it set it up) can reopen, and a second
    client can open while the first holds the pty in silence."""
    monkeypatch.setattr(server, "PTY_REARM", 3600.0)
    monkeypatch.setattr(PtyServer, "_max_wait", 1.0)
    board = Board(clock=RealClock())
    with PtyServer(board) as srv:
        for _ in range(3):
            serial.Serial(srv.path, baud, parity="E").close()
            assert wait_armed(srv.path)
        first = serial.Serial(srv.path, baud, parity="E", timeout=2)
        try:
            assert wait_armed(srv.path)
            serial.Serial(srv.path, baud, parity="E").close()
            assert wait_armed(srv.path)
            assert exchange(first, "03 FE 01") == bytes.fromhex("04 FE 06 08")
        finally:
            first.close()
    board.close()


def test_pty_sends_frame_timeout_nak_and_respects_latency(fd_guard: None) -> None:
    cfg = EmulatorConfig(power_on_system_register=0, min_reply_latency_s=0.02)
    board = Board(cfg, clock=RealClock())
    with PtyServer(board) as srv:
        port = serial.Serial(srv.path, 1250000, timeout=2)
        try:
            port.write(bytes.fromhex("09 00 02"))
            assert port.read(4) == bytes.fromhex("04 00 15 19")
            t0 = time.monotonic()
            port.write(bytes.fromhex("03 FE 01"))
            assert port.read(4) == bytes.fromhex("04 FE 06 08")
            assert time.monotonic() - t0 >= 0.019
        finally:
            port.close()
    board.close()


def test_tcp_serves_and_survives_reconnects(fd_guard: None) -> None:
    board = Board(clock=RealClock())
    with TcpServer(board, "127.0.0.1", 0) as srv:
        host, port = srv.address
        assert host == "127.0.0.1" and port > 0
        for _ in range(3):
            with socket.create_connection(srv.address, timeout=2) as s:
                s.sendall(bytes.fromhex("03 FD 00"))
                buf = b""
                while len(buf) < 35:
                    chunk = s.recv(64)
                    assert chunk
                    buf += chunk
                assert buf == bytes.fromhex(VERSION_REPLY)
            with socket.create_connection(srv.address, timeout=2) as s:
                s.sendall(b"\x09\x00\x02")  # partial frame, then hang up: dropped
    board.close()


def test_paced_replies_take_their_wire_time() -> None:
    cfg = EmulatorConfig(power_on_system_register=0, pace_replies=True, min_reply_latency_s=0)
    board = Board(cfg, clock=RealClock())  # COM baud code 0: 115200
    with TcpServer(board) as srv, socket.create_connection(srv.address, timeout=2) as s:
        t0 = time.monotonic()
        s.sendall(bytes.fromhex("0A 00 20 00 00 00 90 00 80 3A"))  # 128-byte read
        buf = b""
        while len(buf) < 131:
            buf += s.recv(256)
        assert time.monotonic() - t0 >= 131 * 11 / 115200 * 0.9
    board.close()


def test_paced_replies_charge_the_request_bytes_too() -> None:
    """A pty or socket delivers the request at once; pacing charges its wire time as well."""
    cfg = EmulatorConfig(power_on_system_register=0, pace_replies=True, min_reply_latency_s=0)
    board = Board(cfg, clock=RealClock())  # COM baud code 0: 115200
    write = p.Move(p.Ram(0x0300), p.Data(bytes(120))).encode()  # 127-byte request, 4-byte ACK
    with TcpServer(board) as srv, socket.create_connection(srv.address, timeout=2) as s:
        t0 = time.monotonic()
        s.sendall(write)
        buf = b""
        while len(buf) < 4:
            buf += s.recv(16)
        elapsed = time.monotonic() - t0
    board.close()
    assert buf == p.encode_reply(p.Ack(0x00))
    assert elapsed >= (len(write) + 4) * 11 / 115200 * 0.9


def run_cli(*args: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "emulate", *args],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=REPO,
    )


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_cli_pty_prints_path_and_exits_cleanly(sig: int, tmp_path: Path) -> None:
    rom = tmp_path / "board.rom"
    proc = run_cli("--pty", "--rom", str(rom), "--speed", "2")
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline().strip()
        kind, path = line.split(" ", 1)
        assert kind == "PTY" and os.path.exists(path)
        port = serial.Serial(path, 1250000, parity="E", timeout=2)
        try:
            assert exchange(port, "0A 00 32 80 0B 00 03 0D 10 E7") == bytes.fromhex("04 00 06 0A")
        finally:
            port.close()
    finally:
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err
    assert rom.read_bytes()[0x0B80:0x0B83] == bytes.fromhex("03 0D 10")


def test_cli_tcp(tmp_path: Path) -> None:
    proc = run_cli("--tcp", "127.0.0.1:0")
    try:
        assert proc.stdout is not None
        kind, addr = proc.stdout.readline().split()
        host, port = addr.rsplit(":", 1)
        assert kind == "TCP" and host == "127.0.0.1"
        with socket.create_connection((host, int(port)), timeout=2) as s:
            s.sendall(bytes.fromhex("03 FE 01"))
            assert s.recv(4) == bytes.fromhex("04 FE 06 08")
    finally:
        proc.terminate()
        proc.communicate(timeout=10)
    assert proc.returncode == 0


def test_cli_usage_errors() -> None:
    proc = run_cli()
    _, err = proc.communicate(timeout=10)
    assert proc.returncode == 2 and "--pty" in err
