"""Regression tests for the bugs the reliability suite found (each was an xfail reproducer
until it was fixed)."""

from __future__ import annotations

import socket
import time

from rcb4hv import protocol as p
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, VirtualClock
from rcb4hv.emulator.server import TcpServer
from rcb4hv.transport import SerialTransport

# MOVE literal 10h -> RAM 0004 (the PC's top byte): PC becomes 10xxxxh, past the 256 KB ROM.
PC_PAST_ROM = p.encode_command(p.Move(p.Ram(0x0004), p.Data(b"\x10")))


def test_pc_written_past_rom_does_not_escape_from_feed() -> None:
    """Fixed: a PC past 3FFFFh made Board._fetch raise IndexError; now it is a fetch error
    (ROMERR, the program stops) like erased ROM."""
    board = Board(clock=VirtualClock())
    board.run_for(1.0)
    assert board.feed(PC_PAST_ROM) == bytes.fromhex("04 00 06 0A")
    board.run_for(0.1)
    assert board.feed(bytes.fromhex("03 FE 01")) == bytes.fromhex("04 FE 06 08")
    sysreg = p.SystemRegister.from_word(board.system_register)
    assert sysreg.rom_error and not sysreg.rom_run


def test_pc_written_past_rom_does_not_kill_the_server() -> None:
    """Fixed: the same command from a TCP client killed the server thread."""
    board = Board(EmulatorConfig(), clock=RealClock(speed=10.0))
    try:
        with TcpServer(board, "127.0.0.1", 0) as srv:
            with socket.create_connection(srv.address, timeout=2.0) as s:
                s.sendall(PC_PAST_ROM)
                assert s.recv(4) == bytes.fromhex("04 00 06 0A")
                time.sleep(0.1)
                s.sendall(bytes.fromhex("03 FE 01"))
                s.settimeout(1.0)
                try:
                    reply = s.recv(4)
                except TimeoutError:
                    reply = b""
            assert srv.error is None, f"server thread died: {srv.error!r}"
            assert reply == bytes.fromhex("04 FE 06 08")
    finally:
        board.close()


def test_socket_transport_sets_tcp_nodelay() -> None:
    """Fixed: pyserial's socket:// left Nagle on, so a frame written in two parts could arrive
    >20 ms apart and be NAKed by the frame timeout."""
    board = Board(EmulatorConfig(), clock=RealClock(speed=10.0))
    try:
        with TcpServer(board, "127.0.0.1", 0) as srv:
            host, port = srv.address
            transport = SerialTransport.open(f"socket://{host}:{port}")
            try:
                sock = transport.port._socket  # type: ignore[attr-defined]
                assert sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) != 0
            finally:
                transport.close()
    finally:
        board.close()
