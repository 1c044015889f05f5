"""An emulated ICS bus: bytes in, bytes out, the echo first, replies on the bus's clock.

:class:`EmulatedBus` is what a pty, a TCP socket or ``icsemu://`` serves (the board
emulator's servers drive it through :meth:`feed`, :meth:`tick`, :meth:`take_output` and
:meth:`poll_timeout`, as they drive a board), and what a board's SIO line talks to for 0Eh
(:meth:`exchange`).

Rules:

* every byte the host sends comes back first (the half-duplex echo: the adapter hears the
  wire, whether or not a servo is there);
* a byte with the top bit set starts a command (ICS data bytes are 7-bit), so garbage and
  half commands are dropped at the next command byte; data bytes outside a command are
  ignored; nothing the host sends raises;
* the servo a command addresses answers after its delay (0.35 s for an EEPROM write, scaled
  by the clock); an absent ID, a busy servo, or a servo at another baud rate than the host's
  (when the host's rate is known: ``host_baud``) stays silent;
* ID commands go to every servo on the bus: an ID write renumbers them all, an ID read with
  several servos gives the collision of :attr:`IcsSettings.id_collision` (as does any
  command that two servos with one ID answer).
"""

from __future__ import annotations

import heapq
import itertools
import logging
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Final, Protocol

from rcb4hv.ics.codec import BAUD_RATES, command_length
from rcb4hv.ics.eeprom import Eeprom
from rcb4hv.ics.servo import Answer, EmulatedServo
from rcb4hv.ics.settings import IcsSettings

__all__ = ["EmulatedBus", "IcsClock", "ServeOptions", "parse_ids"]

log = logging.getLogger(__name__)

MAX_SERVOS: Final = 32  # one bus, IDs 0-31 (FACTS)


class IcsClock(Protocol):
    """The part of the emulator's clocks the bus needs (they satisfy it as they are)."""

    def now(self) -> float: ...

    def real_seconds(self, board_seconds: float) -> float: ...


@dataclass(frozen=True, slots=True)
class ServeOptions:
    """What the emulator's servers read from a served device's ``config``."""

    min_reply_latency_s: float = 0.0
    pace_replies: bool = False


def parse_ids(text: str) -> tuple[int, ...]:
    """``"0,1,5"`` -> (0, 1, 5); ValueError for anything else than distinct IDs 0..31."""
    try:
        ids = tuple(int(p) for p in text.split(",") if p.strip())
    except ValueError:
        raise ValueError(f"IDs are comma-separated numbers 0..31, not {text!r}") from None
    if not ids or any(not 0 <= i <= 31 for i in ids) or len(set(ids)) != len(ids):
        raise ValueError(f"IDs are distinct numbers 0..31, not {text!r}")
    return ids


class EmulatedBus:
    """One ICS wire with emulated servos on it."""

    def __init__(
        self,
        servos: Iterable[EmulatedServo] = (),
        *,
        clock: IcsClock,
        settings: IcsSettings | None = None,
        baud: int = 115200,
        options: ServeOptions | None = None,
    ) -> None:
        if baud not in BAUD_RATES:
            raise ValueError(f"ICS baud rate {baud} is not one of {BAUD_RATES}")
        self.clock = clock
        self.settings = settings if settings is not None else IcsSettings()
        self.servos: list[EmulatedServo] = list(servos)
        if len(self.servos) > MAX_SERVOS:
            raise ValueError(f"one ICS bus carries at most {MAX_SERVOS} servos")
        self.baud = baud  # the wire's rate (pacing); the servos' own rate is in their EEPROM
        self.host_baud: int | None = None  # the host's rate when it can be seen (in process)
        self.config = options if options is not None else ServeOptions()
        self._buf = bytearray()
        self._out = bytearray()
        self._due: list[tuple[float, int, bytes]] = []
        self._seq = itertools.count()

    @classmethod
    def with_ids(
        cls,
        ids: Iterable[int],
        *,
        clock: IcsClock,
        settings: IcsSettings | None = None,
        baud: int = 115200,
    ) -> EmulatedBus:
        """A bus of default servos with these IDs, their EEPROMs set to ``baud``."""
        s = settings if settings is not None else IcsSettings()
        eeprom = Eeprom().replace(baud=baud)
        servos = [EmulatedServo(i, eeprom, settings=s) for i in ids]
        return cls(servos, clock=clock, settings=s, baud=baud)

    @property
    def wire_baud(self) -> int:
        return self.host_baud if self.host_baud is not None else self.baud

    def servo(self, servo_id: int) -> EmulatedServo | None:
        for s in self.servos:
            if s.servo_id == servo_id:
                return s
        return None

    # ---------------------------------------------------------------- the device interface

    def feed(self, data: bytes | bytearray) -> bytes:
        """Host bytes in; the echo (and any reply due at once) out."""
        now = self.clock.now()
        self._out += data
        for b in data:
            if b & 0x80:
                if self._buf:
                    log.debug("dropped a partial ICS command %s", self._buf.hex(" "))
                self._buf = bytearray((b,))
            elif self._buf:
                self._buf.append(b)
            else:
                continue  # a data byte outside any command: noise
            n = command_length(self._buf)
            if n is not None and len(self._buf) == n:
                command = bytes(self._buf)
                self._buf.clear()
                self._dispatch(command, now)
        self._collect(now)
        return self.take_output()

    def tick(self) -> None:
        self._collect(self.clock.now())

    def take_output(self) -> bytes:
        out = bytes(self._out)
        self._out.clear()
        return out

    def poll_timeout(self) -> float | None:
        """Real seconds until the next reply is due (None: nothing pending)."""
        if not self._due:
            return None
        return max(0.0, self.clock.real_seconds(self._due[0][0] - self.clock.now()))

    def reset_input(self) -> None:
        """Drop a partial command (a TCP client went away)."""
        self._buf.clear()

    def close(self) -> None:
        """Nothing to release (the servers and ``icsemu://`` call it)."""

    # ---------------------------------------------------------------- one exchange (0Eh)

    def exchange(self, command: bytes) -> bytes | None:
        """Send one whole command and return the servo's answer without the echo, at once
        (the board's 0Eh): None if no servo answers."""
        now = self.clock.now()
        answers = self._answers(command, now)
        if not answers:
            return None
        return self._combine([a.data for a in answers])

    # ---------------------------------------------------------------- internals

    def _listening(self, servo: EmulatedServo, now: float) -> bool:
        if servo.busy(now):
            return False
        return self.host_baud is None or servo.eeprom.baud == self.host_baud

    def _answers(self, command: bytes, now: float) -> list[Answer]:
        out = []
        for servo in self.servos:
            if self._listening(servo, now) and servo.addressed(command):
                answer = servo.handle(command, now)
                if answer is not None:
                    servo.busy_until = now + answer.delay + answer.busy_for
                    out.append(answer)
        return out

    def _combine(self, replies: list[bytes]) -> bytes | None:
        if len(replies) == 1:
            return replies[0]
        if self.settings.id_collision == "silent":
            return None
        log.warning("%d servos answered at once: the bytes collide", len(replies))
        n = min(len(r) for r in replies)
        return bytes(_and(r[i] for r in replies) for i in range(n))

    def _dispatch(self, command: bytes, now: float) -> None:
        answers = self._answers(command, now)
        if not answers:
            return
        if len(answers) > 1:  # an ID command, or two servos with one ID: they collide
            data = self._combine([a.data for a in answers])
            if data is not None:
                heapq.heappush(self._due, (now + answers[0].delay, next(self._seq), data))
            return
        a = answers[0]
        heapq.heappush(self._due, (now + a.delay, next(self._seq), a.data))

    def _collect(self, now: float) -> None:
        while self._due and self._due[0][0] <= now:
            self._out += heapq.heappop(self._due)[2]


def _and(values: Iterable[int]) -> int:
    v = 0xFF
    for x in values:
        v &= x
    return v
