"""Bad input gets the spec's answer (NAK or silence) and never stops the board."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from tests.emulator.conftest import IDLE, h, x

ACK_CHECK = h("03 FE 01")
ACK = h("04 FE 06 08")


def board(**cfg: object) -> Board:
    config = EmulatorConfig(power_on_system_register=0, **cfg)  # type: ignore[arg-type]
    return Board(config, clock=VirtualClock())


def test_bad_checksum_naks_cmd(idle: Board) -> None:
    assert x(idle, "09 00 02 00 00 00 02 80 8E") == h("04 00 15 19")
    assert idle.ram[0:2] == b"\x00\x00"
    assert x(idle, ACK_CHECK) == ACK


def test_small_size_bytes_are_dropped_silently(idle: Board) -> None:
    assert x(idle, b"\x00\x01\x02" + ACK_CHECK) == ACK


def test_oversize_frame_is_swallowed_and_naked() -> None:
    b = board()
    frame = bytes([200, 0x00]) + bytes(198)
    assert x(b, frame[:50]) == b""
    assert x(b, frame[50:] + ACK_CHECK) == h("04 00 15 19") + ACK
    silent = board(oversize_frame="silent")
    assert x(silent, frame + ACK_CHECK) == ACK


def test_partial_frame_times_out_with_nak() -> None:
    clock = VirtualClock()
    b = Board(IDLE, clock=clock)
    assert x(b, h("09 00 02 00")) == b""
    clock.advance(0.01)
    b.tick()
    assert b.take_output() == b""
    clock.advance(0.011)
    b.tick()
    assert b.take_output() == h("04 00 15 19")
    assert x(b, ACK_CHECK) == ACK


def test_partial_frame_gap_restarts_with_each_byte() -> None:
    clock = VirtualClock()
    b = Board(IDLE, clock=clock)
    frame = h("09 00 02 62 04 00 05 00 76")
    for byte in frame[:-1]:
        assert b.feed(bytes([byte])) == b""
        clock.advance(0.015)
    assert b.feed(frame[-1:]) == h("04 00 06 0A")
    assert b.take_output() == b""


def test_lone_size_byte_times_out_silently() -> None:
    clock = VirtualClock()
    b = Board(IDLE, clock=clock)
    x(b, b"\x09")
    clock.advance(1.0)
    b.tick()
    assert b.take_output() == b""
    assert x(b, ACK_CHECK) == ACK


def test_partial_frame_silent_setting() -> None:
    clock = VirtualClock()
    b = Board(EmulatorConfig(power_on_system_register=0, partial_frame_reply="silent"), clock=clock)
    x(b, h("09 00 02"))
    clock.advance(1.0)
    b.tick()
    assert b.take_output() == b""


def test_internal_error_becomes_nak(idle: Board, monkeypatch: pytest.MonkeyPatch) -> None:
    def boom(*args: object) -> None:
        raise RuntimeError("bug")

    monkeypatch.setattr(idle._interp, "execute", boom)
    assert x(idle, ACK_CHECK) == h("04 FE 15 17")


@settings(max_examples=150)
@given(st.lists(st.binary(max_size=300), max_size=8))
def test_garbage_never_kills_the_board(chunks: list[bytes]) -> None:
    clock = VirtualClock()
    b = Board(clock=clock)  # default image, ROM program running
    for c in chunks:
        b.feed(c)
        clock.advance(0.003)
        assert len(b._decoder.pending) < 128
    clock.advance(0.05)
    b.tick()
    b.take_output()
    # still serving: an ACK check after the garbage (two tries: a swallowed oversize frame
    # or a partial frame may eat the first)
    replies = b.feed(ACK_CHECK)
    if replies != ACK:
        clock.advance(0.05)
        b.tick()
        b.take_output()
        replies = b.feed(ACK_CHECK)
    assert replies.endswith(ACK)


@settings(max_examples=100)
@given(st.binary(min_size=1, max_size=125), st.integers(0, 255))
def test_valid_checksum_garbage_gets_one_reply(body: bytes, cmd: int) -> None:
    """Any whole frame with a valid checksum gets exactly one reply frame for its CMD."""
    b = Board(IDLE, clock=VirtualClock())
    frame = bytes([len(body) + 3, cmd]) + body
    frame += bytes([sum(frame) & 0xFF])
    reply = b.feed(frame)
    assert len(reply) == reply[0] >= 4
    assert reply[1] == cmd
    assert sum(reply[:-1]) & 0xFF == reply[-1]


def test_output_queue_is_bounded() -> None:
    clock = VirtualClock()
    b = Board(EmulatorConfig(power_on_system_register=0, max_pending_output=256), clock=clock)
    for _ in range(200):
        b.feed(h("09 00"))
        clock.advance(0.05)
        b.tick()
    assert len(b.take_output()) == 256
