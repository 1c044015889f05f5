"""Argument checks shared by both faces of the client, the robot API and the session.

Every check raises :class:`~rcb4hv.errors.ArgumentError` (a ValueError) or
:class:`~rcb4hv.errors.ArgumentTypeError` (also a TypeError) naming the argument, the value
(shown plainly: ``5``, not ``np.int64(5)``) and what it may be, before anything is sent.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from numbers import Real

from rcb4hv.errors import ArgumentError, ArgumentTypeError, TransportError
from rcb4hv.protocol import ICS_COUNT
from rcb4hv.protocol.ranges import OVERRIDE, check_documented_position
from rcb4hv.values import as_index, plain

__all__ = [
    "check_choice",
    "check_ics",
    "check_ics_list",
    "check_link_args",
    "check_wait",
    "closed_error",
    "finite",
    "integer",
    "plain",
    "seconds",
    "servo_targets",
]


def integer(name: str, value: object) -> int:
    """``value`` as an int (:func:`rcb4hv.values.as_index`: ints and numpy integers, not
    bools, floats or text)."""
    out = as_index(value)
    if out is None:
        raise ArgumentTypeError(f"{name} must be an int, not {plain(value)}")
    return out


def finite(name: str, value: object) -> float:
    """``value`` as a finite float (ints, floats, numpy numbers); not bools, text, NaN or inf."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise ArgumentTypeError(f"{name} must be a number, not {plain(value)}")
    out = float(value)
    if not math.isfinite(out):
        raise ArgumentError(f"{name} must be a finite number, not {plain(value)}")
    return out


def seconds(name: str, value: object, *, allow_zero: bool = True) -> float:
    """A finite number of seconds >= 0 (> 0 without ``allow_zero``)."""
    out = finite(name, value)
    if out < 0 or (out == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ArgumentError(f"{name} must be a number of seconds {bound}, not {plain(value)}")
    return out


def check_wait(timeout: object, poll: object | None = None) -> None:
    """The rule of every wait: ``timeout`` a finite number of seconds > 0 (as the client's
    calls take), ``poll`` (when given) a finite number of seconds >= 0."""
    seconds("timeout", timeout, allow_zero=False)
    if poll is not None:
        seconds("poll", poll)


def check_choice(name: str, value: object, allowed: tuple[str, ...]) -> None:
    if value not in allowed:
        raise ArgumentError(
            f"{name} must be one of {', '.join(repr(a) for a in allowed)}, not {plain(value)}"
        )


def check_ics_list(ics: object) -> list[int]:
    """An iterable of ICS numbers as ints (one int is refused: ``[2]`` selects servo 2)."""
    if isinstance(ics, str | bytes) or not isinstance(ics, Iterable):
        raise ArgumentTypeError(
            f"ics must be an iterable of ICS numbers (e.g. [2]) or None, not {plain(ics)}"
        )
    return [integer("ICS number", k) for k in ics]


def servo_targets(
    positions: object, check_range: bool, *, override: str = OVERRIDE
) -> dict[int, int]:
    """``positions`` (ICS number -> raw position) as ints, each ICS number 0..35 and each
    position in the documented 3500..11500 (or hold/free), or 16 bits without ``check_range``.
    A position outside the range is refused with a message that tells to pass ``override``
    (``check_range=False``; the CLI says ``--unchecked``).
    """
    if not isinstance(positions, Mapping):
        raise ArgumentTypeError(
            f"positions must be a mapping of ICS number to position, not {plain(positions)}"
        )
    out: dict[int, int] = {}
    for key, value in positions.items():
        k = check_ics(key)
        p = integer(f"ICS {k}: position", value)
        if check_range:
            try:
                check_documented_position(k, p, override=override)
            except ValueError as exc:
                raise ArgumentError(str(exc)) from None
        elif not 0 <= p <= 0xFFFF:
            raise ArgumentError(f"ICS {k}: position {p} is not 16 bits (0..65535)")
        out[k] = p
    return out


def check_ics(ics: object) -> int:
    """An ICS number 0..35 as an int."""
    k = integer("ICS number", ics)
    if not 0 <= k < ICS_COUNT:
        raise ArgumentError(f"ICS number {k} outside 0..{ICS_COUNT - 1}")
    return k


def check_link_args(url: object, baudrate: object) -> int | None:
    """The checks of ``open(url, baudrate=...)``: ``url`` a str or None, ``baudrate`` an int
    > 0 or None (detect it); returns the baud rate as an int (or None)."""
    if url is not None and not isinstance(url, str):
        raise ArgumentTypeError(f"url must be a str (a port or URL) or None, not {plain(url)}")
    if baudrate is None:
        return None
    rate = integer("baudrate", baudrate)
    if rate <= 0:
        raise ArgumentError(f"baudrate must be > 0 (or None to detect it), not {rate}")
    return rate


def closed_error(url: str) -> TransportError:
    """What a call on a closed client raises."""
    return TransportError(f"{url}: the client is closed (reconnect() opens the link again)")
