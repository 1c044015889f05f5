"""Fault injection at the transport: a :class:`Transport` wrapper that loses, corrupts, delays
and adds bytes, or drops the link, so tests (and ``--port fault://...``) can prove that every
call ends in time with the right exception and that the next call still works.

Faults are chosen once per transaction (a transaction starts with each ``write``):

* deterministically, from a script: ``faulty.inject(Fault.CORRUPT_REPLY, None, Fault.DROP_REPLY)``
  applies those faults to the next three requests (``None`` = no fault); the script wins
  over the probabilities;
* at random, with the per-fault probabilities of :class:`FaultConfig` and a seeded RNG, so
  a run is reproducible.

Every applied fault is appended to :attr:`FaultyTransport.history` as ``(transaction, fault)``.

The wrapper needs no protocol knowledge beyond one fact: the first byte of a reply is its
length, which tells it where the reply ends (for the truncate / corrupt / extra-after faults).

URL form (see :func:`parse_fault_url`): ``fault://drop_reply=0.05,corrupt_reply=0.05,seed=7@URL``,
served by the pyserial URL handler :mod:`rcb4hv.transport.protocol_fault`.
"""

from __future__ import annotations

import enum
import logging
import random
import time
from collections import deque
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Final

from rcb4hv.errors import TransportError
from rcb4hv.transport.base import Transport

__all__ = ["FAULT_SCHEME", "Fault", "FaultConfig", "FaultyTransport", "parse_fault_url"]

log = logging.getLogger(__name__)

FAULT_SCHEME: Final = "fault://"


class Fault(enum.Enum):
    """One fault, applied to one transaction."""

    DROP_REQUEST = "drop_request"
    """The request never reaches the board: no reply (timeout)."""
    CORRUPT_REQUEST = "corrupt_request"
    """The request's checksum byte is flipped: the board NAKs (or ignores) it."""
    DROP_REPLY = "drop_reply"
    """The whole reply is lost (timeout)."""
    DROP_BYTE = "drop_byte"
    """One byte inside the reply is lost (timeout: incomplete reply)."""
    TRUNCATE_REPLY = "truncate_reply"
    """The reply's last byte is lost (timeout: incomplete reply)."""
    CORRUPT_REPLY = "corrupt_reply"
    """One reply byte after CMD is flipped (checksum error)."""
    DELAY_REPLY = "delay_reply"
    """The reply is held back ``delay_s`` (timeout if longer than the call's timeout; the
    late reply then arrives during a later call, which must discard it)."""
    EXTRA_BEFORE = "extra_before"
    """Junk bytes arrive before the reply (they must be discarded; the call succeeds)."""
    EXTRA_AFTER = "extra_after"
    """Junk bytes arrive just after the reply (the next call must discard them)."""
    DISCONNECT = "disconnect"
    """The link fails once: the read raises TransportError; later calls work again."""


@dataclass(frozen=True)
class FaultConfig:
    """Per-transaction fault probabilities (each 0..1, checked in :class:`Fault` order, at most
    one fault per transaction), the RNG seed and the fault parameters."""

    rates: Mapping[Fault, float] = field(default_factory=dict)
    seed: int | None = 0
    delay_s: float = 0.25
    junk_max: int = 6

    def __post_init__(self) -> None:
        rates = {Fault(k): float(v) for k, v in dict(self.rates).items()}
        for k, v in rates.items():
            if not 0.0 <= v <= 1.0:
                raise ValueError(f"probability of {k.value} must be within 0..1, not {v}")
        if sum(rates.values()) > 1.0 + 1e-9:
            raise ValueError("fault probabilities add up to more than 1")
        if self.delay_s < 0:
            raise ValueError("delay_s must be >= 0")
        if not 1 <= self.junk_max <= 64:
            raise ValueError("junk_max must be within 1..64")
        object.__setattr__(self, "rates", rates)

    @classmethod
    def parse(cls, spec: str) -> FaultConfig:
        """Parse ``"drop_reply=0.1,corrupt_reply=0.05,seed=3,delay_s=0.2"``."""
        rates: dict[Fault, float] = {}
        kwargs: dict[str, float | int | None] = {}
        for item in filter(None, (s.strip() for s in spec.split(","))):
            key, sep, value = item.partition("=")
            if not sep:
                raise ValueError(f"fault option {item!r} is not key=value")
            key = key.strip().lower()
            try:
                if key == "seed":
                    kwargs["seed"] = None if value == "none" else int(value)
                elif key in ("delay_s", "delay"):
                    kwargs["delay_s"] = float(value)
                elif key == "junk_max":
                    kwargs["junk_max"] = int(value)
                else:
                    rates[Fault(key)] = float(value)
            except ValueError as exc:
                names = ", ".join(f.value for f in Fault)
                raise ValueError(
                    f"bad fault option {item!r} (faults: {names}; also seed, delay_s, junk_max)"
                ) from exc
        return cls(rates=rates, **kwargs)  # type: ignore[arg-type]


def parse_fault_url(url: str) -> tuple[FaultConfig, str]:
    """Split ``fault://SPEC@INNER_URL`` into its config and the inner URL."""
    if not url.startswith(FAULT_SCHEME):
        raise ValueError(f"not a {FAULT_SCHEME} URL: {url!r}")
    spec, sep, inner = url[len(FAULT_SCHEME) :].partition("@")
    if not sep or not inner:
        raise ValueError(f"expected {FAULT_SCHEME}SPEC@URL, e.g. fault://drop_reply=0.1@rcb4emu://")
    return FaultConfig.parse(spec), inner


class FaultyTransport(Transport):
    """Wrap ``inner`` and inject faults (see the module docstring)."""

    def __init__(
        self,
        inner: Transport,
        config: FaultConfig | None = None,
        script: Iterable[Fault | None] = (),
    ) -> None:
        self.inner = inner
        self.config = config or FaultConfig()
        self.url = f"{FAULT_SCHEME}…@{inner.url}"
        self.rng = random.Random(self.config.seed)
        self.history: list[tuple[int, Fault]] = []
        self.transactions = 0
        self._script: deque[Fault | None] = deque(script)
        self._active: Fault | None = None
        self._seen = 0  # reply bytes seen from inner in this transaction
        self._size = 0  # the reply's size byte, once seen
        self._target = 0  # index of the byte the fault hits
        self._sent_at = 0.0
        self._rx = bytearray()
        self._held: deque[tuple[float, bytes]] = deque()

    # ------------------------------------------------------------------ control

    def inject(self, *faults: Fault | None) -> None:
        """Apply ``faults`` to the next transactions, in order (None = a clean transaction)."""
        self._script.extend(faults)

    def clear(self) -> None:
        """Forget scripted faults that have not run yet."""
        self._script.clear()

    def _choose(self) -> Fault | None:
        if self._script:
            return self._script.popleft()
        rates = self.config.rates
        if not rates:
            return None
        x = self.rng.random()
        for fault in Fault:
            p = rates.get(fault, 0.0)
            if x < p:
                return fault
            x -= p
        return None

    def _junk(self) -> bytes:
        n = self.rng.randint(1, self.config.junk_max)
        return bytes(self.rng.getrandbits(8) for _ in range(n))

    # ------------------------------------------------------------------ Transport

    @property
    def is_open(self) -> bool:
        return self.inner.is_open

    def write(self, data: bytes) -> None:
        self.transactions += 1
        fault = self._choose()
        self._active, self._seen, self._size = fault, 0, 0
        self._sent_at = time.monotonic()
        if fault is not None:
            self.history.append((self.transactions, fault))
            log.debug("transaction %d: injecting %s", self.transactions, fault.value)
        if fault is Fault.DROP_REQUEST:
            return
        if fault is Fault.CORRUPT_REQUEST and data:
            data = data[:-1] + bytes((data[-1] ^ 0x5A,))
        if fault is Fault.EXTRA_BEFORE:
            self._rx += self._junk()
        self.inner.write(data)

    def read(self, size: int, deadline: float) -> bytes:
        if self._active is Fault.DISCONNECT:
            self._active = None
            raise TransportError(f"{self.url}: injected disconnect")
        while True:
            self._release()
            missing = size - len(self._rx)
            if missing <= 0:
                break
            until = min(deadline, self._held[0][0]) if self._held else deadline
            chunk = self.inner.read(missing, until)  # at least one look, even at the deadline
            if chunk:
                self._process(chunk)
            elif time.monotonic() >= deadline:
                break
        out = bytes(self._rx[:size])
        del self._rx[:size]
        return out

    def pending(self) -> int:
        """How many bytes a read returns without waiting (those through the faults)."""
        self._release()
        return len(self._rx)

    def reset_input(self) -> None:
        self.inner.reset_input()
        self._release()
        self._rx.clear()

    def close(self) -> None:
        self.inner.close()

    def set_baudrate(self, baudrate: int) -> None:
        self.inner.set_baudrate(baudrate)

    def reopen(self) -> None:
        self._rx.clear()
        self._held.clear()
        self.inner.reopen()

    # ------------------------------------------------------------------ internals

    def _release(self) -> None:
        now = time.monotonic()
        while self._held and self._held[0][0] <= now:
            self._rx += self._held.popleft()[1]

    def _process(self, chunk: bytes) -> None:
        fault = self._active
        start = self._seen
        self._seen += len(chunk)
        if start == 0 and chunk:
            self._size = chunk[0]
            if fault is Fault.DROP_BYTE:
                self._target = self.rng.randrange(max(self._size, 1))
            elif fault is Fault.CORRUPT_REPLY:
                self._target = self.rng.randrange(2, max(self._size, 3))
            elif fault is Fault.TRUNCATE_REPLY:
                self._target = max(self._size - 1, 0)
        if fault is None or fault in (Fault.DROP_REQUEST, Fault.EXTRA_BEFORE):
            self._rx += chunk
            return
        if fault is Fault.DROP_REPLY:
            return
        if fault is Fault.DELAY_REPLY:
            self._held.append((self._sent_at + self.config.delay_s, chunk))
            return
        out = bytearray()
        for i, b in enumerate(chunk, start):
            if i == self._target and fault in (Fault.DROP_BYTE, Fault.TRUNCATE_REPLY):
                continue
            if i == self._target and fault is Fault.CORRUPT_REPLY:
                b ^= 1 << self.rng.randrange(8)
            out.append(b)
        self._rx += out
        if fault is Fault.EXTRA_AFTER and start < self._size <= self._seen:
            self._held.append((time.monotonic() + 0.0005, self._junk()))
