"""The board's AD converter: AD0-AD10, 10 bits over 0-5 V (spec 10.4).

What each pin sees (its **input**, 0..1023 counts) is the world outside the board: set by the
host, a servo backend or the sensors at rest, and kept across a reset. Each output period,
and when the program writes a reference, the board **samples**: the measured register of a
channel (RAM 0022h + 2 x channel) gets its input minus its reference (000Ch + 2 x channel),
signed in the 16-bit word.
"""

from __future__ import annotations

import struct
from collections.abc import Iterable
from typing import Final

from rcb4hv.emulator.memmap import AD_CHANNELS, AD_REFERENCE, AD_VALUES, read_u16, s16
from rcb4hv.errors import ArgumentError, ArgumentTypeError
from rcb4hv.values import as_index, plain

__all__ = ["AD_MAX", "AdConverter", "check_input"]

AD_MAX: Final = 1023  # a 10-bit converter
_WORDS: Final = struct.Struct(f"<{AD_CHANNELS}H")  # the 11 references, the 11 measured words


def check_input(channel: object, counts: object, *, first: int = 0) -> tuple[int, int]:
    """``(channel, counts)`` as ints: the one rule for an AD input a host hook sets
    (:meth:`Board.set_ad_input`, :meth:`Board.measure`, ``emulate --ad`` and ``?adCH=`` with
    ``first=1``: AD0 is the supply). :class:`~rcb4hv.errors.ArgumentTypeError` (a TypeError)
    for a channel or count that is not an int, :class:`~rcb4hv.errors.ArgumentError` (a
    ValueError) for a channel outside ``first``..10 or counts outside 0..1023."""
    ch = as_index(channel)
    if ch is None:
        raise ArgumentTypeError(f"AD channel must be an int, not {plain(channel)}")
    if not first <= ch < AD_CHANNELS:
        supply = " (AD0 is the supply)" if first else ""
        raise ArgumentError(f"AD{ch}: inputs are set on AD{first}-AD{AD_CHANNELS - 1}{supply}")
    n = as_index(counts)
    if n is None:
        raise ArgumentTypeError(f"AD{ch}: the input must be an int (counts), not {plain(counts)}")
    if not 0 <= n <= AD_MAX:
        raise ArgumentError(f"AD{ch}: the input {n} is outside 0..{AD_MAX} counts")
    return ch, n


class AdConverter:
    """The inputs of the 11 channels and their sampling into ``ram``."""

    def __init__(self, ram: bytearray, inputs: Iterable[int]) -> None:
        self.ram = ram
        self.inputs = list(inputs)

    def sample(self) -> None:
        """Each measured register gets the channel's input minus its reference."""
        r = self.ram
        refs = _WORDS.unpack_from(r, AD_REFERENCE)
        measured = [(v - ref) & 0xFFFF for v, ref in zip(self.inputs, refs, strict=True)]
        _WORDS.pack_into(r, AD_VALUES, *measured)

    def reference(self, channel: int) -> int:
        """The reference word of AD``channel`` (RAM 000Ch + 2 x channel)."""
        return read_u16(self.ram, AD_REFERENCE + 2 * channel)

    def measured(self, channel: int) -> int:
        """The measured register of AD``channel`` (RAM 0022h + 2 x channel), signed."""
        return s16(read_u16(self.ram, AD_VALUES + 2 * channel))
