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

__all__ = ["AD_MAX", "AdConverter"]

AD_MAX: Final = 1023  # a 10-bit converter
_WORDS: Final = struct.Struct(f"<{AD_CHANNELS}H")  # the 11 references, the 11 measured words


class AdConverter:
    """The inputs of the 11 channels and their sampling into ``ram``."""

    def __init__(self, ram: bytearray, inputs: Iterable[int]) -> None:
        self.ram = ram
        self.inputs = list(inputs)

    @staticmethod
    def check(channel: int, counts: int) -> None:
        """ValueError unless ``channel`` is AD0-AD10 and ``counts`` 0..1023."""
        if not 0 <= channel < AD_CHANNELS or not 0 <= counts <= AD_MAX:
            raise ValueError(f"AD channels 0-{AD_CHANNELS - 1} take inputs of 0..{AD_MAX}")

    def clamp(self, channel: int, counts: int) -> None:
        """Set one input clamped to 0..1023 (a backend's measurement)."""
        if not 0 <= channel < AD_CHANNELS:
            raise ValueError("AD channels are 0-10")
        self.inputs[channel] = min(max(counts, 0), AD_MAX)

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
