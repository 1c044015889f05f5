"""Hypothesis strategies that mutate valid frames the way flaky links and bad software do.

Mutations: flipped bits, truncation, a wrong size byte, a wrong checksum, concatenation of
frames, and interleaved garbage. Shared by the protocol and emulator fuzz tests.
"""

from __future__ import annotations

import random
from collections.abc import Sequence

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


# ---------------------------------------------------------------------------------------------
# The same mutations driven by a seeded random.Random (no hypothesis): for long loops that
# measure memory or latency, where thousands of inputs are needed without shrinking.

SEED_FRAMES: tuple[bytes, ...] = tuple(
    bytes.fromhex(h)
    for h in (
        "03 FE 01",
        "04 FE 06 08",
        "03 FD 00",
        "03 0D 10",
        "0A 00 20 00 00 00 00 00 02 2C",
        "0A 00 21 00 00 00 04 05 02 36",
        "0B 00 23 00 00 00 80 0B 00 04 BD",
        "09 06 02 62 04 00 05 00 7C",
        "09 07 82 50 03 00 00 01 E6",
        "08 01 02 3A 00 00 0F 54",
        "0A 04 00 62 04 00 00 00 02 76",
        "0A 05 00 62 04 00 00 01 02 78",
        "07 0F 02 1E 4C 1D 9F",
        "07 0F 02 01 00 80 99",
        "0D 10 01 02 00 00 00 0A 4C 1D 40 1F F2",
        "0E 11 08 00 00 00 01 05 B0 1D 06 14 1E 32",
        "0B 12 01 02 00 00 00 02 64 3C C2",
    )
)
"""Valid command frames of spec section 14 that leave the board serving (no ROM writes)."""


def random_mutation(rng: random.Random, frames: Sequence[bytes] = SEED_FRAMES) -> bytes:
    """One hostile input: a mutated valid frame, several frames with garbage, or noise."""
    kind = rng.randrange(8)
    frame = bytearray(rng.choice(frames))
    if kind == 0:  # flipped bits
        for _ in range(rng.randint(1, 4)):
            frame[rng.randrange(len(frame))] ^= 1 << rng.randrange(8)
        return bytes(frame)
    if kind == 1:  # truncated
        return bytes(frame[: rng.randrange(len(frame))])
    if kind == 2:  # wrong size byte
        frame[0] = (frame[0] + rng.randint(1, 255)) & 0xFF
        return bytes(frame)
    if kind == 3:  # wrong checksum
        frame[-1] = (frame[-1] + rng.randint(1, 255)) & 0xFF
        return bytes(frame)
    if kind == 4:  # concatenation
        return b"".join(rng.choice(frames) for _ in range(rng.randint(2, 4)))
    if kind == 5:  # interleaved garbage
        parts = [
            rng.choice(frames) if rng.random() < 0.5 else rng.randbytes(rng.randint(1, 20))
            for _ in range(rng.randint(1, 5))
        ]
        return b"".join(parts)
    if kind == 6:  # an oversize SIZE byte followed by noise
        return bytes((rng.randint(129, 255),)) + rng.randbytes(rng.randint(0, 300))
    return rng.randbytes(rng.randint(0, 300))
