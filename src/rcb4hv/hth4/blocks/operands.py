"""Operands of a program block by name: ``VAR3``, ``COUNTER0``, ``BUTTONS``, ``AD1``, ``ICS5+14``.

A data command's operand (:class:`~rcb4hv.protocol.Ram`, :class:`~rcb4hv.protocol.Ics`,
:class:`~rcb4hv.protocol.Rom`, :class:`~rcb4hv.protocol.Com`, :class:`~rcb4hv.protocol.Data`)
is written in a program as one string. Each RAM address has one canonical name, taken from
HeartToHeart4's use of the user area (spec 10.1; :class:`~rcb4hv.protocol.memory.ADDR`):

====================  =========================================================
``SYSTEM``            the system register (0000h); also ``PC``, ``CALL_DEPTH``,
                      ``UPDATE_FLAGS``, ``VECTOR_TABLE``, ``KRI3``, ``KRI3_SUM``
``AD_REF0``-``10``    AD reference words (000Ch + 2k)
``AD0``-``AD10``      AD measured words (0022h + 2k)
``PIO_DIR``           PIO direction (0038h); ``PIO_DATA`` its data (003Ah)
``TIMER0``-``3``      the timers (003Ch + 2k)
``SERVO<n>+<off>``    byte ``off`` of the servo block of ICS ``n`` (0090h + 20n)
``BUTTONS``           the remote's button word (0350h, high byte first)
``PA1``-``PA4``       the remote's analog values (0352h-0355h)
``COUNTER0``-``10``   HeartToHeart4's loop counters (0457h + k, one byte each)
``VAR0``-``VAR19``    HeartToHeart4's user variables (0462h + 2k, int16)
``ALLOC0``-``35``,    the ICS allocation table, the vector packages and the
``VPKG0``-``31``,     firmware's temporaries
``TEMP0``-``1``
``RAM:XXXX``          any other RAM address (hex); accepted for every address
====================  =========================================================

The names are the assembler's (:mod:`rcb4hv.protocol.memory.names`), written without
brackets.

and ``ICS<n>+<off>`` (byte ``off`` of ICS ``n``'s block through the allocation table),
``ROM:XXXXX``, ``COM`` and literal bytes ``#05 00``. :func:`operand_name` and
:func:`parse_operand` are inverse: the name gives back the same operand, so the same bytes.
"""

from __future__ import annotations

import re
from typing import Final

from rcb4hv.errors import EditError
from rcb4hv.protocol import Com, Data, Ics, Ram, Rom
from rcb4hv.protocol.memory import RAM_SCALARS, RAM_TABLES

__all__ = ["Operand", "named_ram", "operand_name", "parse_operand", "ram_name"]

Operand = Ram | Ics | Rom | Com | Data

_SERVO: Final = RAM_TABLES["SERVO"]
_NUMBERED: Final = tuple(t for t in RAM_TABLES.values() if t is not _SERVO)
"""The tables named ``<name><index>`` (``VAR3``); a servo block's bytes are ``SERVO<n>+<off>``."""


def ram_name(address: int) -> str:
    """The canonical name of RAM ``address``."""
    for name, (a, _) in RAM_SCALARS.items():
        if a == address:
            return name
    for table in _NUMBERED:
        index = table.index(address)
        if index is not None:
            return f"{table.name}{index}"
    n, off = divmod(address - _SERVO.base, _SERVO.stride)
    if _SERVO.first <= n <= _SERVO.last and address >= _SERVO.base:
        return f"SERVO{n}+{off}"
    return f"RAM:{address:04X}"


def named_ram(name: str) -> int | None:
    """The RAM address of a canonical name (``VAR3``), None if ``name`` is not one."""
    if name in RAM_SCALARS:
        return RAM_SCALARS[name][0]
    m = re.fullmatch(r"([A-Z_]+)(\d+)", name)
    if m and m[1] != _SERVO.name:
        table = RAM_TABLES.get(m[1])
        if table is None or not table.first <= int(m[2]) <= table.last:
            return None
        return table.address(int(m[2]))
    m = re.fullmatch(r"SERVO(\d+)\+(\d+)", name)
    if m and int(m[1]) <= _SERVO.last and int(m[2]) < _SERVO.stride:
        return _SERVO.address(int(m[1])) + int(m[2])
    m = re.fullmatch(r"RAM:([0-9A-Fa-f]{1,4})", name)
    return int(m[1], 16) if m else None


def operand_name(op: Operand) -> str:
    """The program text of operand ``op``."""
    if isinstance(op, Ram):
        return ram_name(op.address)
    if isinstance(op, Ics):
        return f"ICS{op.ics}+{op.offset}"
    if isinstance(op, Rom):
        return f"ROM:{op.address:05X}"
    if isinstance(op, Data):
        return "#" + op.data.hex(" ").upper()
    return "COM"


def parse_operand(text: object, where: str) -> Operand:
    """The operand written ``text``; EditError naming ``where`` if it is not one."""
    if not isinstance(text, str):
        raise EditError(f"{where}: an operand is a string like 'VAR0', not {text!r}")
    try:
        if text == "COM":
            return Com()
        if text.startswith("#"):
            return Data(bytes.fromhex(text[1:]))
        m = re.fullmatch(r"ICS(\d+)\+(\d+)", text)
        if m:
            return Ics(int(m[2]), int(m[1]))
        m = re.fullmatch(r"ROM:([0-9A-Fa-f]{1,5})", text)
        if m:
            return Rom(int(m[1], 16))
        address = named_ram(text)
        if address is not None:
            return Ram(address)
    except ValueError as exc:
        raise EditError(f"{where}: {text!r}: {exc}") from None
    raise EditError(
        f"{where}: {text!r} is not an operand (VAR0, COUNTER0, BUTTONS, AD1, RAM:0462, "
        "ICS5+14, ROM:01000, COM or #05 00)"
    )
