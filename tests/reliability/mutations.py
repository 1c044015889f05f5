"""Hypothesis strategies that mutate valid frames the way flaky links and bad software do.

Mutations: flipped bits, truncation, a wrong size byte, a wrong checksum, concatenation of
frames, and interleaved garbage. Shared by the protocol and emulator fuzz tests.
"""

from __future__ import annotations

from hypothesis import strategies as st

from tests.strategies import command_frames


@st.composite
def flipped_bits(draw: st.DrawFn) -> bytes:
    frame = bytearray(draw(command_frames))
    for _ in range(draw(st.integers(1, 4))):
        i = draw(st.integers(0, len(frame) - 1))
        frame[i] ^= 1 << draw(st.integers(0, 7))
    return bytes(frame)


@st.composite
def truncated(draw: st.DrawFn) -> bytes:
    frame = draw(command_frames)
    return frame[: draw(st.integers(0, len(frame) - 1))]


@st.composite
def wrong_size(draw: st.DrawFn) -> bytes:
    frame = bytearray(draw(command_frames))
    frame[0] = draw(st.integers(0, 255).filter(lambda v: v != frame[0]))
    return bytes(frame)


@st.composite
def wrong_checksum(draw: st.DrawFn) -> bytes:
    frame = bytearray(draw(command_frames))
    frame[-1] = (frame[-1] + draw(st.integers(1, 255))) & 0xFF
    return bytes(frame)


@st.composite
def concatenated(draw: st.DrawFn) -> bytes:
    return b"".join(draw(st.lists(command_frames, min_size=2, max_size=4)))


@st.composite
def interleaved_garbage(draw: st.DrawFn) -> bytes:
    parts = draw(
        st.lists(st.one_of(command_frames, st.binary(min_size=1, max_size=20)), max_size=5)
    )
    return b"".join(parts)


mutated_frames: st.SearchStrategy[bytes] = st.one_of(
    flipped_bits(),
    truncated(),
    wrong_size(),
    wrong_checksum(),
    concatenated(),
    interleaved_garbage(),
)
"""Any of the mutations above."""

hostile_input: st.SearchStrategy[bytes] = st.one_of(mutated_frames, st.binary(max_size=300))
"""Mutated frames or plain random bytes."""
