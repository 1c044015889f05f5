"""Fuzzing the emulator's input path (Board.feed) and the frame decoder's memory bound.

Budget: ``RCB4HV_FUZZ_EXAMPLES`` examples per test (default small for ``make test``;
``make fuzz`` sets 20000).
"""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import protocol as p
from tests.reliability.mutations import hostile_input, mutated_frames
from tests.reliability.scenarios import (
    FUZZ_EXAMPLES,
    check_hostile_feed,
    check_valid_feed,
    feed_memory_growth,
    fresh_board,
    split_replies,
)
from tests.strategies import command_frames

chunks = st.integers(1, 40)
gaps = st.sampled_from([0.0, 0.0, 0.1, 0.45])  # fractions of the frame timeout between chunks


@settings(max_examples=FUZZ_EXAMPLES)
@given(hostile_input, chunks, gaps, st.sampled_from(["booted", "idle"]))
def test_fuzz_board_feed_hostile(data: bytes, chunk: int, gap: float, kind: str) -> None:
    check_hostile_feed(data, chunk, gap, kind)


@settings(max_examples=FUZZ_EXAMPLES)
@given(st.lists(st.one_of(mutated_frames, st.binary(max_size=64)), min_size=1, max_size=8))
def test_fuzz_board_feed_stream_of_mutations(parts: list[bytes]) -> None:
    """Many mutated frames in one stream (no gaps): still one NAK at most per 3 bytes."""
    check_hostile_feed(b"".join(parts), 64, 0.0)


@settings(max_examples=FUZZ_EXAMPLES)
@given(st.lists(command_frames, min_size=1, max_size=6), chunks, gaps)
def test_fuzz_board_valid_commands_one_reply_each(
    frames: list[bytes], chunk: int, gap: float
) -> None:
    check_valid_feed(frames, chunk, gap)


@settings(max_examples=FUZZ_EXAMPLES)
@given(hostile_input, st.lists(command_frames, min_size=1, max_size=3))
def test_fuzz_board_recovers_for_valid_commands(garbage: bytes, frames: list[bytes]) -> None:
    """Garbage, a frame-timeout gap, then valid commands: each gets exactly its reply."""
    board = fresh_board()
    clock = board.clock
    board.feed(garbage)
    clock.advance(board.config.frame_timeout_s * 1.5)  # type: ignore[attr-defined]
    board.tick()
    board.take_output()
    for frame in frames:
        replies = split_replies(board.feed(frame) + board.take_output())
        assert len(replies) == 1, f"{frame.hex(' ')} -> {replies}"
        p.decode_reply(replies[0], p.decode_command(frame))


def test_fuzz_board_memory_stays_bounded() -> None:
    """Thousands of hostile inputs to one board: traced memory does not grow, the queued
    output stays small."""
    fed, growth, peak_out = feed_memory_growth(min(max(FUZZ_EXAMPLES * 20, 1500), 50_000), seed=3)
    assert fed > 50_000
    assert growth < 64 * 1024, f"memory grew by {growth} bytes over {fed} bytes of input"
    assert peak_out <= 8, f"{peak_out} bytes queued outside feed()"


def test_fuzz_check_rejects_a_malformed_reply_stream() -> None:
    """The checker itself fails on output that is not whole frames (so the properties bite)."""
    import pytest

    with pytest.raises(AssertionError):
        split_replies(bytes.fromhex("04 FE 06 08 04 00"))
    with pytest.raises(AssertionError):
        split_replies(bytes.fromhex("04 FE 06 09"))
