"""A request whose call was abandoned (cancelled, interrupted, timed out) still gets its reply
from the board; the next call must not take that late reply for its own. Flushing the input
before sending is not enough: the late reply can arrive after the flush. The client waits out
the replies it owes before it sends again (``_roundtrip``/``_settle``), and the reply hunt
drops an ACK where data is expected (only a NAK is a 4-byte answer to a data command)."""

from __future__ import annotations

import asyncio

import pytest

from rcb4hv.aio import AsyncRcb4Client
from rcb4hv.client import Rcb4Client
from rcb4hv.client.exchange import ReplyMatcher
from rcb4hv.errors import Rcb4TimeoutError
from rcb4hv.protocol import Com, FrameDecoder, Move, Ram

A, B = 0x0462, 0x0464  # user RAM the tests write and read back


def test_a_cancelled_write_does_not_shift_the_replies_of_the_reads_after_it() -> None:
    async def main() -> tuple[int, int]:
        wrong = errors = 0
        url = "rcb4emu://?latency=0.02"
        async with await AsyncRcb4Client.open(url, timeout=1.0) as rcb:
            await rcb.write_ram(A, b"\x11\x11")
            await rcb.write_ram(B, b"\x22\x22")
            for _ in range(8):
                task = asyncio.create_task(rcb.write_ram(0x0466, b"\0\0"))
                await asyncio.sleep(0.005)  # the request is out; its ACK is on its way
                task.cancel()
                with pytest.raises(asyncio.CancelledError):
                    await task
                for address, want in ((A, b"\x11\x11"), (B, b"\x22\x22")):
                    try:
                        wrong += await rcb.read_ram(address, 2) != want
                    except Exception:
                        errors += 1
        return wrong, errors

    assert asyncio.run(main()) == (0, 0)


def test_a_read_that_timed_out_does_not_answer_the_next_read() -> None:
    with Rcb4Client.open("rcb4emu://?latency=0.08", timeout=1.0) as rcb:
        rcb.write_ram(A, b"\x11\x11")
        rcb.write_ram(B, b"\x22\x22")
        with pytest.raises(Rcb4TimeoutError):
            rcb.transact(Move(Com(), Ram(A), 2), timeout=0.03)  # its reply comes later
        assert rcb.read_ram(B, 2) == b"\x22\x22"  # not A's late 11 11
        assert rcb.read_ram(A, 2) == b"\x11\x11"


def test_the_reply_hunt_drops_an_ack_where_data_is_expected() -> None:
    late_ack = bytes.fromhex("04 00 06 0a")  # a MOVE write's ACK, arriving late
    data = bytes.fromhex("05 00 11 11 27")  # the 2-byte read's reply
    matcher = ReplyMatcher(FrameDecoder(), 0x00, 5, "Move", 0.02)
    assert matcher.feed(late_ack + data, 0.0) == data
    assert matcher.discarded == 4
    nak = bytes.fromhex("04 00 15 19")
    assert ReplyMatcher(FrameDecoder(), 0x00, 5, "Move", 0.02).feed(nak, 0.0) == nak
