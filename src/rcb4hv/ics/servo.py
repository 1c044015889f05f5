"""One emulated ICS servo: an ID, its EEPROM, live values and a position it reports.

:class:`EmulatedServo` answers whole commands (:meth:`EmulatedServo.handle`); the bus
(:mod:`rcb4hv.ics.bus`) splits the byte stream into commands, echoes, and delivers replies on
time. The servo is sans-I/O: time comes in as an argument (board or real seconds, as the
caller's clock says).

Two seams let a host model own the servo's state (the board emulator does, so a servo on an
SIO line *is* the board's servo slot):

* :class:`Plant`: where the horn is and how it moves (default :class:`SlewPlant`);
* :class:`LiveValues`: the working stretch and speed (default: a dict of its own).

Motion of the default plant: a constant-rate slew toward the target at the no-load speed of
the default servo, a KRS-3304R2 (:data:`rcb4hv.robot.servos.DEFAULT_SERVO`: 0.13 s / 60
degrees), times ``speed / 127``, at :data:`rcb4hv.protocol.COUNTS_PER_DEGREE`. Rotation mode,
punch, dead band and damping are stored and reported but do not change the motion.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import Final, Protocol

from rcb4hv.ics.codec import (
    EEPROM_SIZE,
    MAX_ID,
    POSITION_FREE,
    Kind,
    Sc,
    join7,
    split7,
)
from rcb4hv.ics.eeprom import Eeprom
from rcb4hv.ics.settings import IcsSettings
from rcb4hv.protocol import COUNTS_PER_DEGREE
from rcb4hv.protocol.ranges import STRETCH_MAX as SPEED_MAX
from rcb4hv.robot.servos import DEFAULT_SERVO

__all__ = ["COUNTS_PER_S_AT_127", "EmulatedServo", "LiveValues", "Plant", "SlewPlant"]

log = logging.getLogger(__name__)

COUNTS_PER_S_AT_127: Final = math.degrees(DEFAULT_SERVO.no_load_speed) * COUNTS_PER_DEGREE
"""The default plant's slew rate at speed 127: the KRS-3304R2's no-load speed (~13675
counts/s)."""
AMBIENT_C: Final = 25.0  # room temperature: below the 26.7 degC end of the rcb4 table


class Plant(Protocol):
    """The mechanics behind a servo: what it reports and what a command does to it."""

    def position(self, now: float) -> int: ...

    def move(self, target: int, speed: int, now: float) -> None: ...

    def free(self, now: float) -> None: ...


class LiveValues(Protocol):
    """The servo's working values ``stretch`` and ``speed`` (None: not set since power-on)."""

    def get(self, name: str) -> int | None: ...

    def set(self, name: str, value: int) -> None: ...


@dataclass
class DictLive:
    """Working values kept by the servo itself."""

    values: dict[str, int] = field(default_factory=dict)

    def get(self, name: str) -> int | None:
        return self.values.get(name)

    def set(self, name: str, value: int) -> None:
        self.values[name] = value


@dataclass
class SlewPlant:
    """A horn that slews at a constant rate toward its target; free, it stays put."""

    pos: float = 7500.0
    target: float | None = None
    rate: float = 0.0  # counts per second
    t: float = 0.0

    def _advance(self, now: float) -> None:
        if self.target is not None and now > self.t:
            step = self.rate * (now - self.t)
            d = self.target - self.pos
            self.pos = self.target if abs(d) <= step else self.pos + (step if d > 0 else -step)
        self.t = max(self.t, now)

    def position(self, now: float) -> int:
        self._advance(now)
        return round(self.pos)

    def move(self, target: int, speed: int, now: float) -> None:
        self._advance(now)
        self.target = float(target)
        self.rate = COUNTS_PER_S_AT_127 * max(1, min(SPEED_MAX, speed)) / SPEED_MAX

    def free(self, now: float) -> None:
        self._advance(now)
        self.target = None


@dataclass(frozen=True, slots=True)
class Answer:
    """What a servo sends back and how long after the command it starts (seconds)."""

    data: bytes
    delay: float = 0.0
    busy_for: float = 0.0  # the servo ignores commands for this long after answering


class EmulatedServo:
    """An ICS 3.5/3.6 servo on an emulated bus."""

    def __init__(
        self,
        servo_id: int = 0,
        eeprom: Eeprom | None = None,
        *,
        settings: IcsSettings | None = None,
        plant: Plant | None = None,
        live: LiveValues | None = None,
    ) -> None:
        if not 0 <= servo_id <= MAX_ID:
            raise ValueError(f"ICS ID {servo_id} is not 0..{MAX_ID}")
        self.settings = settings if settings is not None else IcsSettings()
        self.eeprom = (eeprom if eeprom is not None else Eeprom()).replace(id=servo_id)
        self.plant: Plant = plant if plant is not None else SlewPlant()
        self.live: LiveValues = live if live is not None else DictLive()
        self.current_limit = self.eeprom.get("current_limit")
        self.temperature_limit = self.eeprom.get("temperature_limit")
        self.current_a = 0.0
        self.temperature_c = AMBIENT_C
        self.is_free = True  # a servo holds nothing until its first position command
        self.busy_until = float("-inf")

    # ---------------------------------------------------------------- state

    @property
    def servo_id(self) -> int:
        return self.eeprom.servo_id

    @property
    def stretch(self) -> int:
        v = self.live.get("stretch")
        return self.eeprom.stretch if v is None else v

    @property
    def speed(self) -> int:
        v = self.live.get("speed")
        return self.eeprom.speed if v is None else v

    def position(self, now: float) -> int:
        """The position the servo reports (its measured position)."""
        return self.plant.position(now)

    def set_load(self, current_a: float, temperature_c: float) -> None:
        """What a physics model measures: motor current (A, negative reverse) and case
        temperature (degC); read back through read sc 3 and sc 4."""
        self.current_a = float(current_a)
        self.temperature_c = float(temperature_c)

    def busy(self, now: float) -> bool:
        return now < self.busy_until

    # ---------------------------------------------------------------- commands

    def addressed(self, command: bytes) -> bool:
        """Whether ``command`` is for this servo (ID commands are for every servo)."""
        return command[0] & 0xE0 == Kind.ID or command[0] & MAX_ID == self.servo_id

    def handle(self, command: bytes, now: float) -> Answer | None:
        """Answer one whole command addressed to this servo (None: silence)."""
        kind = command[0] & 0xE0
        if kind == Kind.POSITION:
            return self._position(command, now)
        if kind == Kind.READ:
            return self._read(command, now)
        if kind == Kind.WRITE:
            return self._write(command, now)
        return self._id(command)

    def _reply_head(self, command: bytes) -> bytes:
        return bytes((command[0] & 0x7F,))

    def _position(self, command: bytes, now: float) -> Answer:
        target = join7(command[1], command[2])
        if target == POSITION_FREE:
            self.plant.free(now)
            self.is_free = True
        else:
            lo, hi = self.eeprom.get("min_pulse"), self.eeprom.get("max_pulse")
            self.plant.move(max(lo, min(hi, target)), self.speed, now)
            self.is_free = False
        reply = self._reply_head(command) + bytes(split7(self.position(now)))
        return Answer(reply, self.settings.response_delay_s)

    def _read(self, command: bytes, now: float) -> Answer | None:
        sc = command[1]
        head = self._reply_head(command) + bytes((sc,))
        s = self.settings
        if sc == Sc.EEPROM:
            return Answer(head + self.eeprom.data, s.response_delay_s)
        if sc == Sc.POSITION:
            if s.version == "3.5":
                return None  # an ICS 3.5 servo does not answer it (Kondo IcsClass getPos)
            return Answer(head + bytes(split7(self.position(now))), s.response_delay_s)
        values = {
            Sc.STRETCH: self.stretch,
            Sc.SPEED: self.speed,
            Sc.CURRENT: s.current_raw(self.current_a),
            Sc.TEMPERATURE: s.temperature_raw(self.temperature_c),
        }
        if sc not in values:
            return None
        return Answer(head + bytes((values[Sc(sc)],)), s.response_delay_s)

    def _write(self, command: bytes, now: float) -> Answer | None:
        sc = command[1]
        s = self.settings
        if sc == Sc.EEPROM:
            if len(command) != 2 + EEPROM_SIZE:
                return None
            self._apply_eeprom(Eeprom(bytes(b & 0x0F for b in command[2:])))
            return Answer(self._reply_head(command) + bytes((sc,)), s.eeprom_write_delay_s)
        value = command[2]
        if sc in (Sc.STRETCH, Sc.SPEED):
            if not 1 <= value <= SPEED_MAX:
                return None
            self.live.set("stretch" if sc == Sc.STRETCH else "speed", value)
            field_name = "stretch" if sc == Sc.STRETCH else "speed"
        elif sc == Sc.CURRENT:
            self.current_limit = value
            field_name = "current_limit"
        elif sc == Sc.TEMPERATURE:
            self.temperature_limit = value
            field_name = "temperature_limit"
        else:
            return None
        if s.live_writes_persist:
            try:
                self.eeprom = self.eeprom.replace(**{field_name: value})
            except ValueError:
                log.debug(
                    "servo %d: %s %d not stored in the EEPROM", self.servo_id, field_name, value
                )
        return Answer(self._reply_head(command) + bytes((sc, value)), s.response_delay_s)

    def _apply_eeprom(self, new: Eeprom) -> None:
        """An EEPROM write: the new parameters take effect at once (rcb4's ics-manager reads
        rotation, reverse and baud back right after writing them)."""
        self.eeprom = new
        for name in ("stretch", "speed"):
            self.live.set(name, new.get(name))
        self.current_limit = new.get("current_limit")
        self.temperature_limit = new.get("temperature_limit")

    def _id(self, command: bytes) -> Answer | None:
        if command[1:] == bytes(3):  # ID read
            return Answer(bytes((Kind.ID | self.servo_id,)), self.settings.response_delay_s)
        if command[1:] == b"\x01\x01\x01":  # ID write
            self.eeprom = self.eeprom.replace(id=command[0] & MAX_ID)
            s = self.settings
            return Answer(bytes((Kind.ID | self.servo_id,)), s.response_delay_s, s.id_write_busy_s)
        return None
