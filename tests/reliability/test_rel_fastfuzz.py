"""The fast mutation fuzzer of ``make reliability``: a small run here, and proof that its
checks catch a planted bug in each target."""

from __future__ import annotations

import random

import pytest

from rcb4hv import protocol as p
from rcb4hv.emulator import Board
from tests.reliability import fastfuzz
from tests.reliability.mutations import SEED_FRAMES


@pytest.fixture(scope="module")
def frames() -> list[bytes]:
    return fastfuzz.corpus()


def test_corpus_is_the_fixture_motions_and_the_host_frames(frames: list[bytes]) -> None:
    assert set(SEED_FRAMES) <= set(frames)
    assert len(frames) > len(SEED_FRAMES) + 300  # 586 distinct motion frames in the fixture
    assert {f[1] for f in frames} >= {0x00, 0x0B, 0x0C, 0x10}  # MOVE, JUMP, CALL, 10h


def test_mutations_reach_past_framing(frames: list[bytes]) -> None:
    rng = random.Random(3)
    inputs = [fastfuzz.mutate(rng, frames) for _ in range(2000)]
    framed = [d for d in inputs if 3 <= len(d) == d[0] and sum(d[:-1]) & 0xFF == d[-1]]
    assert 0.4 < len(framed) / len(inputs) < 0.8
    assert len(set(inputs)) > 1900


def test_fast_fuzz_run_finds_no_crash(frames: list[bytes]) -> None:
    result = fastfuzz.fuzz(3000, seed=11, frames=frames)
    assert result.crashes == []
    assert result.inputs == 3000
    assert result.decoded > 50 and result.frames > 500 and result.replies > 500
    assert result.rate > 0


def test_a_planted_decode_bug_is_reported(
    frames: list[bytes], monkeypatch: pytest.MonkeyPatch
) -> None:
    real = p.decode_command

    def buggy(frame: bytes | bytearray | memoryview) -> p.Command:
        cmd = real(frame)
        if isinstance(cmd, p.RunConstFrameServo) and len(cmd.positions) > 3:
            return p.RunConstFrameServo(cmd.speed, cmd.positions[:3])  # loses servos
        return cmd

    monkeypatch.setattr(p, "decode_command", buggy)
    result = fastfuzz.fuzz(2000, seed=5, frames=frames)
    assert any(c.startswith("decode: AssertionError('re-encodes") for c in result.crashes)


def test_a_planted_board_bug_is_reported(
    frames: list[bytes], monkeypatch: pytest.MonkeyPatch
) -> None:
    real = Board.feed

    def buggy(self: Board, data: bytes) -> bytes:
        out = real(self, data)
        return out[:-1] if len(out) > 4 else out  # a reply cut short

    monkeypatch.setattr(Board, "feed", buggy)
    result = fastfuzz.fuzz(500, seed=5, frames=frames)
    assert any(c.startswith("board:") for c in result.crashes)
