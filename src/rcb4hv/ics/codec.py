"""The ICS 3.5/3.6 wire codec: pure functions, no I/O (sans-I/O, like :mod:`rcb4hv.protocol`).

Facts (``../shared/robots/FACTS.md`` "ICS 3.5 on the wire", from Kondo's ICS 3.5 software
manual (2015), Kondo's IcsClass for Arduino and iory/rcb4 ``ics.py``):

* one half-duplex wire, 8E1, 115200 / 625000 / 1,250,000 baud; the host hears its own bytes
  (the *echo*) before the servo's reply;
* the command byte's top 3 bits pick the command (100 position, 101 read, 110 write, 111 ID)
  and its low 5 bits the ID 0-31; a reply's command byte has the top bit cleared;
* every other byte is 7-bit data (top bit 0), so a byte with the top bit set always starts a
  command;
* positions travel as two 7-bit halves, high first; the EEPROM as 64 bytes of 4 bits each.

===============================  ======================  ====================================
command                          sent                    reply (after the echo)
===============================  ======================  ====================================
position (0 = free)              ``80h|id, hi, lo``      ``id, hi, lo`` (the current position)
read EEPROM                      ``A0h|id, 00h``         ``20h|id, 00h`` + 64 EEPROM bytes
read stretch/speed/current/temp  ``A0h|id, sc``          ``20h|id, sc, value``
read position (ICS 3.6)          ``A0h|id, 05h``         ``20h|id, 05h, hi, lo``
write EEPROM                     ``C0h|id, 00h`` + 64    ``40h|id, 00h`` (~0.35 s later)
write stretch/speed/limits       ``C0h|id, sc, value``   ``40h|id, sc, value``
read ID (one servo on the bus)   ``FFh, 00h, 00h, 00h``  ``E0h|id``
write ID (one servo on the bus)  ``E0h|new, 01h×3``      ``E0h|new``
===============================  ======================  ====================================

The EEPROM-write reply length (2 bytes) is what iory/rcb4's ``set_param`` reads (68 = 66 echo
+ 2); the ID replies keep the top bits (``E0h|id``), which both Kondo's IcsClass and rcb4 mask
with ``1Fh``.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import Final

from rcb4hv.errors import IcsError
from rcb4hv.protocol import POSITION_MAX, POSITION_MIN  # the same 3500..11500 (+-135 degrees)

__all__ = [
    "BAUD_RATES",
    "EEPROM_SIZE",
    "ID_READ",
    "MAX_ID",
    "POSITION_FREE",
    "EepromReply",
    "IdReply",
    "Kind",
    "PositionReply",
    "Reply",
    "Sc",
    "ValueReply",
    "WriteReply",
    "command_length",
    "decode_reply",
    "encode_eeprom_write",
    "encode_id_read",
    "encode_id_write",
    "encode_position",
    "encode_read",
    "encode_write",
    "join7",
    "reply_length",
    "split7",
    "strip_echo",
]

BAUD_RATES: Final = (115200, 625000, 1250000)
MAX_ID: Final = 31  # 5 bits of the command byte
EEPROM_SIZE: Final = 64
POSITION_FREE: Final = 0  # "position 0 frees the servo and still returns its position"
WIRE_MAX: Final = 0x3FFF  # two 7-bit halves
ID_SC_READ: Final = 0
ID_SC_WRITE: Final = 1
ID_READ: Final = bytes((0xFF, ID_SC_READ, ID_SC_READ, ID_SC_READ))


class Kind(IntEnum):
    """The top 3 bits of a command byte."""

    POSITION = 0x80
    READ = 0xA0
    WRITE = 0xC0
    ID = 0xE0


class Sc(IntEnum):
    """Sub-command of read (``A0h``) and write (``C0h``)."""

    EEPROM = 0
    STRETCH = 1
    SPEED = 2
    CURRENT = 3  # read: the current; write: the current limit
    TEMPERATURE = 4  # read: the temperature; write: the temperature limit
    POSITION = 5  # read only, ICS 3.6 servos


def _check_id(servo_id: int) -> None:
    if isinstance(servo_id, bool) or not isinstance(servo_id, int) or not 0 <= servo_id <= MAX_ID:
        raise ValueError(f"ICS ID {servo_id!r} is not 0..{MAX_ID}")


def _check7(name: str, value: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value <= 0x7F:
        raise ValueError(f"{name} {value!r} is not a 7-bit value 0..127")


def split7(value: int) -> tuple[int, int]:
    """``value`` (0..3FFFh) as its high and low 7-bit halves."""
    if not 0 <= value <= WIRE_MAX:
        raise ValueError(f"{value} does not fit two 7-bit halves (0..{WIRE_MAX})")
    return (value >> 7) & 0x7F, value & 0x7F


def join7(hi: int, lo: int) -> int:
    """The value of two 7-bit halves (any top bits are ignored, as Kondo's IcsClass masks)."""
    return ((hi & 0x7F) << 7) | (lo & 0x7F)


# ---------------------------------------------------------------------- host -> servo


def encode_position(servo_id: int, position: int) -> bytes:
    """Move to ``position`` (3500..11500; 0 frees the servo): ``80h|id, hi, lo``."""
    _check_id(servo_id)
    if position != POSITION_FREE and not POSITION_MIN <= position <= POSITION_MAX:
        raise ValueError(f"position {position} is not 0 (free) or {POSITION_MIN}..{POSITION_MAX}")
    return bytes((Kind.POSITION | servo_id, *split7(position)))


def encode_read(servo_id: int, sc: Sc | int) -> bytes:
    """Read the EEPROM (sc 0) or one live value: ``A0h|id, sc``."""
    _check_id(servo_id)
    Sc(sc)
    return bytes((Kind.READ | servo_id, sc))


def encode_write(servo_id: int, sc: Sc | int, value: int) -> bytes:
    """Write stretch (1), speed (2), the current limit (3) or the temperature limit (4)."""
    _check_id(servo_id)
    if Sc(sc) not in (Sc.STRETCH, Sc.SPEED, Sc.CURRENT, Sc.TEMPERATURE):
        raise ValueError(f"sub-command {sc} cannot be written with one value")
    _check7("value", value)
    return bytes((Kind.WRITE | servo_id, sc, value))


def encode_eeprom_write(servo_id: int, eeprom: bytes) -> bytes:
    """Write the whole EEPROM: ``C0h|id, 00h`` and 64 nibble bytes."""
    _check_id(servo_id)
    if len(eeprom) != EEPROM_SIZE or any(b > 0x0F for b in eeprom):
        raise ValueError("an EEPROM image is 64 bytes of 0..15")
    return bytes((Kind.WRITE | servo_id, Sc.EEPROM)) + bytes(eeprom)


def encode_id_read() -> bytes:
    """Ask the (single) servo on the bus for its ID."""
    return ID_READ


def encode_id_write(new_id: int) -> bytes:
    """Give the (single) servo on the bus a new ID."""
    _check_id(new_id)
    return bytes((Kind.ID | new_id, ID_SC_WRITE, ID_SC_WRITE, ID_SC_WRITE))


def command_length(head: bytes | bytearray) -> int | None:
    """Bytes in the command starting ``head`` (None: more bytes are needed to tell)."""
    if not head or not head[0] & 0x80:
        raise ValueError("a command starts with a byte whose top bit is set")
    kind = head[0] & 0xE0
    if kind == Kind.POSITION:
        return 3
    if kind == Kind.READ:
        return 2
    if kind == Kind.ID:
        return 4
    if len(head) < 2:
        return None
    return 2 + EEPROM_SIZE if head[1] == Sc.EEPROM else 3


def reply_length(command: bytes | bytearray) -> int:
    """Bytes of the servo's reply to ``command`` (the echo not counted)."""
    kind = command[0] & 0xE0
    if kind == Kind.POSITION:
        return 3
    if kind == Kind.ID:
        return 1
    sc = command[1]
    if kind == Kind.READ:
        return {Sc.EEPROM: 2 + EEPROM_SIZE, Sc.POSITION: 4}.get(Sc(sc), 3)
    return 2 if sc == Sc.EEPROM else 3


# ---------------------------------------------------------------------- servo -> host


@dataclass(frozen=True, slots=True)
class PositionReply:
    """The servo's position after a position command (also after free)."""

    servo_id: int
    position: int


@dataclass(frozen=True, slots=True)
class ValueReply:
    """A live value read with sc 1..5 (position for sc 5)."""

    servo_id: int
    sc: Sc
    value: int


@dataclass(frozen=True, slots=True)
class EepromReply:
    """The 64 EEPROM bytes, as read."""

    servo_id: int
    data: bytes


@dataclass(frozen=True, slots=True)
class WriteReply:
    """A write's acknowledgement (``value`` None for the EEPROM write)."""

    servo_id: int
    sc: Sc
    value: int | None


@dataclass(frozen=True, slots=True)
class IdReply:
    """The ID of the servo on the bus (after an ID read or write)."""

    servo_id: int


Reply = PositionReply | ValueReply | EepromReply | WriteReply | IdReply


def strip_echo(command: bytes, received: bytes) -> bytes:
    """``received`` without the echo of ``command``; :class:`IcsError` if the echo differs
    (another device talked over the host: a collision or a wrong baud rate)."""
    echo = received[: len(command)]
    if echo != command[: len(echo)]:
        raise IcsError(f"echo {echo.hex(' ')} differs from the command {command.hex(' ')}")
    return received[len(command) :]


def decode_reply(command: bytes, reply: bytes) -> Reply:
    """Decode the servo's ``reply`` (echo removed) to ``command``; :class:`IcsError` if it
    cannot be the answer."""
    want = reply_length(command)
    if len(reply) != want:
        raise IcsError(f"reply {reply.hex(' ')} has {len(reply)} bytes, expected {want}")
    kind = command[0] & 0xE0
    if kind == Kind.ID:
        if reply[0] & 0xE0 != Kind.ID:
            raise IcsError(f"ID reply {reply[0]:02X}h is not E0h|id")
        return IdReply(reply[0] & MAX_ID)
    servo_id = command[0] & MAX_ID
    expect_head = (command[0] & 0x7F,) if kind == Kind.POSITION else (command[0] & 0x7F, command[1])
    if tuple(reply[: len(expect_head)]) != expect_head:
        raise IcsError(f"reply {reply.hex(' ')} does not answer {command.hex(' ')}")
    if any(b & 0x80 for b in reply):
        raise IcsError(f"reply {reply.hex(' ')} has a byte with the top bit set")
    if kind == Kind.POSITION:
        return PositionReply(servo_id, join7(reply[1], reply[2]))
    sc = Sc(command[1])
    if kind == Kind.READ:
        if sc is Sc.EEPROM:
            return EepromReply(servo_id, bytes(reply[2:]))
        if sc is Sc.POSITION:
            return ValueReply(servo_id, sc, join7(reply[2], reply[3]))
        return ValueReply(servo_id, sc, reply[2])
    return WriteReply(servo_id, sc, None if sc is Sc.EEPROM else reply[2])
