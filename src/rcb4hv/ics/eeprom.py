"""The 64-byte ICS servo EEPROM: nibble packing and a typed model of its documented fields.

Each EEPROM byte carries 4 bits; a field of n bytes is a value of 4n bits, high nibble first
(FACTS "ICS 3.5 on the wire"; iory/rcb4 ``ics.py`` ``_4bit2num`` reads them the same way).
Fields by 1-based byte: 1-2 fixed 5Ah; 3-4 stretch (stored x2); 5-6 speed; 7-8 punch; 9-10
dead band; 11-12 damping; 13-14 safe timer; 15-16 flags (b7 slave, b4 rotation, b3 PWM
inhibit, b1 free, b0 reverse); 17-20 max pulse; 21-24 min pulse; 27-28 baud (low nibble 10 =
115200, 1 = 625000, 0 = 1,250,000); 29-30 temperature limit; 31-32 current limit; 51-52
response; 53-54 user offset; 57-58 ID; 59-64 stretch presets 1-3 (stored x2, like stretch).

Every other byte is "do not change": :class:`Eeprom` keeps the 64 bytes as read and only ever
rewrites the nibbles of a field that is set, so those bytes go back exactly as read.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any, Final

from rcb4hv.errors import IcsError
from rcb4hv.ics.codec import EEPROM_SIZE

__all__ = [
    "BAUD_CODES",
    "DEFAULT_EEPROM",
    "FIELDS",
    "RESERVED_BYTES",
    "Eeprom",
    "Field",
    "pack_nibbles",
    "unpack_nibbles",
]

HEADER: Final = 0x5A
# the baud nibble (bytes 27-28, low nibble) -> baud rate
BAUD_CODES: Final[Mapping[int, int]] = {10: 115200, 1: 625000, 0: 1250000}
_BAUD_OF: Final = {v: k for k, v in BAUD_CODES.items()}


def pack_nibbles(value: int, count: int) -> bytes:
    """``value`` as ``count`` EEPROM bytes of 4 bits each, high nibble first."""
    if count < 1 or not 0 <= value < 1 << (4 * count):
        raise ValueError(f"{value} does not fit {count} nibble(s)")
    return bytes((value >> (4 * (count - 1 - i))) & 0x0F for i in range(count))


def unpack_nibbles(data: bytes | bytearray | Iterable[int]) -> int:
    """The value of EEPROM bytes (4 bits each, high nibble first); upper bits are ignored."""
    v = 0
    for b in data:
        v = (v << 4) | (b & 0x0F)
    return v


@dataclass(frozen=True, slots=True)
class Field:
    """One documented EEPROM field: ``start`` is the 1-based first byte, ``count`` its bytes."""

    name: str
    start: int
    count: int
    low: int
    high: int
    scale: int = 1  # stored = value * scale (stretch and the presets are stored x2)
    signed: bool = False
    doc: str = ""

    @property
    def span(self) -> slice:
        return slice(self.start - 1, self.start - 1 + self.count)

    def decode(self, data: bytes) -> int:
        raw = unpack_nibbles(data[self.span])
        if self.signed and raw >= 1 << (4 * self.count - 1):
            raw -= 1 << (4 * self.count)
        return raw // self.scale

    def encode(self, value: int) -> bytes:
        if (
            isinstance(value, bool)
            or not isinstance(value, int)
            or not self.low <= value <= self.high
        ):
            raise ValueError(f"{self.name} {value!r} is not {self.low}..{self.high}")
        raw = value * self.scale
        if raw < 0:
            raw += 1 << (4 * self.count)
        return pack_nibbles(raw, self.count)


# ranges: stretch/speed/presets 1-127 (Kondo IcsClass setStrc/setSpd); 7-bit limits 1-127
# (temperature) and 1-63 (current: IcsClass setCur); pulses 3500-11500 (the position range);
# one-byte fields 0-255; the user offset a signed byte.
FIELDS: Final[tuple[Field, ...]] = (
    Field("stretch", 3, 2, 1, 127, scale=2, doc="holding stiffness (stored x2)"),
    Field("speed", 5, 2, 1, 127, doc="speed cap"),
    Field("punch", 7, 2, 0, 255, doc="minimum drive"),
    Field("dead_band", 9, 2, 0, 255, doc="dead band"),
    Field("damping", 11, 2, 0, 255, doc="damping"),
    Field("safe_timer", 13, 2, 0, 255, doc="safe timer"),
    Field("flags", 15, 2, 0, 255, doc="b7 slave, b4 rotation, b3 PWM inhibit, b1 free, b0 rev"),
    Field("max_pulse", 17, 4, 3500, 11500, doc="upper position limit"),
    Field("min_pulse", 21, 4, 3500, 11500, doc="lower position limit"),
    Field("baud_code", 27, 2, 0, 255, doc="baud: low nibble 10/1/0 = 115200/625000/1250000"),
    Field("temperature_limit", 29, 2, 1, 127, doc="temperature limit (lower is hotter)"),
    Field("current_limit", 31, 2, 1, 63, doc="current limit"),
    Field("response", 51, 2, 0, 255, doc="response"),
    Field("user_offset", 53, 2, -128, 127, signed=True, doc="user offset (signed)"),
    Field("id", 57, 2, 0, 31, doc="servo ID"),
    Field("stretch_1", 59, 2, 1, 127, scale=2, doc="stretch preset 1 (stored x2)"),
    Field("stretch_2", 61, 2, 1, 127, scale=2, doc="stretch preset 2 (stored x2)"),
    Field("stretch_3", 63, 2, 1, 127, scale=2, doc="stretch preset 3 (stored x2)"),
)
FIELD: Final = {f.name: f for f in FIELDS}
FLAG_BITS: Final = {"slave": 7, "rotation": 4, "pwm_inhibit": 3, "free": 1, "reverse": 0}
# 1-based bytes marked "do not change": 25-26, 33-50, 55-56 (and the fixed header 1-2)
RESERVED_BYTES: Final = tuple(
    b
    for b in range(1, EEPROM_SIZE + 1)
    if not any(f.start <= b < f.start + f.count for f in FIELDS)
)

# A real servo's EEPROM as iory/rcb4 ``ics.py`` ``set_default_eeprom_param`` writes it back:
# stretch 90, speed 127, punch 0, dead band 2, damping 30, safe timer 250, flags 06h, pulses
# 11500/3500, 1,250,000 baud, temperature limit 10, current limit 30, response 1, offset 0,
# ID 0, presets 30/60/127, and the "do not change" bytes of that servo.
DEFAULT_EEPROM: Final = bytes.fromhex(
    "050a0b04070f00000002010e0f0a0006020c0e0c000d0a0c00000000000a010e"
    "010209080e0d090d060e090b0a0c0905000e000100000d020000030c07080f0e"
)


@dataclass(frozen=True, slots=True)
class Eeprom:
    """The 64 EEPROM bytes of one servo, as read, with typed views of the documented fields."""

    data: bytes = DEFAULT_EEPROM

    def __post_init__(self) -> None:
        data = bytes(self.data)
        if len(data) != EEPROM_SIZE:
            raise IcsError(f"an ICS EEPROM has {EEPROM_SIZE} bytes, not {len(data)}")
        if any(b > 0x0F for b in data):
            raise IcsError("EEPROM bytes carry 4 bits each (0..15)")
        object.__setattr__(self, "data", data)

    # ---------------------------------------------------------------- fields

    def get(self, name: str) -> int:
        """A field (see :data:`FIELDS`) or a flag (``slave``, ``rotation``, ``pwm_inhibit``,
        ``free``, ``reverse``: 0 or 1)."""
        if name in FLAG_BITS:
            return (self.get("flags") >> FLAG_BITS[name]) & 1
        try:
            return FIELD[name].decode(self.data)
        except KeyError:
            raise ValueError(f"no EEPROM field {name!r}") from None

    def replace(self, **values: int) -> Eeprom:
        """A copy with the given fields (or flags) set; every other byte is kept as it is."""
        data = bytearray(self.data)
        for name, value in values.items():
            if name in FLAG_BITS:
                if value not in (0, 1):
                    raise ValueError(f"{name} is a flag: 0 or 1, not {value!r}")
                flags = unpack_nibbles(data[FIELD["flags"].span])
                bit = 1 << FLAG_BITS[name]
                flags = (flags | bit) if value else (flags & ~bit)
                data[FIELD["flags"].span] = pack_nibbles(flags, 2)
            elif name == "baud":
                code = _BAUD_OF.get(value)
                if code is None:
                    raise ValueError(f"baud {value} is not one of {sorted(_BAUD_OF)}")
                data[FIELD["baud_code"].span.start + 1] = code  # the low nibble: the rate
            elif name in FIELD:
                f = FIELD[name]
                encoded = f.encode(value)  # validates even when nothing changes
                if f.decode(bytes(data)) != value:  # an odd stored stretch stays as it was
                    data[f.span] = encoded
            else:
                raise ValueError(f"no EEPROM field {name!r}")
        return Eeprom(bytes(data))

    @property
    def header_ok(self) -> bool:
        return unpack_nibbles(self.data[0:2]) == HEADER

    @property
    def servo_id(self) -> int:
        return self.get("id")

    @property
    def stretch(self) -> int:
        return self.get("stretch")

    @property
    def speed(self) -> int:
        return self.get("speed")

    @property
    def baud(self) -> int | None:
        """The baud rate the servo talks at (None: a code no manual documents)."""
        return BAUD_CODES.get(self.get("baud_code") & 0x0F)

    def fields(self) -> dict[str, int | None]:
        """Every documented field and flag by name, plus ``baud`` (in baud)."""
        out: dict[str, int | None] = {f.name: self.get(f.name) for f in FIELDS}
        out.update({name: self.get(name) for name in FLAG_BITS})
        out["baud"] = self.baud
        return out

    def differences(self, other: Eeprom) -> dict[str, tuple[int | None, int | None]]:
        """Fields that differ: ``{name: (self's, other's)}``; reserved bytes as ``byte_N``."""
        a, b = self.fields(), other.fields()
        out = {k: (a[k], b[k]) for k in a if a[k] != b[k]}
        for n in RESERVED_BYTES:
            if self.data[n - 1] != other.data[n - 1]:
                out[f"byte_{n}"] = (self.data[n - 1], other.data[n - 1])
        return out

    def merged_from(self, backup: Eeprom) -> Eeprom:
        """``backup``'s writable bytes over this one's, keeping this EEPROM's "do not change"
        bytes and its ID (a restore must not renumber the servo it is written to)."""
        data = bytearray(backup.data)
        for n in RESERVED_BYTES:
            data[n - 1] = self.data[n - 1]
        data[FIELD["id"].span] = self.data[FIELD["id"].span]
        return Eeprom(bytes(data))

    # ---------------------------------------------------------------- JSON

    def to_json(self) -> dict[str, Any]:
        """``{"format": ..., "fields": {...}, "bytes": [64 ints]}`` (the bytes are what counts)."""
        return {"format": "rcb4hv-ics-eeprom/1", "fields": self.fields(), "bytes": list(self.data)}

    @classmethod
    def from_json(cls, obj: object) -> Eeprom:
        """Read :meth:`to_json`'s output back (its ``bytes``); :class:`IcsError` if malformed."""
        if not isinstance(obj, dict) or obj.get("format") != "rcb4hv-ics-eeprom/1":
            raise IcsError("not an rcb4hv ICS EEPROM backup (format rcb4hv-ics-eeprom/1)")
        raw = obj.get("bytes")
        if not isinstance(raw, list) or not all(isinstance(b, int) for b in raw):
            raise IcsError("an EEPROM backup needs a list of 64 integers under 'bytes'")
        if not all(0 <= b <= 0x0F for b in raw) or len(raw) != EEPROM_SIZE:
            raise IcsError("an EEPROM backup needs 64 bytes of 0..15")
        return cls(bytes(raw))
