"""Reliability scenarios shared by the test suite (small budgets) and ``make reliability``
(``python -m bench.reliability``, larger budgets).

Four groups, one section each:

* fuzz: properties of :meth:`Board.feed` under hostile input (:func:`check_hostile_feed`,
  :func:`check_valid_feed`, :func:`feed_memory_growth`);
* link faults: every client call ends in time with the right typed error and the next call
  works (:func:`run_fault_scenario`, :data:`FAULT_SCENARIOS`);
* ROM crash safety: SIGKILL the ``rcb4hv emulate --rom`` process during a long upload
  (:func:`run_kill_cycles`);
* server load: sequential connections, stalled and flooding clients, a soak of valid
  traffic (:func:`tcp_sequential`, :func:`pty_sequential`, :func:`tcp_stalled_client`,
  :func:`tcp_flooding_client`, :func:`soak`).

Every function cleans up what it starts (processes killed and waited, sockets closed).
"""

from __future__ import annotations

import contextlib
import copy
import logging
import os
import random
import select
import signal
import socket
import statistics
import subprocess
import sys
import threading
import time
import tracemalloc
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Final

from rcb4hv import protocol as p
from rcb4hv.client import Rcb4Client
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, VirtualClock
from rcb4hv.emulator.server import TcpServer
from rcb4hv.errors import (
    ChecksumError,
    FrameError,
    NakError,
    ProtocolError,
    Rcb4TimeoutError,
    TransportError,
)
from rcb4hv.transport import Fault, FaultConfig, FaultyTransport, SerialTransport
from tests.reliability.linkfaults import LinkFault, LinkFaults
from tests.reliability.mutations import SEED_FRAMES, random_mutation

REPO: Final = Path(__file__).resolve().parents[2]

FUZZ_EXAMPLES: Final = int(os.environ.get("RCB4HV_FUZZ_EXAMPLES", "60"))
"""Hypothesis examples per fuzz test: small in ``make test``, 20000 in ``make fuzz``."""

ACK_CHECK: Final = bytes.fromhex("03 FE 01")
ACK_REPLY: Final = bytes.fromhex("04 FE 06 08")
READ_SYSREG: Final = bytes.fromhex("0A 00 20 00 00 00 00 00 02 2C")
ROMERR: Final = 1 << 10
ROM_F: Final = 1 << 1

# ============================================================================================
# fuzz: Board.feed under hostile input
# ============================================================================================

_TEMPLATES: dict[str, Board] = {}


def fresh_board(kind: str = "booted") -> Board:
    """A board on a VirtualClock: ``"booted"`` (ROM program in its main loop) or ``"idle"``
    (ROM_F clear). Copied from a cached template, so each example starts from the same state."""
    template = _TEMPLATES.get(kind)
    if template is None:
        if kind == "idle":
            template = Board(EmulatorConfig(power_on_system_register=0), clock=VirtualClock())
        else:
            template = Board(clock=VirtualClock())
            template.run_for(3.0)
        _TEMPLATES[kind] = template
    return copy.deepcopy(template)


class InternalErrors(logging.Handler):
    """Collects ERROR records of the emulator: the board answers NAK to an internal exception
    and logs it, so a crash hidden behind a NAK shows up here."""

    def __init__(self) -> None:
        super().__init__(logging.ERROR)
        self.records: list[logging.LogRecord] = []

    def emit(self, record: logging.LogRecord) -> None:
        self.records.append(record)


@contextlib.contextmanager
def no_internal_errors() -> Iterator[InternalErrors]:
    handler = InternalErrors()
    logger = logging.getLogger("rcb4hv.emulator")
    logger.addHandler(handler)
    try:
        yield handler
    finally:
        logger.removeHandler(handler)
    if handler.records:
        first = handler.records[0]
        raise AssertionError(f"emulator logged an internal error: {first.getMessage()}")


def split_replies(out: bytes) -> list[bytes]:
    """Cut the board's output into frames with the protocol core; every byte must belong to a
    whole, valid frame."""
    dec = p.FrameDecoder(max_size=p.MAX_REPLY_SIZE, resync="frame")
    dec.receive_data(out)
    frames: list[bytes] = []
    while True:
        try:
            frame = dec.next_frame()
        except ProtocolError as exc:
            raise AssertionError(f"the board emitted a malformed frame: {out.hex(' ')}") from exc
        if frame is p.NEED_DATA:
            break
        assert isinstance(frame, bytes)
        frames.append(frame)
    assert not dec.pending, f"the board emitted a partial frame: {dec.pending.hex(' ')}"
    return frames


_ACK_ONLY = frozenset(range(0x0B, 0x13))  # JUMP..12h: ACK or NAK
_DATA_CMDS = frozenset(range(0x00, 0x0B))  # MOVE..MOD: data, ACK (MOVE) or NAK


def check_reply_shape(frame: bytes) -> None:
    """A reply the spec allows: ACK/NAK ``04 CMD 06|15 SUM``, a data reply of MOVE..MOD, or the
    33-byte version reply."""
    cmd = frame[1]
    if len(frame) == 4 and frame[2] == 0x15:
        return  # NAK echoes any CMD byte
    if len(frame) == 4 and frame[2] == 0x06 and (cmd in _ACK_ONLY or cmd in _DATA_CMDS):
        return
    if cmd == 0xFE:
        assert frame == ACK_REPLY, f"bad ACK-check reply {frame.hex(' ')}"
        return
    if cmd == 0xFD:
        assert len(frame) == 0x23, f"bad version reply {frame.hex(' ')}"
        return
    assert cmd in _DATA_CMDS, f"reply {frame.hex(' ')} to a command that has no data reply"


def _nak(frame: bytes) -> bool:
    return len(frame) == 4 and frame[2] == 0x15


def settle_and_check_ack(board: Board, clock: VirtualClock) -> list[bytes]:
    """After a frame-timeout gap the board drops partial input (at most one NAK) and answers
    an ACK check exactly. Returns the frames emitted during the gap."""
    clock.advance(board.config.frame_timeout_s * 1.5)
    board.tick()
    late = split_replies(board.take_output())
    assert len(late) <= 1 and all(_nak(f) for f in late), f"after the gap: {late}"
    reply = board.feed(ACK_CHECK) + board.take_output()
    assert reply == ACK_REPLY, f"ACK check answered {reply.hex(' ')}"
    return late


def _feed_chunks(
    board: Board, clock: VirtualClock, data: bytes, chunk: int, dt: float
) -> tuple[bytes, bytes]:
    """Feed ``data`` in chunks, ``dt`` board seconds apart (below the frame timeout)."""
    inline = bytearray()
    queued = bytearray()
    for i in range(0, len(data), max(chunk, 1)):
        if dt:
            clock.advance(dt)
        inline += board.feed(data[i : i + chunk])
        queued += board.take_output()
    return bytes(inline), bytes(queued)


def check_hostile_feed(data: bytes, chunk: int, dt_fraction: float, kind: str = "booted") -> int:
    """Property of the board under any input; returns the number of replies.

    Nothing escapes, no internal error is logged; every output byte belongs to a well-formed
    reply frame of an allowed shape whose CMD byte came in; at most one reply per 3 input bytes
    (a frame is at least 3 bytes); after a frame-timeout gap the board answers an ACK check."""
    board = fresh_board(kind)
    assert isinstance(board.clock, VirtualClock)
    clock = board.clock
    dt = board.config.frame_timeout_s * dt_fraction
    with no_internal_errors():
        inline, queued = _feed_chunks(board, clock, data, chunk, dt)
        assert not queued, "a NAK for a timed-out frame without any gap"
        replies = split_replies(inline)
        for frame in replies:
            check_reply_shape(frame)
            assert frame[1] in data, f"reply {frame.hex(' ')} echoes a CMD that never came"
        assert 3 * len(replies) <= len(data), f"{len(replies)} replies to {len(data)} bytes"
        settle_and_check_ack(board, clock)
    return len(replies)


def check_valid_feed(frames: Sequence[bytes], chunk: int, dt_fraction: float) -> None:
    """Valid command frames back to back, cut anywhere: exactly one reply per frame, in order,
    each the reply its command expects (or NAK for a command that cannot run)."""
    board = fresh_board("booted")
    assert isinstance(board.clock, VirtualClock)
    clock = board.clock
    dt = board.config.frame_timeout_s * dt_fraction
    with no_internal_errors():
        inline, queued = _feed_chunks(board, clock, b"".join(frames), chunk, dt)
        assert not queued
        replies = split_replies(inline)
        assert len(replies) == len(frames), f"{len(replies)} replies to {len(frames)} commands"
        for frame, reply in zip(frames, replies, strict=True):
            command = p.decode_command(frame)
            decoded = p.decode_reply(reply, command)
            if not isinstance(decoded, p.Nak):
                assert p.encode_reply(decoded) == reply
        settle_and_check_ack(board, clock)


def feed_memory_growth(iterations: int, seed: int = 1) -> tuple[int, int, int]:
    """Feed ``iterations`` random hostile inputs (with frame-timeout gaps now and then) to one
    board under tracemalloc. Returns (bytes fed, traced memory growth after warm-up, peak
    take_output length)."""
    rng = random.Random(seed)
    board = fresh_board("booted")
    assert isinstance(board.clock, VirtualClock)
    clock = board.clock
    fed = 0
    peak_out = 0
    warmup = max(iterations // 5, 1)
    tracemalloc.start()
    try:
        base = 0
        for i in range(iterations):
            if i == warmup:
                base = tracemalloc.get_traced_memory()[0]
            data = random_mutation(rng)
            fed += len(data)
            board.feed(data)
            clock.advance(rng.choice((0.0, 0.001, board.config.frame_timeout_s * 1.5)))
            board.tick()
            peak_out = max(peak_out, len(board.take_output()))
        board.tick()
        growth = tracemalloc.get_traced_memory()[0] - base
    finally:
        tracemalloc.stop()
    return fed, growth, peak_out


@dataclass
class FuzzStats:
    inputs: int = 0
    bytes_fed: int = 0
    crashes: list[str] = field(default_factory=list)
    memory_growth: int = 0


def run_fuzz_budget(examples: int, memory_iterations: int) -> FuzzStats:
    """The fuzz properties outside pytest (for ``make reliability``): ``examples`` hypothesis
    examples per property plus a tracemalloc loop. A property failure counts as a crash."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from tests.reliability.mutations import hostile_input, mutated_frames
    from tests.strategies import command_frames

    stats = FuzzStats()
    cfg = settings(
        max_examples=examples,
        database=None,
        deadline=None,
        suppress_health_check=list(HealthCheck),
    )

    @cfg
    @given(hostile_input, st.integers(1, 40), st.sampled_from([0.0, 0.1, 0.45]), st.booleans())
    def hostile(data: bytes, chunk: int, gap: float, idle: bool) -> None:
        stats.inputs += 1
        stats.bytes_fed += len(data)
        check_hostile_feed(data, chunk, gap, "idle" if idle else "booted")

    @cfg
    @given(st.lists(st.one_of(mutated_frames, st.binary(max_size=64)), min_size=1, max_size=8))
    def stream(parts: list[bytes]) -> None:
        data = b"".join(parts)
        stats.inputs += 1
        stats.bytes_fed += len(data)
        check_hostile_feed(data, 64, 0.0)

    @cfg
    @given(st.lists(command_frames, min_size=1, max_size=6), st.integers(1, 40))
    def valid(frames: list[bytes], chunk: int) -> None:
        stats.inputs += 1
        stats.bytes_fed += sum(map(len, frames))
        check_valid_feed(frames, chunk, 0.1)

    @cfg
    @given(hostile_input)
    def decoder(data: bytes) -> None:
        stats.inputs += 1
        stats.bytes_fed += len(data)
        dec = p.FrameDecoder()
        dec.receive_data(data)
        while True:
            try:
                if dec.next_frame() is p.NEED_DATA:
                    break
            except ProtocolError:
                continue
        assert len(dec.pending) < p.MAX_FRAME_SIZE
        with contextlib.suppress(ProtocolError):
            p.decode_command(data)

    for prop in (hostile, stream, valid, decoder):
        try:
            prop()
        except Exception as exc:
            stats.crashes.append(f"{prop.__name__}: {exc!r}"[:300])
    fed, growth, _ = feed_memory_growth(memory_iterations)
    stats.inputs += memory_iterations
    stats.bytes_fed += fed
    stats.memory_growth = growth
    return stats


# ============================================================================================
# link faults
# ============================================================================================

FaultKind = Fault | LinkFault


@dataclass(frozen=True)
class FaultScenario:
    """One injected fault and the outcome the client must report."""

    name: str
    fault: FaultKind
    expected: tuple[type[BaseException], ...] | None  # None: the call succeeds
    call: str = "read"  # "read" (read RAM), "write" (write RAM), "version"


_ERR_CORRUPT: Final = (ChecksumError, FrameError)

FAULT_SCENARIOS: Final[tuple[FaultScenario, ...]] = (
    FaultScenario("drop request", Fault.DROP_REQUEST, (Rcb4TimeoutError,)),
    FaultScenario("drop request (write)", Fault.DROP_REQUEST, (Rcb4TimeoutError,), "write"),
    FaultScenario("corrupt request", Fault.CORRUPT_REQUEST, (NakError,)),
    FaultScenario("corrupt request (write)", Fault.CORRUPT_REQUEST, (NakError,), "write"),
    FaultScenario("drop reply", Fault.DROP_REPLY, (Rcb4TimeoutError,)),
    FaultScenario("drop reply (write)", Fault.DROP_REPLY, (Rcb4TimeoutError,), "write"),
    FaultScenario("drop reply byte", Fault.DROP_BYTE, (Rcb4TimeoutError, *_ERR_CORRUPT)),
    FaultScenario("truncate reply", Fault.TRUNCATE_REPLY, (Rcb4TimeoutError,)),
    FaultScenario("corrupt reply", Fault.CORRUPT_REPLY, _ERR_CORRUPT),
    FaultScenario("corrupt version reply", Fault.CORRUPT_REPLY, _ERR_CORRUPT, "version"),
    FaultScenario("delay reply past timeout", Fault.DELAY_REPLY, (Rcb4TimeoutError,)),
    FaultScenario("junk before reply", Fault.EXTRA_BEFORE, None),
    FaultScenario("junk after reply", Fault.EXTRA_AFTER, None),
    FaultScenario("injected disconnect", Fault.DISCONNECT, (TransportError,)),
    FaultScenario("duplicate reply", LinkFault.DUPLICATE_REPLY, None),
    FaultScenario("split reply, slow bytes", LinkFault.SPLIT_REPLY, None, "version"),
    FaultScenario("split request, short gap", LinkFault.SPLIT_REQUEST, None),
    FaultScenario("split request, gap > frame timeout", LinkFault.SPLIT_REQUEST_LONG, (NakError,)),
    FaultScenario("delay reply within timeout", LinkFault.DELAY_SHORT, None),
    FaultScenario("peer drops the connection", LinkFault.PEER_DISCONNECT, (TransportError,)),
)
"""Every fault the suite injects, with the typed error it must produce."""

SLACK: Final = 0.1
"""Seconds a failing call may overrun its timeout in ``make reliability`` (its figure: a
quiet 2-core box)."""
LOADED_SLACK: Final = 1.0
"""The same for the tests, which must pass on a loaded runner too (load 4 on two cores delays
a wake-up by a good part of a second); a hang still fails them."""


@dataclass
class TcpRig:
    """A board served by an in-process TcpServer and a client over ``socket://`` wrapped in
    both fault layers: ``faults`` (rcb4hv.transport.faults) outside ``link`` (LinkFaults)."""

    board: Board
    server: TcpServer
    link: LinkFaults
    faults: FaultyTransport
    client: Rcb4Client

    def close(self) -> None:
        self.client.close()
        self.server.stop()
        self.board.close()


@contextlib.contextmanager
def tcp_rig(timeout: float = 0.25, seed: int = 0, frame_timeout: float = 0.05) -> Iterator[TcpRig]:
    # A 50 ms frame timeout (the board's is 20 ms) leaves a split request's short gap a wide
    # margin on a quiet machine; the long gap scales with it. The tests widen both (see
    # test_rel_faults) to hold on a loaded one.
    board = Board(EmulatorConfig(frame_timeout_s=frame_timeout), clock=RealClock(speed=10.0))
    server = TcpServer(board, "127.0.0.1", 0)
    rig: TcpRig | None = None
    try:
        server.start()
        host, port = server.address
        inner = SerialTransport.open(f"socket://{host}:{port}")
        link = LinkFaults(inner, frame_timeout=board.config.frame_timeout_s, server=server)
        faults = FaultyTransport(link, FaultConfig(seed=seed, delay_s=timeout + 0.15))
        rig = TcpRig(board, server, link, faults, Rcb4Client(faults, timeout=timeout))
        yield rig
    finally:
        if rig is not None:
            rig.client.close()
        server.stop()
        board.close()


@dataclass
class FaultOutcome:
    scenario: str
    got: str  # "ok" or the exception's class name
    elapsed: float
    ok: bool
    why: str = ""


def _do_call(client: Rcb4Client, call: str, value: bytes) -> None:
    if call == "write":
        client.write_ram(0x0464, value)
    elif call == "version":
        assert client.get_version_info().text.startswith("CB-4")
    else:
        assert client.read_ram(0x0462, len(value)) == value


def run_fault_scenario(
    rig: TcpRig, scenario: FaultScenario, value: bytes, slack: float = SLACK
) -> FaultOutcome:
    """Inject ``scenario.fault`` into one call, check its outcome and time (``slack`` past
    the timeout at most), then check that calls on the (healed) link work again. ``value`` is
    in RAM 0462 before the call."""
    client = rig.client
    timeout = client.timeout
    if isinstance(scenario.fault, Fault):
        rig.faults.inject(scenario.fault)
    else:
        rig.link.inject(scenario.fault)
    before = rig.faults.transactions
    got = "ok"
    error: BaseException | None = None
    t0 = time.monotonic()
    try:
        _do_call(client, scenario.call, value)
    except Exception as exc:
        error = exc
        got = type(exc).__name__
    elapsed = time.monotonic() - t0
    rig.faults.clear()
    rig.link.clear()
    why = ""
    if scenario.expected is None and error is not None:
        why = f"expected success, got {error!r}"
    elif scenario.expected is not None and not isinstance(error, scenario.expected):
        want = "/".join(e.__name__ for e in scenario.expected)
        why = f"expected {want}, got {error!r}"
    elif elapsed > timeout + slack:
        why = f"took {elapsed:.3f} s with a timeout of {timeout} s"
    elif rig.faults.transactions - before != 1:
        why = f"{rig.faults.transactions - before} transactions: the client retried"
    if not why:
        why = _recover(rig, value, scenario.fault, reconnect=isinstance(error, TransportError))
    return FaultOutcome(scenario.name, got, elapsed, not why, why)


def _recover(rig: TcpRig, value: bytes, fault: FaultKind, *, reconnect: bool) -> str:
    """Heal the link (reconnect after a disconnect, let late bytes land) and check the next
    calls succeed with the right data."""
    client = rig.client
    late = rig.faults.config.delay_s if fault is Fault.DELAY_REPLY else 0.0
    time.sleep(max(late, 3 * rig.board.config.frame_timeout_s) + 0.02)
    if reconnect or not rig.faults.is_open:
        client.reconnect()
    try:
        client.acknowledge_check()
        client.write_ram(0x0462, value)
        if client.read_ram(0x0462, len(value)) != value:
            return "the next read returned other data"
        if not client.get_version_info().text.startswith("CB-4"):
            return "the next version request failed"
    except Exception as exc:
        return f"the next call on a healthy link failed: {exc!r}"
    return ""


def run_fault_matrix(
    rounds: int = 1, seed: int = 0, scenarios: Sequence[FaultScenario] = FAULT_SCENARIOS
) -> list[FaultOutcome]:
    """Every scenario ``rounds`` times (in a seeded random order) on one TCP rig."""
    rng = random.Random(seed)
    outcomes: list[FaultOutcome] = []
    with tcp_rig(seed=seed) as rig:
        rig.client.acknowledge_check(timeout=2.0)
        order = [s for _ in range(rounds) for s in scenarios]
        rng.shuffle(order)
        for scenario in order:
            value = rng.randbytes(4)
            rig.client.write_ram(0x0462, value)
            outcomes.append(run_fault_scenario(rig, scenario, value))
    return outcomes


# ============================================================================================
# subprocess emulator (for SIGKILL, /proc/<pid>/fd and VmRSS)
# ============================================================================================


class EmulatorProcess:
    """``rcb4hv emulate`` in a subprocess; :meth:`kill` (SIGKILL) or :meth:`stop` (SIGTERM)."""

    def __init__(self, *args: str, startup_timeout: float = 20.0) -> None:
        self.proc = subprocess.Popen(
            [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "emulate", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            cwd=REPO,
        )
        try:
            self.line = self._readline(startup_timeout)
        except BaseException:
            self.kill()
            raise
        kind, _, where = self.line.partition(" ")
        self.kind = kind
        self.where = where

    def _readline(self, timeout: float) -> str:
        assert self.proc.stdout is not None
        fd = self.proc.stdout.fileno()
        buf = b""
        deadline = time.monotonic() + timeout
        while b"\n" not in buf:
            left = deadline - time.monotonic()
            if left <= 0:
                raise TimeoutError("the emulator did not print its address")
            ready, _, _ = select.select([fd], [], [], left)
            if ready:
                chunk = os.read(fd, 256)
                if not chunk:
                    raise RuntimeError(f"the emulator exited (code {self.proc.wait()})")
                buf += chunk
        return buf.split(b"\n", 1)[0].decode().strip()

    @property
    def pid(self) -> int:
        return self.proc.pid

    @property
    def tcp(self) -> tuple[str, int]:
        host, _, port = self.where.rpartition(":")
        return host, int(port)

    @property
    def url(self) -> str:
        if self.kind == "TCP":
            host, port = self.tcp
            return f"socket://{host}:{port}"
        return self.where

    def fd_count(self) -> int:
        return len(os.listdir(f"/proc/{self.pid}/fd"))

    def rss_kb(self) -> int:
        for line in Path(f"/proc/{self.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
        raise RuntimeError("no VmRSS")

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGKILL)
        self.proc.wait(timeout=10)
        if self.proc.stdout is not None:
            self.proc.stdout.close()

    def stop(self) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            code = self.proc.wait(timeout=10)
        finally:
            self.kill()
        return code

    def __enter__(self) -> EmulatorProcess:
        return self

    def __exit__(self, *exc: object) -> None:
        self.kill()


# ============================================================================================
# ROM image crash safety
# ============================================================================================

PAGE: Final = 64
"""The atomic unit of a ROM upload: one MOVE of 64 bytes (the client's ROM_WRITE_CHUNK). A
128-byte EEPROM page cannot be written by one MOVE (its literal holds at most 121 bytes), so a
128-byte page is two MOVEs; the prefix check below pins down how such a page may look."""
UPLOAD_BASE: Final = 0x0B80 + 2048 * 89  # motion 90: never run by the default image
UPLOAD_SIZE: Final = 16 * 1024


def page_pattern(generation: int, page: int) -> bytes:
    """Distinct content for each (generation, page): no two pages or generations alike."""
    rng = random.Random(generation * 1_000_003 + page)
    head = generation.to_bytes(2, "little") + page.to_bytes(2, "little")
    return head + rng.randbytes(PAGE - 4)


@dataclass
class KillStats:
    cycles: int = 0
    pages_checked: int = 0
    torn_pages: int = 0  # a 64-byte page neither old nor new, or new pages not a prefix
    outside_changed: int = 0  # bytes outside the upload region that changed
    pages_persisted: int = 0  # new pages found on disk after the kills (progress)
    mixed_128: int = 0  # 128-byte pages with one 64-byte half new and one old (allowed)
    boot_failures: int = 0
    stale_temp_files: int = 0
    problems: list[str] = field(default_factory=list)


def _upload(url: str, generation: int, stop: threading.Event, done: list[int]) -> None:
    try:
        with Rcb4Client.open(url, timeout=1.0) as client:
            for page in range(UPLOAD_SIZE // PAGE):
                if stop.is_set():
                    return
                data = p.Data(page_pattern(generation, page))
                client.move(p.Rom(UPLOAD_BASE + page * PAGE), data)
                done[0] = page + 1
    except (TransportError, Rcb4TimeoutError, ProtocolError, NakError):
        return  # the emulator was killed under us


def check_boots(url: str, run_s: float = 0.3) -> str:
    """ACK check, read the system register, run a bit, no ROMERR. Returns a problem or ""."""
    try:
        with Rcb4Client.open(url, timeout=1.0) as client:
            client.acknowledge_check()
            first = int.from_bytes(client.read_ram(0x0000, 2), "little")
            time.sleep(run_s)
            client.acknowledge_check()
            reg = int.from_bytes(client.read_ram(0x0000, 2), "little")
    except Exception as exc:
        return f"boot check failed: {exc!r}"
    if (first | reg) & ROMERR:
        return f"ROMERR set after boot (system register {first:04X} then {reg:04X})"
    return ""


def check_image(old: bytes, new: bytes, generation: int) -> tuple[int, int, int, int, str]:
    """Compare the image on disk after a kill with the one before the cycle.

    Returns (torn pages, bytes changed outside the region, new pages, mixed 128-byte pages,
    problem). The upload writes pages in order, a flush snapshots the whole image, so the file
    must hold generation ``generation`` on a prefix of the pages and the old content after it."""
    if len(new) != p.ROM_SIZE:
        return 0, 0, 0, 0, f"image of {len(new)} bytes"
    lo, hi = UPLOAD_BASE, UPLOAD_BASE + UPLOAD_SIZE
    outside = sum(a != b for a, b in zip(old[:lo] + old[hi:], new[:lo] + new[hi:], strict=True))
    states: list[str] = []
    torn = 0
    for page in range(UPLOAD_SIZE // PAGE):
        a = lo + page * PAGE
        got = new[a : a + PAGE]
        if got == page_pattern(generation, page):
            states.append("n")
        elif got == old[a : a + PAGE]:
            states.append("o")
        else:
            states.append("x")
            torn += 1
    s = "".join(states)
    n_new = s.count("n")
    ordered = s.replace("x", "").rstrip("o")
    if ordered != "n" * len(ordered):
        torn += 1
        problem = "new pages are not a prefix: " + s
    else:
        problem = "" if not torn else f"{torn} torn page(s)"
    mixed = sum(1 for i in range(0, len(s) - 1, 2) if s[i] != s[i + 1])
    return torn, outside, n_new, mixed, problem


def run_kill_cycles(
    rom: Path, cycles: int, seed: int = 0, max_delay: float = 1.0, speed: float = 5.0
) -> KillStats:
    """Start ``rcb4hv emulate --tcp 127.0.0.1:0 --rom FILE``, upload UPLOAD_SIZE bytes of ROM
    page by page, SIGKILL it at a random moment; check the image after each kill and that the
    board boots from it; repeat."""
    rng = random.Random(seed)
    stats = KillStats()
    args = ("--tcp", "127.0.0.1:0", "--rom", str(rom), "--speed", str(speed))
    old: bytes | None = rom.read_bytes() if rom.exists() else None
    for generation in range(1, cycles + 1):
        with EmulatorProcess(*args) as emu:
            if old is None:
                old = rom.read_bytes()
            problem = check_boots(emu.url)
            if problem:
                stats.boot_failures += 1
                stats.problems.append(f"cycle {generation}: {problem}")
            stop = threading.Event()
            done = [0]
            writer = threading.Thread(target=_upload, args=(emu.url, generation, stop, done))
            writer.start()
            if rng.random() < 0.5:  # at a random moment
                time.sleep(rng.uniform(0.0, max_delay))
            else:  # just after a random page (often during a flush)
                target = rng.randrange(UPLOAD_SIZE // PAGE)
                deadline = time.monotonic() + 10.0
                while done[0] < target and writer.is_alive() and time.monotonic() < deadline:
                    time.sleep(0.001)
                time.sleep(rng.uniform(0.0, 0.01))
            emu.kill()
            stop.set()
            writer.join(timeout=10)
        new = rom.read_bytes()
        torn, outside, n_new, mixed, problem = check_image(old, new, generation)
        stats.cycles += 1
        stats.pages_checked += UPLOAD_SIZE // PAGE
        stats.torn_pages += torn
        stats.outside_changed += outside
        stats.pages_persisted += n_new
        stats.mixed_128 += mixed
        if problem or outside:
            stats.problems.append(f"cycle {generation}: {problem} outside={outside}")
        if n_new > done[0]:
            stats.problems.append(f"cycle {generation}: {n_new} pages on disk, {done[0]} acked")
        old = new
    with EmulatorProcess(*args) as emu:
        problem = check_boots(emu.url)
        if problem:
            stats.boot_failures += 1
            stats.problems.append(f"final boot: {problem}")
    stats.stale_temp_files = len(list(rom.parent.glob(f".{rom.name}.*.tmp")))
    return stats


# ============================================================================================
# server load
# ============================================================================================


@dataclass
class LoadStats:
    connections: int = 0
    failures: int = 0
    latencies: list[float] = field(default_factory=list)
    fd_before: int = 0
    fd_after: int = 0
    rss_before_kb: int = 0
    rss_after_kb: int = 0
    rss_peak_kb: int = 0
    notes: list[str] = field(default_factory=list)

    def p99(self) -> float:
        if not self.latencies:
            return float("nan")
        if len(self.latencies) < 2:
            return self.latencies[0]
        return statistics.quantiles(self.latencies, n=100, method="inclusive")[98]


def _recv_exact(sock: socket.socket, n: int, timeout: float) -> bytes:
    deadline = time.monotonic() + timeout
    buf = b""
    while len(buf) < n:
        left = deadline - time.monotonic()
        if left <= 0:
            break
        sock.settimeout(left)
        try:
            chunk = sock.recv(n - len(buf))
        except TimeoutError:
            break
        if not chunk:
            break
        buf += chunk
    return buf


def _tcp_ack(addr: tuple[str, int], timeout: float = 2.0) -> tuple[bool, float]:
    t0 = time.monotonic()
    with socket.create_connection(addr, timeout=timeout) as s:
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        s.sendall(ACK_CHECK)
        ok = _recv_exact(s, 4, timeout) == ACK_REPLY
    return ok, time.monotonic() - t0


def _settled_fds(emu: EmulatorProcess, limit: int, wait: float = 2.0) -> int:
    """The server's fd count, given a moment to close a dropped connection."""
    deadline = time.monotonic() + wait
    n = emu.fd_count()
    while n > limit and time.monotonic() < deadline:
        time.sleep(0.02)
        n = emu.fd_count()
    return n


def tcp_sequential(emu: EmulatorProcess, n: int) -> LoadStats:
    """``n`` clients one after another: connect, ACK check, close."""
    stats = LoadStats(fd_before=emu.fd_count(), rss_before_kb=emu.rss_kb())
    for _ in range(n):
        ok, dt = _tcp_ack(emu.tcp)
        stats.connections += 1
        stats.failures += not ok
        stats.latencies.append(dt)
        stats.rss_peak_kb = max(stats.rss_peak_kb, emu.rss_kb())
    stats.fd_after = _settled_fds(emu, stats.fd_before)
    stats.rss_after_kb = emu.rss_kb()
    return stats


def pty_sequential(emu: EmulatorProcess, n: int) -> LoadStats:
    """``n`` opens of the pty (1,250,000 baud, 8E1), each an ACK check, then close."""
    import serial

    stats = LoadStats(fd_before=emu.fd_count(), rss_before_kb=emu.rss_kb())
    for _ in range(n):
        t0 = time.monotonic()
        port = serial.Serial(emu.where, 1250000, parity=serial.PARITY_EVEN, timeout=2.0)
        try:
            port.write(ACK_CHECK)
            ok = port.read(4) == ACK_REPLY
        finally:
            port.close()
        stats.connections += 1
        stats.failures += not ok
        stats.latencies.append(time.monotonic() - t0)
        stats.rss_peak_kb = max(stats.rss_peak_kb, emu.rss_kb())
    stats.fd_after = _settled_fds(emu, stats.fd_before)
    stats.rss_after_kb = emu.rss_kb()
    return stats


def tcp_stalled_client(emu: EmulatorProcess, stall_s: float = 0.3) -> LoadStats:
    """A client sends a partial frame and stalls (never reads, never closes). The board NAKs
    the partial frame after its frame timeout; the next client is served at once and the
    stalled one is cut off (the server serves one connection at a time, the newest)."""
    stats = LoadStats(fd_before=emu.fd_count(), rss_before_kb=emu.rss_kb())
    stalled = socket.create_connection(emu.tcp, timeout=2.0)
    try:
        stalled.sendall(bytes.fromhex("0A 00 20 00"))
        nak = _recv_exact(stalled, 4, 2.0)
        if nak != bytes.fromhex("04 00 15 19"):
            stats.notes.append(f"partial frame answered {nak.hex(' ')}, not NAK 04 00 15 19")
            stats.failures += 1
        stalled.sendall(bytes.fromhex("0A 00"))  # and stall in the middle of a frame
        time.sleep(stall_s)
        ok, dt = _tcp_ack(emu.tcp)
        stats.connections += 2
        stats.failures += not ok
        stats.latencies.append(dt)
        stalled.settimeout(2.0)
        try:
            rest = stalled.recv(64)
        except OSError:
            rest = b""
        if rest not in (b"", bytes.fromhex("04 00 15 19")):
            stats.notes.append(f"the stalled client got {rest.hex(' ')}")
        if rest and stalled.recv(64) != b"":
            stats.failures += 1
            stats.notes.append("the stalled client was not cut off")
    finally:
        stalled.close()
    stats.fd_after = _settled_fds(emu, stats.fd_before)
    stats.rss_after_kb = emu.rss_kb()
    return stats


def tcp_flooding_client(emu: EmulatorProcess, flood_s: float = 1.0, seed: int = 0) -> LoadStats:
    """A client floods random garbage and hostile frames without reading; meanwhile other
    clients connect: each is answered in bounded time and the flooder is cut off."""
    rng = random.Random(seed)
    stats = LoadStats(fd_before=emu.fd_count(), rss_before_kb=emu.rss_kb())
    blob = b"".join(random_mutation(rng) for _ in range(2000))
    stop = threading.Event()
    flooded = [0]
    cut_off = threading.Event()

    def flood() -> None:
        with socket.create_connection(emu.tcp, timeout=2.0) as s:
            s.settimeout(0.5)
            while not stop.is_set():
                try:
                    flooded[0] += s.send(blob)
                except TimeoutError:
                    continue
                except OSError:
                    cut_off.set()
                    return

    flooder = threading.Thread(target=flood, name="flooder")
    flooder.start()
    try:
        t_end = time.monotonic() + flood_s
        time.sleep(min(0.2, flood_s / 2))
        while time.monotonic() < t_end:
            stats.rss_peak_kb = max(stats.rss_peak_kb, emu.rss_kb())
            ok, dt = _tcp_ack(emu.tcp)
            stats.connections += 1
            stats.failures += not ok
            stats.latencies.append(dt)
            if cut_off.wait(0.2):
                break
    finally:
        stop.set()
        flooder.join(timeout=10)
    stats.notes.append(f"flooder sent {flooded[0]} bytes; cut off: {cut_off.is_set()}")
    if not cut_off.is_set():
        stats.failures += 1
    stats.fd_after = _settled_fds(emu, stats.fd_before)
    stats.rss_after_kb = emu.rss_kb()
    return stats


SOAK_CALLS: Final[tuple[Callable[[Rcb4Client, random.Random], object], ...]] = (
    lambda c, r: c.acknowledge_check(),
    lambda c, r: c.write_ram(0x0462, r.randbytes(r.randint(1, 40))),
    lambda c, r: c.read_ram(0x0090, r.randint(1, 128)),
    lambda c, r: c.read_rom(0x0B80, r.randint(1, 128)),
    lambda c, r: c.get_version_info(),
    lambda c, r: c.run_single_servo(r.choice((0, 2, 3, 4)), 10, r.randint(5000, 10000)),
    lambda c, r: c.add(p.Ram(0x0462), p.Data(b"\x01\x00"), 2),
)


def soak(emu: EmulatorProcess, duration_s: float, seed: int = 0) -> LoadStats:
    """Valid traffic from one client for ``duration_s``: every call must succeed; per-call
    latency, fd count and RSS are recorded."""
    rng = random.Random(seed)
    stats = LoadStats(fd_before=emu.fd_count())
    with Rcb4Client.open(emu.url, timeout=1.0) as client:
        client.acknowledge_check()
        stats.connections = 1
        # warm up, then take the baseline RSS
        for _ in range(200):
            rng.choice(SOAK_CALLS)(client, rng)
        stats.rss_before_kb = emu.rss_kb()
        t_end = time.monotonic() + duration_s
        next_sample = 0.0
        while time.monotonic() < t_end:
            call = rng.choice(SOAK_CALLS)
            t0 = time.monotonic()
            try:
                call(client, rng)
            except Exception as exc:
                stats.failures += 1
                stats.notes.append(repr(exc))
            stats.latencies.append(time.monotonic() - t0)
            if t0 >= next_sample:
                stats.rss_peak_kb = max(stats.rss_peak_kb, emu.rss_kb())
                next_sample = t0 + 0.2
    stats.fd_after = _settled_fds(emu, stats.fd_before)
    stats.rss_after_kb = emu.rss_kb()
    stats.rss_peak_kb = max(stats.rss_peak_kb, stats.rss_after_kb)
    return stats


def check_load(stats: LoadStats, *, rss_growth_kb: int = 4096) -> list[str]:
    """Problems in a load run: failed calls, fd growth, RSS growth."""
    problems = [f"{stats.failures} failed call(s): {stats.notes}"] if stats.failures else []
    if stats.fd_after > stats.fd_before:
        problems.append(f"fds grew from {stats.fd_before} to {stats.fd_after}")
    if stats.rss_before_kb and stats.rss_after_kb - stats.rss_before_kb > rss_growth_kb:
        problems.append(f"RSS grew from {stats.rss_before_kb} to {stats.rss_after_kb} kB")
    return problems


__all__ = [
    "FAULT_SCENARIOS",
    "FUZZ_EXAMPLES",
    "SEED_FRAMES",
    "EmulatorProcess",
    "FaultOutcome",
    "FaultScenario",
    "KillStats",
    "LoadStats",
    "check_hostile_feed",
    "check_image",
    "check_load",
    "check_valid_feed",
    "feed_memory_growth",
    "pty_sequential",
    "run_fault_matrix",
    "run_fault_scenario",
    "run_kill_cycles",
    "soak",
    "tcp_flooding_client",
    "tcp_sequential",
    "tcp_stalled_client",
]
