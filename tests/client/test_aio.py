"""rcb4hv.aio natively: the async robot's calls over each link, concurrent tasks, deadlines,
cancellation and link failures. (The whole shared client suite also runs on AsyncRobot and
AsyncRcb4Client themselves through tests/client/aio_bridge.py: the ``aio-*`` kinds of the
``rig``; tests/client/test_faces.py compares the two faces frame by frame.)"""

from __future__ import annotations

import asyncio
import logging
import math
import socket
import threading
import time
from collections.abc import Iterator
from contextlib import ExitStack

import pytest

from rcb4hv.aio import AsyncRcb4Client, AsyncRobot, PolledTransport, StreamTransport
from rcb4hv.client import Rcb4Client
from rcb4hv.emulator import emulator_url
from rcb4hv.errors import ChecksumError, NakError, Rcb4TimeoutError, TransportError
from rcb4hv.protocol import Button, Com, Data, Ics, Ram
from tests.client.conftest import make_board
from tests.client.test_client_faults import SLACK

LINKS = ("inproc", "pty", "tcp")


@pytest.fixture(params=LINKS)
def url(request: pytest.FixtureRequest) -> Iterator[str]:
    """A URL serving a fresh emulated board (time moved by the requests) over one link."""
    import rcb4hv.emulator as emu

    board = make_board()
    with ExitStack() as stack:
        stack.callback(board.close)
        if request.param == "inproc":
            yield emulator_url(board)
        elif request.param == "pty":
            yield str(stack.enter_context(emu.PtyServer(board)).path)
        else:
            srv = stack.enter_context(emu.TcpServer(board, "127.0.0.1", 0))
            yield f"socket://{srv.address[0]}:{srv.address[1]}"


def test_async_robot_common_calls(url: str) -> None:
    async def main() -> None:
        async with await AsyncRobot.open(url) as robot:
            kind = type(robot.client.transport)
            assert kind is (PolledTransport if url.startswith("rcb4emu") else StreamTransport)
            await robot.wait_ready(timeout=5.0)
            assert (await robot.version()).text.startswith("CB-4")
            servos = await robot.discover_servos()
            assert len(servos) == 17
            ids = await robot.servo_ids()
            pos = await robot.positions()
            assert set(pos) == set(ids)
            k = ids[1]
            await robot.hold()
            await robot.move_angles({k: 15.0}, duration=1.0, wait=True)
            assert (await robot.angles([k], kind="output"))[k] == pytest.approx(15.0, abs=0.05)
            await robot.free([k])
            assert math.isnan((await robot.angles([k], kind="output"))[k])
            with pytest.raises(ValueError):
                await robot.move({k: 20000})
            await robot.play_motion(1)
            assert (await robot.motion_status()).motion == 1
            await robot.wait_motion(timeout=5.0)
            assert (await robot.motion_status()).motion is None
            await robot.set_buttons(Button.UP)
            assert await robot.buttons() == Button.UP
            await robot.press_button(Button.NONE, 0.0)
            assert 0 < await robot.battery_voltage() < 25
            await robot.set_variable(3, -7)
            assert await robot.variable(3) == -7
            assert (await robot.system_register()).rom_run
            assert await robot.ping() < 0.5

    asyncio.run(main())


def test_baud_detection_runs_on_every_link_as_on_the_blocking_face(url: str) -> None:
    """``baudrate=None`` runs the ACK checks over socket:// too (the blocking client does; the
    asyncio one refused: "baud detection needs a serial port")."""
    with Rcb4Client.open(url, baudrate=None, timeout=0.5) as blocking:
        blocking.acknowledge_check()

    async def main() -> None:
        async with await AsyncRcb4Client.open(url, baudrate=None, timeout=0.5) as rcb:
            assert await rcb.detect_baudrate(probe_timeout=0.2) == 1250000
            await rcb.acknowledge_check()

    asyncio.run(main())


def test_concurrent_tasks_are_serialised(url: str) -> None:
    async def worker(robot: AsyncRobot, n: int) -> None:
        for i in range(15):
            await robot.set_variable(n, i * (n + 1))
            assert await robot.variable(n) == i * (n + 1)

    async def main() -> None:
        # what is tested is the order of 180 exchanges, not their speed: a timeout that a busy
        # two-core runner cannot miss (the pty link's 0.5 s default did, at load 12)
        async with await AsyncRobot.open(url, timeout=5.0) as robot:
            await asyncio.gather(*(worker(robot, n) for n in range(6)))
            assert [await robot.variable(n) for n in range(6)] == [14 * (n + 1) for n in range(6)]

    asyncio.run(main())


def test_nak_and_typed_errors() -> None:
    async def main() -> None:
        async with await AsyncRcb4Client.open("rcb4emu://") as rcb:
            assert await rcb.move(Com(), Ics(4, 2), 2) is not None  # booted: ICS 2 allocated
            with pytest.raises(NakError) as info:
                await rcb.division(Ram(0x0462), Data(b"\x00\x00"))
            assert info.value.command == 0x09
            with pytest.raises(ValueError):
                await rcb.read_ram(0x0480, 64)  # outside RAM: refused before sending
            await rcb.acknowledge_check()

    asyncio.run(main())


def test_cancelled_call_leaves_the_client_usable() -> None:
    async def main() -> None:
        async with await AsyncRcb4Client.open("rcb4emu://?latency=0.15", timeout=1.0) as rcb:
            task = asyncio.create_task(rcb.acknowledge_check())
            await asyncio.sleep(0.03)
            task.cancel()
            with pytest.raises(asyncio.CancelledError):
                await task
            # the late ACK arrives during the next call and is discarded
            assert (await rcb.get_version_info()).text.startswith("CB-4")
            await rcb.acknowledge_check()

    asyncio.run(main())


def test_a_late_reply_is_dropped_in_one_line(caplog: pytest.LogCaptureFixture) -> None:
    """The 131-byte late reply of a cancelled RAM read is waited out before the next request
    and dropped: one line with the total count (it was one warning per 4-byte chunk read, 33
    lines; then one "stray bytes" warning, while the next call hunted for its own reply
    among them)."""

    async def main() -> None:
        async with await AsyncRcb4Client.open("rcb4emu://?latency=0.15", timeout=1.0) as rcb:
            task = asyncio.create_task(rcb.read_ram(0x0000, 128))
            await asyncio.sleep(0.03)
            task.cancel()
            with pytest.raises(asyncio.CancelledError):
                await task
            caplog.clear()
            with caplog.at_level(logging.INFO, logger="rcb4hv"):
                assert (await rcb.get_version_info()).text.startswith("CB-4")

    asyncio.run(main())
    lines = [r.getMessage() for r in caplog.records if "byte(s)" in r.getMessage()]
    assert lines == ["dropped 131 byte(s) of replies to abandoned requests"], lines


@pytest.fixture
def silent_server() -> Iterator[tuple[str, list[socket.socket]]]:
    """A TCP server that accepts and reads but never answers."""
    srv = socket.create_server(("127.0.0.1", 0))
    conns: list[socket.socket] = []
    stop = threading.Event()

    def serve() -> None:
        srv.settimeout(0.05)
        while not stop.is_set():
            try:
                conn, _ = srv.accept()
            except OSError:
                continue
            conns.append(conn)

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    yield f"socket://127.0.0.1:{srv.getsockname()[1]}", conns
    stop.set()
    thread.join()
    for c in conns:
        c.close()
    srv.close()


def test_no_reply_times_out_in_time(silent_server: tuple[str, list[socket.socket]]) -> None:
    url, _ = silent_server

    async def main() -> None:
        async with await AsyncRcb4Client.open(url, timeout=0.2) as rcb:
            t0 = time.monotonic()
            with pytest.raises(Rcb4TimeoutError, match="AcknowledgeCheck"):
                await rcb.acknowledge_check()
            assert 0.19 < time.monotonic() - t0 < 0.2 + SLACK  # never early, never hung

    asyncio.run(main())


def test_peer_closing_raises_transport_error(
    silent_server: tuple[str, list[socket.socket]],
) -> None:
    url, conns = silent_server

    async def main() -> None:
        async with await AsyncRcb4Client.open(url, timeout=2.0) as rcb:
            while not conns:
                await asyncio.sleep(0.01)
            task = asyncio.create_task(rcb.acknowledge_check())
            await asyncio.sleep(0.05)
            conns[0].close()
            t0 = time.monotonic()
            with pytest.raises(TransportError):
                await task
            assert time.monotonic() - t0 < SLACK  # the close is seen, not the 2 s timeout
            with pytest.raises(TransportError):
                await rcb.acknowledge_check()

    asyncio.run(main())


def test_open_failures_are_typed(tmp_path: object) -> None:
    async def main() -> None:
        with pytest.raises(TransportError, match="cannot open"):
            await AsyncRcb4Client.open("/dev/no-such-rcb4-port")
        probe = socket.create_server(("127.0.0.1", 0))
        port = probe.getsockname()[1]
        probe.close()
        with pytest.raises(TransportError, match="cannot open"):
            await AsyncRcb4Client.open(f"socket://127.0.0.1:{port}")
        with pytest.raises(TransportError, match="fault://SPEC@URL"):  # as the blocking face
            await AsyncRcb4Client.open("fault://drop_reply=1")
        with pytest.raises(ValueError, match="timeout"):
            await AsyncRcb4Client.open("rcb4emu://", timeout=0)

    asyncio.run(main())


class ScriptedBoard:
    """A TCP peer that answers the n-th request with the n-th scripted reply bytes."""

    def __init__(self, replies: list[bytes]) -> None:
        self.replies = list(replies)
        self.server = socket.create_server(("127.0.0.1", 0))
        self.url = f"socket://127.0.0.1:{self.server.getsockname()[1]}"
        self.thread = threading.Thread(target=self._serve, daemon=True)
        self.thread.start()

    def _serve(self) -> None:
        conn, _ = self.server.accept()
        with conn:
            for reply in self.replies:
                if not conn.recv(256):
                    return
                conn.sendall(reply)
            conn.recv(256)

    def close(self) -> None:
        self.server.close()
        self.thread.join(timeout=2)


ACK = bytes.fromhex("04 FE 06 08")


def test_stray_bytes_and_bad_checksums_over_asyncio_streams() -> None:
    bad_ack = bytes.fromhex("04 FE 06 09")
    board = ScriptedBoard([b"\x55\xaa" + ACK, bad_ack, ACK + b"\x01\x02", ACK])

    async def main() -> None:
        async with await AsyncRcb4Client.open(board.url, timeout=1.0) as rcb:
            await rcb.acknowledge_check()  # junk before the reply is discarded
            t0 = time.monotonic()
            with pytest.raises(ChecksumError):
                await rcb.acknowledge_check()  # fails after the 20 ms grace, not the timeout
            assert time.monotonic() - t0 < rcb.corrupt_grace + SLACK
            await rcb.acknowledge_check()  # junk after the reply...
            await rcb.acknowledge_check()  # ...is gone before the next call

    try:
        asyncio.run(main())
    finally:
        board.close()


@pytest.mark.parametrize("version", ["2.1", "2.2"])
def test_async_robot_reads_the_layout_from_the_board(version: str) -> None:
    from rcb4hv.rom.layout import LAYOUTS

    async def main() -> None:
        async with await AsyncRobot.open(f"rcb4emu://?layout={version}&speed=10") as robot:
            assert robot.layout is None
            assert (await robot.board_layout()).main_loop == LAYOUTS[version].main_loop
            await robot.play_motion(1)
            assert (await robot.motion_status()).motion == 1
            await robot.wait_motion(timeout=5.0)

    asyncio.run(main())


def test_async_play_stop_and_resume_send_the_host_sequences() -> None:
    """The async robot sends exactly the frames of rcb4hv.protocol.sequences (as Robot does)."""
    from rcb4hv.protocol import Command, Move
    from rcb4hv.protocol import sequences as seq
    from rcb4hv.protocol.memory import SYS

    board = make_board()

    async def main() -> None:
        async with await AsyncRobot.open(emulator_url(board)) as robot:
            await robot.wait_ready(timeout=5.0)
            lay = await robot.board_layout()
            sent: list[Command] = []
            transact = robot.client.transact

            async def recording(command: Command, timeout: float | None = None) -> object:
                if not (isinstance(command, Move) and isinstance(command.dst, Com)):
                    sent.append(command)  # reads excluded: only what the sequence writes
                return await transact(command, timeout)

            robot.client.transact = recording  # type: ignore[method-assign,assignment]
            word = await robot.system_word()
            await robot.play_motion(1)
            assert sent == seq.play_motion(word, lay.address(1), lay.main_loop)
            assert (await robot.motion_status()).motion == 1
            sent.clear()
            word = await robot.system_word()
            await robot.stop_motion(reset=False)
            assert sent == seq.stop_program(word, lay.main_loop, reset=False)
            assert not (await robot.system_register()).rom_run
            assert (await robot.motion_status()).motion == 1
            sent.clear()
            await robot.resume_motion()
            assert sent == seq.resume_program(word & ~SYS.ROM_RUN)
            await robot.wait_motion(timeout=5.0)
            await robot.play_motion(1)
            await robot.stop_motion()
            status = await robot.motion_status()
            assert status.motion is None and lay.main_loop <= status.pc < lay.motion_base

    try:
        asyncio.run(main())
    finally:
        board.close()


def test_fault_urls_work_on_the_asyncio_face() -> None:
    """fault:// is a pyserial URL handler, so the asyncio client opens it like any port."""

    async def main() -> None:
        async with await AsyncRcb4Client.open("fault://drop_reply=1@rcb4emu://") as rcb:
            assert isinstance(rcb.transport, PolledTransport)
            t0 = time.monotonic()
            with pytest.raises(Rcb4TimeoutError):
                await rcb.acknowledge_check(timeout=0.1)
            assert time.monotonic() - t0 < 0.5
        async with await AsyncRcb4Client.open("fault://seed=1@rcb4emu://") as rcb:
            await rcb.acknowledge_check()
            await rcb.write_ram(0x0357, bytes(range(200)))
            assert await rcb.read_ram(0x0357, 200) == bytes(range(200))

    asyncio.run(main())
