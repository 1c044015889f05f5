"""The board's two ICS lines (SIO1-4 and SIO5-8) with emulated servos, for 0Eh.

With ``EmulatorConfig(ics_comm=True)`` each virtual servo slot ``k`` (ICS number = 2 x ID +
side, spec 8.1) is also an :class:`~rcb4hv.ics.EmulatedServo` with ID ``k // 2`` on line
``k % 2``. The servo *is* the slot:

* its position is the servo unit's measured position (what the board reports in the servo
  block), and an ICS position command sets it, as if the horn were moved;
* its working stretch and speed are :attr:`Board.stretch` / :attr:`Board.speed_parameter`,
  which 12h sets, so whichever way they were set the physics sees one value.

0Eh runs at once in board time (the servo's answer, even the 0.35 s EEPROM write, is written
before the ACK): how long a real board waits for an answer is not documented.
"""

from __future__ import annotations

import logging

from rcb4hv.emulator.clock import Clock
from rcb4hv.emulator.config import EmulatorConfig
from rcb4hv.emulator.servos import Servos
from rcb4hv.ics import EmulatedBus, EmulatedServo, IcsSettings
from rcb4hv.ics.codec import command_length

__all__ = ["IcsLines", "SlotLive", "SlotPlant"]

log = logging.getLogger(__name__)


class SlotPlant:
    """An ICS servo's mechanics = the board's virtual servo ``ics``."""

    def __init__(self, servos: Servos, ics: int) -> None:
        self.servos = servos
        self.ics = ics

    def position(self, now: float) -> int:
        return self.servos.physical.get(self.ics, 0)

    def move(self, target: int, speed: int, now: float) -> None:
        self.servos.physical[self.ics] = target

    def free(self, now: float) -> None:
        """The horn stays where it is."""


class SlotLive:
    """An ICS servo's working stretch / speed = the board's 12h values for slot ``ics``."""

    def __init__(self, servos: Servos, ics: int) -> None:
        self.servos = servos
        self.ics = ics

    def _table(self, name: str) -> dict[int, int]:
        return self.servos.stretch if name == "stretch" else self.servos.speed_parameter

    def get(self, name: str) -> int | None:
        return self._table(name).get(self.ics)

    def set(self, name: str, value: int) -> None:
        self._table(name)[self.ics] = value


class IcsLines:
    """Line 0 (SIO1-4) and line 1 (SIO5-8), each an :class:`~rcb4hv.ics.EmulatedBus`."""

    def __init__(
        self,
        servos: Servos,
        config: EmulatorConfig,
        clock: Clock,
        settings: IcsSettings | None = None,
    ) -> None:
        s = settings if settings is not None else IcsSettings()
        self.lines: tuple[EmulatedBus, EmulatedBus] = (
            EmulatedBus(clock=clock, settings=s),
            EmulatedBus(clock=clock, settings=s),
        )
        self.slots = servos.ics
        """The ICS numbers with a servo on the lines."""
        for ics in servos.ics:
            servo = EmulatedServo(
                ics // 2,
                settings=s,
                plant=SlotPlant(servos, ics),
                live=SlotLive(servos, ics),
            )
            self.lines[ics % 2].servos.append(servo)

    def servo(self, ics: int) -> EmulatedServo | None:
        """The ICS servo of slot ``ics`` (None: no virtual servo there)."""
        return self.lines[ics % 2].servo(ics // 2)

    def exchange(self, ics: int, data: bytes) -> bytes | None:
        """0Eh: send ``data`` on the line of ICS number ``ics``; the answer without the echo
        (None: nothing answered, or ``data`` is not one whole ICS command)."""
        line = self.lines[ics & 1]
        if not data or not data[0] & 0x80:
            return None
        n = command_length(data)
        if n is None or n != len(data):
            log.debug("0Eh: %s is not one whole ICS command", data.hex(" "))
            return None
        return line.exchange(data)
