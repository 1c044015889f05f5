"""Links opened, closed and reopened on real ptys and TCP sockets, on both faces: a pty
reopened at once, one rule for socket URLs, a close that has closed, TCP_NODELAY and the fault
injector kept across a reopen, and what a link that failed says."""

from __future__ import annotations

import asyncio
import os
import pty
import socket
import threading
import time
import tty
from collections.abc import Iterator

import pytest
import serial

from rcb4hv import emulator as emu
from rcb4hv.aio import AsyncRcb4Client
from rcb4hv.aio import transport as aio_transport
from rcb4hv.client import Rcb4Client
from rcb4hv.emulator import emulator_url
from rcb4hv.errors import Rcb4TimeoutError, TransportError
from rcb4hv.transport import Fault, SerialTransport
from tests.client.conftest import make_board


def fds() -> set[str]:
    return set(os.listdir("/proc/self/fd"))


@pytest.fixture
def pty_path() -> Iterator[str]:
    """The path of an emulator's pty (a server thread in this process)."""
    board = make_board()
    try:
        with emu.PtyServer(board) as srv:
            yield str(srv.path)
    finally:
        board.close()


@pytest.fixture
def tcp_url() -> Iterator[str]:
    board = make_board()
    try:
        with emu.TcpServer(board, "127.0.0.1", 0) as srv:
            yield "socket://{}:{}".format(*srv.address[:2])
    finally:
        board.close()


# ------------------------------------------------------------------------- a pty reopened


def test_a_pty_opened_and_closed_in_silence_reopens_at_once(pty_path: str) -> None:
    """A pty cannot store even parity, and a set-up that changes nothing it holds is refused
    (EINVAL): an open, a close with nothing sent, and an open right after used to fail."""
    before = fds()
    for _ in range(10):
        Rcb4Client.open(pty_path, timeout=2.0).close()
        with Rcb4Client.open(pty_path, timeout=2.0) as client:
            client.acknowledge_check()

    async def main() -> None:
        for _ in range(10):
            await (await AsyncRcb4Client.open(pty_path, timeout=2.0)).close()
            async with await AsyncRcb4Client.open(pty_path, timeout=2.0) as client:
                await client.acknowledge_check()

    asyncio.run(main())
    assert fds() <= before


def test_a_pty_refusing_its_set_up_says_what_to_do() -> None:
    """A pty nobody re-arms (another program's) refuses a reopen with the settings it holds;
    the error says why and what to do."""
    master, slave = pty.openpty()
    tty.setraw(slave)
    path = os.ttyname(slave)
    try:
        serial.Serial(path, 115200, parity="E").close()  # pyserial leaves it as set up
        with pytest.raises(TransportError, match="cannot open") as info:
            SerialTransport.open(path, 115200)
        said = str(info.value)
        assert "a pty cannot store even parity" in said and "open it again" in said
        assert "rcb4hv emulate --tcp" in said and info.value.__cause__ is not None
    finally:
        os.close(master)
        os.close(slave)


# ------------------------------------------------------------------------- socket URLs


@pytest.mark.parametrize(
    ("url", "said"),
    [
        ("socket://127.0.0.1", "needs a port"),
        ("socket://:4000", "needs a host"),
        ("socket://localhost:99999", "out of range"),
        ("socket://127.0.0.1:port", "socket://HOST:PORT"),
    ],
)
def test_a_bad_socket_url_is_the_same_transport_error_on_both_faces(url: str, said: str) -> None:
    with pytest.raises(TransportError, match=said) as blocking:
        Rcb4Client.open(url)
    with pytest.raises(TransportError, match=said) as in_asyncio:
        asyncio.run(AsyncRcb4Client.open(url))
    assert str(in_asyncio.value) == str(blocking.value)


# ------------------------------------------------------------------------- close, reopen


def test_an_asyncio_close_returns_with_the_pty_closed(pty_path: str) -> None:
    """The pty's fd and pyserial's pipes are closed when close() returns, not a moment after."""

    async def main() -> None:
        before = fds()
        client = await AsyncRcb4Client.open(pty_path, timeout=2.0)
        await client.acknowledge_check()
        assert fds() > before
        await client.close()
        assert fds() <= before
        await client.close()  # again: nothing to wait for
        await client.reconnect()
        await client.acknowledge_check()
        await client.close()
        assert fds() <= before

    asyncio.run(main())


def test_an_asyncio_close_drops_bytes_a_silent_peer_never_takes(
    monkeypatch: pytest.MonkeyPatch, caplog: pytest.LogCaptureFixture
) -> None:
    """Bytes still queued get CLOSE_TIMEOUT to leave; then the close drops them, and returns
    with the socket closed all the same."""
    monkeypatch.setattr(aio_transport, "CLOSE_TIMEOUT", 0.2)
    server = socket.create_server(("127.0.0.1", 0))
    url = f"socket://127.0.0.1:{server.getsockname()[1]}"

    async def main() -> None:
        before = fds()
        link = await aio_transport.open_async_transport(url)
        peer, _ = server.accept()  # it never reads: the queue cannot drain
        before.add(str(peer.fileno()))
        try:
            link.write(bytes(32 << 20))
            t0 = time.monotonic()
            await link.close()
            assert time.monotonic() - t0 < 0.2 + 5.0
            assert fds() <= before
        finally:
            peer.close()

    try:
        asyncio.run(main())
    finally:
        server.close()
    assert any("not sent at close" in r.getMessage() for r in caplog.records)


def test_a_reopened_socket_keeps_nagle_off(tcp_url: str) -> None:
    """A frame written in two parts must leave at once after a reconnect too (reopen used to
    skip what open did: TCP_NODELAY was off again)."""
    client = Rcb4Client.open(tcp_url, timeout=2.0)
    try:
        for _ in range(2):
            sock = client.transport.port._socket  # type: ignore[attr-defined]
            assert sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) != 0
            client.acknowledge_check()
            client.close()
            client.reconnect()
    finally:
        client.close()


def test_a_reconnected_fault_link_keeps_its_injector() -> None:
    board = make_board()
    try:
        url = "fault://seed=1@" + emulator_url(board)
        client = Rcb4Client.open(url, timeout=0.2)
        faults = client.transport.port.faults  # type: ignore[attr-defined]
        faults.inject(None, Fault.DROP_REPLY)
        client.acknowledge_check()
        client.close()
        client.reconnect()
        assert client.transport.port.faults is faults  # type: ignore[attr-defined]
        with pytest.raises(Rcb4TimeoutError):  # the fault queued before the reconnect
            client.acknowledge_check()
        assert faults.history == [(2, Fault.DROP_REPLY)]
        client.acknowledge_check()
        client.close()

        async def main() -> None:
            aclient = await AsyncRcb4Client.open(url, timeout=0.2)
            port = aclient.transport._port  # type: ignore[attr-defined]
            injector = port.faults
            injector.inject(Fault.DROP_REPLY)
            await aclient.close()
            await aclient.reconnect()
            assert port.faults is injector
            with pytest.raises(Rcb4TimeoutError):
                await aclient.acknowledge_check()
            await aclient.close()

        asyncio.run(main())
    finally:
        board.close()


# ------------------------------------------------------------------------- what a failure says


def test_a_write_to_a_dead_tcp_peer_says_write_failed_once() -> None:
    server = socket.create_server(("127.0.0.1", 0))
    accepted: list[socket.socket] = []
    thread = threading.Thread(target=lambda: accepted.append(server.accept()[0]))
    thread.start()
    transport = SerialTransport.open(f"socket://127.0.0.1:{server.getsockname()[1]}")
    try:
        thread.join()
        accepted[0].close()  # the peer is gone: a write or two later, EPIPE
        with pytest.raises(TransportError) as info:
            for _ in range(100):
                transport.write(b"\x03\xfe\x01")
                time.sleep(0.01)
        assert str(info.value).count("write failed") == 1, info.value
    finally:
        transport.close()
        server.close()


def test_a_failed_reopen_says_the_port_is_not_open() -> None:
    server = socket.create_server(("127.0.0.1", 0))
    url = f"socket://127.0.0.1:{server.getsockname()[1]}"
    client = Rcb4Client.open(url, timeout=0.2)
    try:
        server.close()  # the board is gone, and does not come back
        with pytest.raises(TransportError, match="cannot reopen"):
            client.reconnect()
        with pytest.raises(TransportError, match="the port is not open") as info:
            client.acknowledge_check()
        assert "Attempting to use" not in str(info.value)
    finally:
        client.close()


def test_a_pty_whose_emulator_stopped_says_the_link_is_gone() -> None:
    board = make_board()
    srv = emu.PtyServer(board).__enter__()
    try:
        client = Rcb4Client.open(str(srv.path), timeout=0.3)
        try:
            client.acknowledge_check()
            srv.stop()
            with pytest.raises(TransportError, match="the link is gone") as info:
                client.acknowledge_check()
            assert "emulator serving the port stopped" in str(info.value)
        finally:
            client.close()
    finally:
        srv.stop()
        board.close()
