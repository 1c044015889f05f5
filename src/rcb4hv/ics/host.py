"""The typed host API: :class:`IcsBus` (scan, ID) and :class:`IcsServo` (one servo's values,
EEPROM and position) over an :class:`~rcb4hv.ics.link.IcsLink`.

Every write is verified: a live write by the value the servo echoes in its reply, an EEPROM
write by reading the EEPROM back. Writes return what changed.

>>> from rcb4hv.ics import IcsBus
>>> with IcsBus.open("icsemu://?ids=0") as bus:
...     bus.scan()
...     servo = bus.servo(0)
...     servo.set_params(stretch=60)
[0]
{'stretch': (90, 60)}
"""

from __future__ import annotations

import logging
from collections.abc import Iterable, Mapping
from types import TracebackType
from typing import Final

from rcb4hv.errors import IcsError, IcsNoReply
from rcb4hv.ics.codec import (
    BAUD_RATES,
    MAX_ID,
    POSITION_FREE,
    EepromReply,
    IdReply,
    PositionReply,
    Sc,
    ValueReply,
    WriteReply,
    decode_reply,
    encode_eeprom_write,
    encode_id_read,
    encode_id_write,
    encode_position,
    encode_read,
    encode_write,
)
from rcb4hv.ics.eeprom import FIELD, FLAG_BITS, Eeprom
from rcb4hv.ics.link import IcsLink, SerialIcsLink
from rcb4hv.transport import SerialTransport

__all__ = ["LIVE", "IcsBus", "IcsServo"]

log = logging.getLogger(__name__)

# values with a live read/write sub-command (the others live in the EEPROM only)
LIVE: Final = {"stretch": Sc.STRETCH, "speed": Sc.SPEED}
DEFAULT_BAUD: Final = 115200  # what Kondo's servos ship with (EEPROM baud code 10)


class IcsServo:
    """One servo on an :class:`IcsBus`."""

    def __init__(self, link: IcsLink, servo_id: int, baud: int | None = None) -> None:
        if not 0 <= servo_id <= MAX_ID:
            raise ValueError(f"ICS ID {servo_id} is not 0..{MAX_ID}")
        self.link = link
        self.servo_id = servo_id
        self.baud = baud  # the host's rate, when known: an EEPROM baud change is followed

    def __repr__(self) -> str:
        return f"<IcsServo {self.servo_id}>"

    def _ask(self, command: bytes) -> object:
        return decode_reply(command, self.link.exchange(command))

    # ---------------------------------------------------------------- position

    def move(self, position: int) -> int:
        """Move to ``position`` (3500..11500); return the position the servo reports."""
        reply = self._ask(encode_position(self.servo_id, position))
        assert isinstance(reply, PositionReply)
        return reply.position

    def free(self) -> int:
        """Let the servo go limp; return its position."""
        reply = self._ask(encode_position(self.servo_id, POSITION_FREE))
        assert isinstance(reply, PositionReply)
        return reply.position

    def position(self) -> int:
        """Read the position (ICS 3.6 read sc 5). An ICS 3.5 servo does not answer it: when the
        servo answers a stretch read but not this, :class:`IcsNoReply` says so."""
        command = encode_read(self.servo_id, Sc.POSITION)
        try:
            reply = self._ask(command)
        except IcsNoReply as exc:
            try:
                self.stretch()
            except IcsNoReply:
                raise exc from None
            raise IcsNoReply(
                f"servo {self.servo_id} answers, but not the position read: an ICS 3.5 servo "
                "has none (ICS 3.6 only); a move or a free returns the position "
                f"[no reply to {command.hex(' ')}]"
            ) from exc
        assert isinstance(reply, ValueReply)
        return reply.value

    # ---------------------------------------------------------------- live values

    def read(self, sc: Sc) -> int:
        """A live value: stretch, speed, current, temperature (raw) or position."""
        reply = self._ask(encode_read(self.servo_id, sc))
        assert isinstance(reply, ValueReply)
        return reply.value

    def write(self, sc: Sc, value: int) -> int:
        """Write a live value; :class:`IcsError` unless the servo acknowledges that value."""
        reply = self._ask(encode_write(self.servo_id, sc, value))
        assert isinstance(reply, WriteReply)
        if reply.value != value:
            raise IcsError(f"servo {self.servo_id} acknowledged {reply.value}, not {value}")
        return value

    def stretch(self) -> int:
        return self.read(Sc.STRETCH)

    def speed(self) -> int:
        return self.read(Sc.SPEED)

    def current(self) -> int:
        """Raw current: 0..63 forward, 64..127 reverse (see IcsSettings.current_scale_a)."""
        return self.read(Sc.CURRENT)

    def temperature(self) -> int:
        """Raw temperature: lower is hotter (see IcsSettings.temperature_c)."""
        return self.read(Sc.TEMPERATURE)

    # ---------------------------------------------------------------- EEPROM

    def eeprom(self) -> Eeprom:
        reply = self._ask(encode_read(self.servo_id, Sc.EEPROM))
        assert isinstance(reply, EepromReply)
        return Eeprom(reply.data)

    def write_eeprom(self, new: Eeprom) -> Eeprom:
        """Write ``new`` whole and read it back; :class:`IcsError` if the read-back differs.
        Write to the ID the servo has *after* the write if ``new`` changes it."""
        reply = self._ask(encode_eeprom_write(self.servo_id, new.data))
        assert isinstance(reply, WriteReply)
        self.servo_id = new.servo_id
        if self.baud is not None and new.baud is not None and new.baud != self.baud:
            log.warning("servo %d now talks at %d baud: the host follows", new.servo_id, new.baud)
            self.link.follow_baud(new.baud)
            self.baud = new.baud
        back = self.eeprom()
        if back.data != new.data:
            diff = new.differences(back)
            raise IcsError(f"servo {self.servo_id}: EEPROM read back differs: {diff}")
        return back

    def get(self, name: str) -> int | None:
        """A parameter by name: ``stretch`` and ``speed`` live, anything else from the EEPROM
        (fields of :data:`~rcb4hv.ics.eeprom.FIELDS`, flags, ``baud``)."""
        if name in LIVE:
            return self.read(LIVE[name])
        e = self.eeprom()
        return e.baud if name == "baud" else e.get(name)

    def set_params(
        self, *, live: bool = False, **values: int
    ) -> dict[str, tuple[int | None, int | None]]:
        """:meth:`update` with keyword arguments: ``servo.set_params(stretch=60)``."""
        return self.update(values, live=live)

    def update(
        self, values: Mapping[str, int], *, live: bool = False
    ) -> dict[str, tuple[int | None, int | None]]:
        """Set parameters and return ``{name: (before, after)}`` for those that changed.

        By default every value goes into the EEPROM (read, change, write, read back), so it
        survives power-off. ``live=True`` writes ``stretch`` / ``speed`` with the live
        sub-command instead (the servo forgets it at power-off, like the RCB-4's 12h).
        """
        if live:
            bad = set(values) - set(LIVE)
            if bad:
                raise ValueError(f"only {sorted(LIVE)} have live writes, not {sorted(bad)}")
            for name, v in values.items():  # the EEPROM's ranges, checked before a byte goes
                FIELD[name].encode(v)
            changes: dict[str, tuple[int | None, int | None]] = {}
            for name, v in values.items():
                before = self.read(LIVE[name])
                self.write(LIVE[name], v)
                if before != v:
                    changes[name] = (before, v)
            return changes
        old = self.eeprom()
        new = old.replace(**dict(values))
        if new.data == old.data:
            return {}
        if self.baud is None and old.baud is not None:
            self.baud = old.baud  # it answered at the host's rate
        back = self.write_eeprom(new)
        return old.differences(back)


class IcsBus:
    """An ICS bus seen from the host."""

    def __init__(self, link: IcsLink) -> None:
        self.link = link

    @classmethod
    def open(cls, url: str, baud: int = DEFAULT_BAUD) -> IcsBus:
        """A serial port (the adapter in ICS mode, ``/dev/pts/N``, ``socket://``, ``icsemu://``)
        at ``baud`` (115200, 625000, 1250000), 8E1."""
        if baud not in BAUD_RATES:
            raise ValueError(f"ICS baud rate {baud} is not one of {BAUD_RATES}")
        return cls(SerialIcsLink(SerialTransport.open(url, baud)))

    def close(self) -> None:
        self.link.close()

    def __enter__(self) -> IcsBus:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()

    def servo(self, servo_id: int) -> IcsServo:
        return IcsServo(self.link, servo_id)

    def scan(self, ids: Iterable[int] = range(MAX_ID + 1)) -> list[int]:
        """The IDs that answer a stretch read (ICS 3.5 and 3.6 servos both do)."""
        found = []
        for i in ids:
            try:
                self.servo(i).stretch()
            except IcsNoReply:
                continue
            found.append(i)
        return found

    def read_id(self, *, alone: bool = True) -> int:
        """The ID of the one servo on the bus, checked: that ID answers a stretch read. With
        several servos the answers collide on the wire and AND into an ID none of them may
        have: :class:`~rcb4hv.errors.IcsError` then, not a wrong ID. The AND may also be the
        ID of one of them (IDs 1 and 3 read as 1), so with ``alone`` (the default) every ID
        another servo could have (the IDs holding every bit of the one read) is probed too,
        and an answer is an IcsError naming the servos: up to 31 stretch reads, about 3 s
        when the ID read is 0."""
        command = encode_id_read()
        reply = decode_reply(command, self.link.exchange(command))
        assert isinstance(reply, IdReply)
        got = reply.servo_id
        try:
            self.servo(got).stretch()
        except IcsNoReply:
            raise IcsError(
                f"the ID read back, {got}, does not answer: more than one servo on "
                "the line? Connect only the one to read (or rename)"
            ) from None
        if alone:
            others = self.scan(i for i in range(MAX_ID + 1) if i != got and i & got == got)
            if others:
                ids = ", ".join(map(str, sorted([got, *others])))
                raise IcsError(
                    f"servos {ids} answer: an ID read reaches every servo on the line, so it "
                    "reads none of them; connect only the one to read or rename, or name a "
                    "servo by its ID"
                )
        return got

    def write_id(self, new_id: int) -> int:
        """Give the one servo on the bus ``new_id`` (every servo on the bus takes it); verify
        by reading the ID back."""
        command = encode_id_write(new_id)
        reply = decode_reply(command, self.link.exchange(command))
        assert isinstance(reply, IdReply)
        back = self.read_id(alone=False)  # the bus was checked before the rename
        if back != new_id:
            raise IcsError(f"the servo answers ID {back} after being given {new_id}")
        return back


FLAGS: Final = tuple(FLAG_BITS)
