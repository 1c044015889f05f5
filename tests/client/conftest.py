"""Fixtures of the client suite: a connected client per transport (in process, pty, TCP)."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import ExitStack
from dataclasses import dataclass
from typing import Any

import pytest

from rcb4hv.client import Rcb4Client, Robot
from rcb4hv.emulator import emulator_url
from tests.client.aio_bridge import BlockingBridge

TRANSPORTS = ("inproc", "pty", "tcp", "aio-inproc", "aio-pty", "aio-tcp")
"""Blocking client and robot over each link; ``aio-*``: the asyncio client and AsyncRobot
(their coroutines run through a blocking bridge, so the same tests drive them) over the same
links."""
SPEED = 10.0  # emulator clock speed for the suite: 10x real time keeps start-up short


@dataclass
class Rig:
    """A client connected to an emulated board over one transport."""

    kind: str
    board: Any
    client: Rcb4Client  # or a BlockingBridge around an AsyncRcb4Client (aio-* kinds)
    robot: Robot  # or a Blocking around an AsyncRobot (aio-* kinds)
    url: str

    def new_robot(self, **options: Any) -> Robot:
        """Another robot (Robot, or AsyncRobot for the aio-* kinds) on the rig's client."""
        if isinstance(self.client, BlockingBridge):
            return self.client.robot(**options)  # type: ignore[return-value]
        return Robot(self.client, **options)


def _emulator() -> Any:
    return pytest.importorskip("rcb4hv.emulator", reason="the emulator is not available")


def make_board(speed: float = SPEED, **config: Any) -> Any:
    emu = _emulator()
    cfg = emu.EmulatorConfig(**config) if config else emu.EmulatorConfig()
    return emu.Board(cfg, clock=emu.RealClock(speed=speed))


SYNC_TRANSPORTS = tuple(k for k in TRANSPORTS if not k.startswith("aio-"))


@pytest.fixture(params=TRANSPORTS)
def rig(request: pytest.FixtureRequest) -> Iterator[Rig]:
    """One connected client per transport; everything is closed on exit."""
    yield from make_rig(request.param)


def make_rig(kind: str) -> Iterator[Rig]:
    emu = _emulator()
    board = make_board()
    with ExitStack() as stack:
        stack.callback(board.close)
        link = kind.removeprefix("aio-")
        if link == "inproc":
            url = emulator_url(board)
        elif link == "pty":
            srv = stack.enter_context(emu.PtyServer(board))
            url = str(srv.path)
        else:
            srv = stack.enter_context(emu.TcpServer(board, "127.0.0.1", 0))
            host, port = srv.address[:2]
            url = f"socket://{host}:{port}"
        client: Any
        if kind.startswith("aio-"):
            client = BlockingBridge(url, timeout=0.5)
        else:
            client = Rcb4Client.open(url, timeout=0.5)
        stack.callback(client.close)
        robot = client.robot() if isinstance(client, BlockingBridge) else Robot(client)
        robot.wait_ready(timeout=5.0)
        yield Rig(kind, board, client, robot, url)
