"""ICS 3.5/3.6 servos: the wire codec, the EEPROM model, emulated servos and bus, and the
host API (:class:`IcsBus`, :class:`IcsServo`).

Layer: beside :mod:`rcb4hv.rom` and :mod:`rcb4hv.robot`; imports only :mod:`rcb4hv.errors`,
:mod:`rcb4hv.protocol` and :mod:`rcb4hv.transport`. The board emulator builds its SIO lines
from :class:`EmulatedBus` and :class:`EmulatedServo`; the ``icsemu://`` URL handler and the
``rcb4hv emulate-ics`` servers live in :mod:`rcb4hv.emulator` (they serve).
"""

from __future__ import annotations

from rcb4hv.ics.bus import EmulatedBus, IcsClock, ServeOptions, parse_ids
from rcb4hv.ics.codec import BAUD_RATES, Sc
from rcb4hv.ics.eeprom import DEFAULT_EEPROM, FIELDS, RESERVED_BYTES, Eeprom
from rcb4hv.ics.host import IcsBus, IcsServo
from rcb4hv.ics.link import BoardIcsLink, IcsLink, SerialIcsLink
from rcb4hv.ics.servo import EmulatedServo, LiveValues, Plant, SlewPlant
from rcb4hv.ics.settings import IcsSettings

__all__ = [
    "BAUD_RATES",
    "DEFAULT_EEPROM",
    "FIELDS",
    "RESERVED_BYTES",
    "BoardIcsLink",
    "Eeprom",
    "EmulatedBus",
    "EmulatedServo",
    "IcsBus",
    "IcsClock",
    "IcsLink",
    "IcsServo",
    "IcsSettings",
    "LiveValues",
    "Plant",
    "Sc",
    "SerialIcsLink",
    "ServeOptions",
    "SlewPlant",
    "parse_ids",
]
