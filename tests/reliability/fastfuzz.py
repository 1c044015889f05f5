"""A fast mutation fuzzer over real frames, beside the hypothesis properties.

Hypothesis explores cleverly but spends most of its time drawing; this driver spends it on
the code under test, for ``make reliability``'s million inputs. The corpus is real traffic:
the command frames of every motion of the HeartToHeart4 fixture project (as HeartToHeart4
wrote them; ``../shared/fixtures/hth4/kxr-l2-hac``) plus the host frames of
:data:`~tests.reliability.mutations.SEED_FRAMES`. Each input is one to three mutations of a
corpus frame (bit flips, interesting byte values, truncation, insertion, deletion, splicing
two frames, garbage around), and half of the time its SIZE and SUM are made right again so
the input gets past framing into command decoding and execution.

Every input goes through four targets, each with its property:

* ``decode``: :func:`decode_command` returns a command or raises ProtocolError, and a
  decoded command encodes back to the very input;
* ``decoder``: the sans-I/O :class:`FrameDecoder` yields whole checked frames or raises
  ProtocolError, and keeps fewer than 128 bytes pending;
* ``reply``: :func:`decode_reply` against a command from the corpus returns a reply or raises
  ProtocolError;
* ``board``: :meth:`Board.feed` of a running board never raises and logs no internal error,
  and everything it sends is whole reply frames of an allowed shape. The board's virtual
  clock moves between inputs; a frame-timeout gap now and then is followed by an ACK check
  that must be answered exactly, and the board is replaced by a fresh copy every
  :data:`BOARD_LIFETIME` inputs.

Anything else is a crash, kept with the input that caused it.
"""

from __future__ import annotations

import logging
import os
import random
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final

from rcb4hv import protocol as p
from rcb4hv.errors import ProtocolError
from tests.reliability.mutations import SEED_FRAMES
from tests.reliability.scenarios import (
    ACK_CHECK,
    ACK_REPLY,
    InternalErrors,
    check_reply_shape,
    fresh_board,
)

FIXTURE_PROJECT: Final = (
    Path(__file__).resolve().parents[2].parent
    / "shared"
    / "fixtures"
    / "hth4"
    / "kxr-l2-hac"
    / "HAC_KXR_HTH4_project.h4p"
)
BOARD_LIFETIME: Final = 5000
GAP_EVERY: Final = 64
INTERESTING: Final = (0x00, 0x01, 0x02, 0x03, 0x04, 0x06, 0x15, 0x7F, 0x80, 0x81, 0xFE, 0xFF)
MAX_CRASHES_KEPT: Final = 20


def corpus(project: Path = FIXTURE_PROJECT) -> list[bytes]:
    """The fixture project's motion frames (distinct, in order) and the host seed frames.

    Raises FileNotFoundError if the fixture is absent."""
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.image import motion_image_frames

    if not project.is_file():
        raise FileNotFoundError(f"fixture project {project} is absent")
    frames: dict[bytes, None] = {}
    for motion in load_project(project).motions:
        for frame in motion_image_frames(motion.frames):
            frames[frame] = None
    for frame in SEED_FRAMES:
        frames[frame] = None
    return list(frames)


def _fix(data: bytearray) -> None:
    """Make SIZE and SUM right again (a frame of 3..255 bytes)."""
    if 3 <= len(data) <= 255:
        data[0] = len(data)
        data[-1] = sum(data[:-1]) & 0xFF


def mutate(rng: random.Random, frames: Sequence[bytes]) -> bytes:
    """One input: 1-3 mutations of a corpus frame, framing repaired half of the time."""
    data = bytearray(rng.choice(frames))
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(9)
        n = len(data)
        if kind == 0 and n:  # flip a bit
            data[rng.randrange(n)] ^= 1 << rng.randrange(8)
        elif kind == 1 and n:  # an interesting byte value
            data[rng.randrange(n)] = rng.choice(INTERESTING)
        elif kind == 2 and n:  # a random byte value
            data[rng.randrange(n)] = rng.randrange(256)
        elif kind == 3 and n > 1:  # truncate
            del data[rng.randrange(1, n) :]
        elif kind == 4:  # insert random bytes
            i = rng.randrange(n + 1)
            data[i:i] = rng.randbytes(rng.randint(1, 8))
        elif kind == 5 and n > 1:  # delete a run
            i = rng.randrange(n)
            del data[i : i + rng.randint(1, 4)]
        elif kind == 6:  # splice with another frame
            other = rng.choice(frames)
            data = data[: rng.randrange(len(data) + 1)] + other[rng.randrange(len(other)) :]
        elif kind == 7:  # another whole frame after it
            data += rng.choice(frames)
        else:  # garbage before it
            data[0:0] = rng.randbytes(rng.randint(1, 4))
    if rng.random() < 0.5:
        _fix(data)
    return bytes(data)


@dataclass
class FuzzResult:
    """Counters of one run (summed over workers)."""

    inputs: int = 0
    bytes_fed: int = 0
    seconds: float = 0.0
    decoded: int = 0
    frames: int = 0
    replies: int = 0
    board_resets: int = 0
    crashes: list[str] = field(default_factory=list)

    def add(self, other: FuzzResult) -> None:
        self.inputs += other.inputs
        self.bytes_fed += other.bytes_fed
        self.seconds = max(self.seconds, other.seconds)
        self.decoded += other.decoded
        self.frames += other.frames
        self.replies += other.replies
        self.board_resets += other.board_resets
        room = MAX_CRASHES_KEPT - len(self.crashes)
        self.crashes += other.crashes[: max(room, 0)]

    @property
    def rate(self) -> float:
        """Inputs per second of wall time."""
        return self.inputs / self.seconds if self.seconds else 0.0


class _Run:
    def __init__(self, frames: Sequence[bytes], seed: int) -> None:
        self.frames = frames
        self.rng = random.Random(seed)
        self.commands = [c for c in (self._decode(f) for f in frames) if c is not None]
        self.result = FuzzResult()
        self.errors = InternalErrors()
        self.crash_count = 0
        self._new_board()

    @staticmethod
    def _decode(frame: bytes) -> p.Command | None:
        try:
            return p.decode_command(frame)
        except ProtocolError:
            return None

    def _new_board(self) -> None:
        self.board = fresh_board("booted")
        self.clock = self.board.clock
        self.result.board_resets += 1

    def _crash(self, target: str, data: bytes, exc: BaseException) -> None:
        self.crash_count += 1
        if len(self.result.crashes) < MAX_CRASHES_KEPT:
            self.result.crashes.append(f"{target}: {exc!r} on input {data.hex(' ')}"[:400])

    def one(self, data: bytes, i: int) -> None:
        res = self.result
        res.inputs += 1
        res.bytes_fed += len(data)
        # decode
        try:
            cmd = p.decode_command(data)
        except ProtocolError:
            pass
        except Exception as exc:
            self._crash("decode", data, exc)
        else:
            res.decoded += 1
            try:
                again = p.encode_command(cmd)
            except Exception as exc:
                self._crash("decode", data, exc)
            else:
                if again != data:
                    self._crash("decode", data, AssertionError(f"re-encodes as {again.hex()}"))
        # decoder
        dec = p.FrameDecoder()
        dec.receive_data(data)
        try:
            while True:
                try:
                    frame = dec.next_frame()
                except ProtocolError:
                    continue
                if frame is p.NEED_DATA:
                    break
                assert isinstance(frame, bytes) and frame[0] == len(frame)
                res.frames += 1
            assert len(dec.pending) < p.MAX_FRAME_SIZE, "decoder holds a whole frame's bytes"
        except Exception as exc:
            self._crash("decoder", data, exc)
        # reply
        try:
            p.decode_reply(data, self.rng.choice(self.commands))
        except ProtocolError:
            pass
        except Exception as exc:
            self._crash("reply", data, exc)
        # board
        try:
            self._board(data, i)
        except Exception as exc:
            self._crash("board", data, exc)
        if self.errors.records:
            record = self.errors.records[0]
            self.errors.records.clear()
            self._crash("board", data, RuntimeError(f"internal error: {record.getMessage()}"))

    def _board(self, data: bytes, i: int) -> None:
        board = self.board
        out = board.feed(data) + board.take_output()
        if i % GAP_EVERY == 0:
            self.clock.advance(board.config.frame_timeout_s * 1.5)
            board.tick()
            out += board.take_output()
        else:
            self.clock.advance(self.rng.choice((0.0, 0.0005, 0.002)))
        dec = p.FrameDecoder(max_size=p.MAX_REPLY_SIZE, resync="frame")
        dec.receive_data(out)
        while True:
            frame = dec.next_frame()  # a ProtocolError here is a malformed reply: a crash
            if frame is p.NEED_DATA:
                break
            assert isinstance(frame, bytes)
            check_reply_shape(frame)
            self.result.replies += 1
        assert not dec.pending, f"the board sent a partial frame {dec.pending.hex(' ')}"
        if i % GAP_EVERY == 0:
            reply = board.feed(ACK_CHECK) + board.take_output()
            assert reply == ACK_REPLY, f"ACK check after a gap answered {reply.hex(' ')}"
        if i % BOARD_LIFETIME == BOARD_LIFETIME - 1:
            self._new_board()

    def run(self, n: int) -> FuzzResult:
        logger = logging.getLogger("rcb4hv.emulator")
        logger.addHandler(self.errors)
        t0 = time.perf_counter()
        try:
            for i in range(1, n + 1):
                self.one(mutate(self.rng, self.frames), i)
        finally:
            logger.removeHandler(self.errors)
        self.result.seconds = time.perf_counter() - t0
        return self.result


def fuzz(n: int, seed: int = 0, frames: Sequence[bytes] | None = None) -> FuzzResult:
    """Run ``n`` inputs in this process."""
    return _Run(corpus() if frames is None else frames, seed).run(n)


def _worker(args: tuple[int, int]) -> FuzzResult:
    logging.disable(logging.WARNING)  # the board logs garbage at INFO/WARNING; errors count
    n, seed = args
    return fuzz(n, seed)


def fuzz_parallel(n: int, seed: int = 0, workers: int | None = None) -> FuzzResult:
    """Run ``n`` inputs split over ``workers`` processes (default: one per CPU)."""
    workers = workers or os.cpu_count() or 1
    shares = [n // workers + (1 if k < n % workers else 0) for k in range(workers)]
    total = FuzzResult()
    t0 = time.perf_counter()
    with ProcessPoolExecutor(workers) as pool:
        for part in pool.map(_worker, [(s, seed * 1000 + k) for k, s in enumerate(shares)]):
            total.add(part)
    total.seconds = time.perf_counter() - t0
    return total
