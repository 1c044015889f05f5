"""Fixtures of the client suite: a connected client per transport (in process, pty, TCP).

The emulated board runs on virtual time that the client's own requests move: every request
frame the board answers advances its :class:`~rcb4hv.emulator.VirtualClock` by
:data:`STEP`. A waiting client polls, so its waits move the board on exactly as far as its
polls say, whatever the machine's load: a 1.5 s move finishes after the same number of polls on
an idle laptop and on a loaded CI runner, and tests assert board time, not wall time.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import ExitStack
from dataclasses import dataclass
from typing import Any

import pytest

from rcb4hv import emulator as emu
from rcb4hv.client import Rcb4Client, Robot
from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock, emulator_url
from rcb4hv.emulator.boot import booted
from rcb4hv.rom.default import default_image
from rcb4hv.rom.layout import HTH4_22, MotionLayout
from tests.client.aio_bridge import BlockingBridge

TRANSPORTS = ("inproc", "pty", "tcp", "aio-inproc", "aio-pty", "aio-tcp")
"""Blocking client over each link; ``aio-*``: the asyncio client (through a blocking bridge,
so the same tests drive it) over the same links."""
STEP = 0.05
"""Board seconds each answered request frame moves the clock: a client polling every 50 ms.
Coarser than the 15 ms output period (so a 1.5 s move is 30 polls, not 100) and finer than any
wait the suite makes."""
BOOT_LIMIT_S = 30.0  # board seconds the start-up program may take (the default image: < 1 s)


@dataclass
class Rig:
    """A client connected to an emulated board over one transport."""

    kind: str
    board: Any
    client: Rcb4Client  # or a BlockingBridge around an AsyncRcb4Client (aio-* kinds)
    robot: Robot
    url: str


class SteppedBoard(Board):
    """A board on a :class:`VirtualClock` that each answered request frame moves by ``step``."""

    def __init__(
        self, config: EmulatorConfig, step: float = STEP, rom_image: bytes | None = None
    ) -> None:
        self.virtual = VirtualClock()
        self.step = step
        super().__init__(config, clock=self.virtual, rom_image=rom_image)

    def feed(self, data: bytes | bytearray) -> bytes:
        before = self.frames_handled
        reply = super().feed(data)
        self.virtual.advance(self.step * (self.frames_handled - before))
        return reply


def make_board(layout: MotionLayout = HTH4_22, **config: Any) -> SteppedBoard:
    """The default board in ``layout``, its start-up finished (run in virtual time), on
    request-driven time."""
    image = None if layout is HTH4_22 else default_image(layout)
    board = SteppedBoard(EmulatorConfig(**config), rom_image=image)
    while not booted(board.ram, layout):
        assert board.now < BOOT_LIMIT_S, "the start-up program never reached the main loop"
        board.run_for(STEP)
    return board


SYNC_TRANSPORTS = tuple(k for k in TRANSPORTS if not k.startswith("aio-"))


@pytest.fixture(params=TRANSPORTS)
def rig(request: pytest.FixtureRequest) -> Iterator[Rig]:
    """One connected client per transport; everything is closed on exit."""
    yield from make_rig(request.param)


def make_rig(kind: str) -> Iterator[Rig]:
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
        robot = Robot(client)
        robot.wait_ready(timeout=5.0)
        yield Rig(kind, board, client, robot, url)
