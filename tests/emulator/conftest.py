"""Fixtures of the emulator tests."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.protocol import Command, encode_command

IDLE = EmulatorConfig(power_on_system_register=0x0000)
"""ROM_F clear at power-on: the ROM program does not run, RAM holds only what tests put."""


def h(text: str) -> bytes:
    return bytes.fromhex(text)


def x(board: Board, request: str | bytes | Command) -> bytes:
    """One request -> reply exchange."""
    if isinstance(request, str):
        data = h(request)
    elif isinstance(request, bytes):
        data = request
    else:
        data = encode_command(request)
    return board.feed(data)


@pytest.fixture
def clock() -> VirtualClock:
    return VirtualClock()


@pytest.fixture
def idle(clock: VirtualClock) -> Iterator[Board]:
    """A board with the default image whose ROM program is not running, RAM at power-on."""
    b = Board(IDLE, clock=clock)
    yield b
    b.close()


@pytest.fixture
def booted(clock: VirtualClock) -> Iterator[Board]:
    """The default board after its boot sequence (servos homed, main loop running)."""
    b = Board(clock=clock)
    b.run_for(3.0)
    yield b
    b.close()
