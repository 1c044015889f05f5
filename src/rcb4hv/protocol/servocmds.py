"""Servo commands (0Fh, 10h, 11h, 12h speed/stretch) and the system commands (FDh, FEh).

Each class owns its codec: ``encode()`` builds the frame, ``from_frame`` parses one. The
frame layouts and packers live in :mod:`rcb4hv.protocol.servopack`.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import ClassVar, Final

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.frame import build_frame
from rcb4hv.protocol.operands import ICS_COUNT, Op, check_ics, check_int, check_position
from rcb4hv.protocol.servopack import pack_const_frame, pack_single_servo, servo_set

__all__ = [
    "AcknowledgeCheck",
    "GetVersionInfo",
    "RunConstFrameServo",
    "RunSeriesServo",
    "RunSingleServo",
    "SetSpeed",
    "SetStretch",
    "SpeedStretch",
    "move_periods",
]


def move_periods(speed: int) -> int:
    """Output periods a ROM program's servo move of ``speed`` frames holds the program: the
    servo reaches its end in ``speed`` periods and its update flag clears in the next (spec 9,
    the firmware's interpolation), and only then is the next instruction fetched. The one
    rule the walk generator, ``project ease`` and a host playing poses time themselves by."""
    return speed + 1


def _bitmap(ics_numbers: Iterable[int], flag: bool) -> bytes:
    m = 0
    for k in ics_numbers:
        m |= 1 << k
    if flag:
        m |= 1 << 39
    return m.to_bytes(5, "little")


def _bitmap_ics(m: bytes, allow_flag: bool) -> tuple[list[int], bool]:
    value = int.from_bytes(m, "little")
    if value & (0x7 << 36):
        raise ProtocolError("servo bitmap: M4 bits 4-6 must be 0")
    flag = bool(value & (1 << 39))
    if flag and not allow_flag:
        raise ProtocolError("servo bitmap: M4 bit 7 must be 0 for this command")
    return [k for k in range(ICS_COUNT) if value >> k & 1], flag


_INT_ONLY: Final = frozenset((int,))


def _plain_pairs(items: object, value_max: int) -> tuple[tuple[int, int], ...] | None:
    """Fast path of :func:`_normalise_pairs`: a non-empty dict of int ICS numbers 0-35 to int
    values 0..``value_max``, sorted; None for anything else (the slow path decides)."""
    if type(items) is not dict or not items or not set(map(type, items)) <= _INT_ONLY:
        return None
    servos = servo_set(tuple(items))
    if servos is None:
        return None
    keys = servos[0]
    values = list(map(items.__getitem__, keys))
    if not set(map(type, values)) <= _INT_ONLY or min(values) < 0 or max(values) > value_max:
        return None
    return tuple(zip(keys, values, strict=True))


def _normalise_pairs(
    name: str, items: Mapping[int, int] | Iterable[tuple[int, int]], check: Callable[[int], None]
) -> tuple[tuple[int, int], ...]:
    pairs = list(items.items()) if isinstance(items, Mapping) else [tuple(p) for p in items]
    out: list[tuple[int, int]] = []
    seen: set[int] = set()
    for p in pairs:
        if len(p) != 2:
            raise ValueError(f"{name}: expected (ics, value) pairs")
        ics, value = p
        check_ics(ics)
        if ics in seen:
            raise ValueError(f"{name}: ICS {ics} given twice")
        seen.add(ics)
        check(value)
        out.append((ics, value))
    out.sort()
    return tuple(out)


@dataclass(frozen=True, slots=True)
class RunSingleServo:
    """0Fh: move one servo to ``position`` in ``speed`` output periods.

    With ``set_update_flag`` (the default, bit 7 of the ICS byte clear) this servo's update flag
    is set and all others are cleared.
    """

    ics: int
    speed: int
    position: int
    set_update_flag: bool = True
    cmd: ClassVar[int] = Op.SINGLE_SERVO

    def __post_init__(self) -> None:
        ics, speed, position = self.ics, self.speed, self.position
        if (  # fast path: plain ints in range, checked at once
            type(ics) is int
            and type(speed) is int
            and type(position) is int
            and 0 <= ics <= 0x7F
            and 0 <= speed <= 0xFF
            and 0 <= position <= 0xFFFF
        ):
            return
        # bits 6-0 of the ICS byte: any value decodes; ICS 36-127 have no allocation entry and
        # are skipped like an unallocated slot (the robot level and the lint check 0-35)
        check_int("ICS number", ics, 0, 0x7F)
        check_int("speed", speed, 0, 255)
        check_position(position)

    def encode(self) -> bytes:
        return pack_single_servo(self.ics, self.speed, self.position, bool(self.set_update_flag))

    @classmethod
    def from_frame(cls, frame: bytes) -> RunSingleServo:
        if len(frame) != 7:
            raise ProtocolError("RunSingleServo frames are 7 bytes")
        b = frame[2]
        return cls(b & 0x7F, frame[3], frame[4] | frame[5] << 8, not b & 0x80)

    @property
    def reply_data_size(self) -> int | None:
        return None


def _check_speed(v: int) -> None:
    check_int("speed", v, 0, 255)


@dataclass(frozen=True, slots=True)
class RunConstFrameServo:
    """10h: move several servos with one speed; ``positions`` are (ics, position) pairs."""

    speed: int
    positions: tuple[tuple[int, int], ...]
    set_update_flag: bool = True
    cmd: ClassVar[int] = Op.CONST_FRAME_SERVO

    def __init__(
        self,
        speed: int,
        positions: Mapping[int, int] | Iterable[tuple[int, int]],
        set_update_flag: bool = True,
    ) -> None:
        if type(speed) is not int or not 0 <= speed <= 0xFF:
            _check_speed(speed)
        pairs = _plain_pairs(positions, 0xFFFF)
        if pairs is None:
            pairs = _normalise_pairs("RunConstFrameServo", positions, check_position)
        object.__setattr__(self, "speed", speed)
        object.__setattr__(self, "positions", pairs)
        object.__setattr__(self, "set_update_flag", bool(set_update_flag))

    def encode(self) -> bytes:
        pairs = self.positions
        if not pairs:
            return pack_const_frame(self.speed, (), (), self.set_update_flag)
        ics, positions = zip(*pairs, strict=True)
        return pack_const_frame(self.speed, ics, positions, self.set_update_flag)

    @classmethod
    def from_frame(cls, frame: bytes) -> RunConstFrameServo:
        ics, flag = _bitmap_ics(frame[2:7], True)
        if len(frame) != 9 + 2 * len(ics):
            raise ProtocolError(f"RunConstFrameServo for {len(ics)} servos: wrong frame length")
        pos = [frame[8 + 2 * i] | frame[9 + 2 * i] << 8 for i in range(len(ics))]
        return cls(frame[7], zip(ics, pos, strict=True), not flag)

    @property
    def reply_data_size(self) -> int | None:
        return None


@dataclass(frozen=True, slots=True)
class RunSeriesServo:
    """11h: move several servos, each with its own speed: (ics, speed, position) triples."""

    moves: tuple[tuple[int, int, int], ...]
    set_update_flag: bool = True
    cmd: ClassVar[int] = Op.SERIES_SERVO

    def __init__(self, moves: Iterable[tuple[int, int, int]], set_update_flag: bool = True) -> None:
        items = [tuple(m) for m in moves]
        seen: set[int] = set()
        out: list[tuple[int, int, int]] = []
        for m in items:
            if len(m) != 3:
                raise ValueError("RunSeriesServo: expected (ics, speed, position) triples")
            ics, speed, pos = m
            check_ics(ics)
            if ics in seen:
                raise ValueError(f"RunSeriesServo: ICS {ics} given twice")
            seen.add(ics)
            _check_speed(speed)
            check_position(pos)
            out.append((ics, speed, pos))
        out.sort()
        object.__setattr__(self, "moves", tuple(out))
        object.__setattr__(self, "set_update_flag", bool(set_update_flag))

    def encode(self) -> bytes:
        body = bytearray(_bitmap((k for k, _, _ in self.moves), not self.set_update_flag))
        for _, s, p in self.moves:
            body += bytes((s, p & 0xFF, p >> 8))
        return build_frame(self.cmd, body)

    @classmethod
    def from_frame(cls, frame: bytes) -> RunSeriesServo:
        ics, flag = _bitmap_ics(frame[2:7] if len(frame) >= 8 else b"", True)
        if len(frame) != 8 + 3 * len(ics):
            raise ProtocolError(f"RunSeriesServo for {len(ics)} servos: wrong frame length")
        moves = [
            (k, frame[7 + 3 * i], frame[8 + 3 * i] | frame[9 + 3 * i] << 8)
            for i, k in enumerate(ics)
        ]
        return cls(moves, not flag)

    @property
    def reply_data_size(self) -> int | None:
        return None


def _check_stretch_value(v: int) -> None:
    # Any byte: the reference documents 1-127, but real HeartToHeart4 motions hold 0 and the
    # board runs them. The documented range lives in rcb4hv.protocol.ranges (robot level, lint).
    check_int("value", v, 0, 0xFF)


@dataclass(frozen=True, slots=True)
class SpeedStretch:
    values: tuple[tuple[int, int], ...]
    cmd: ClassVar[int] = Op.SPEED_STRETCH
    sub: ClassVar[int] = 0

    def __init__(self, values: Mapping[int, int] | Iterable[tuple[int, int]]) -> None:
        object.__setattr__(
            self, "values", _normalise_pairs(type(self).__name__, values, _check_stretch_value)
        )

    def encode(self) -> bytes:
        body = bytearray(_bitmap((k for k, _ in self.values), False))
        body.append(self.sub)
        body += bytes(v for _, v in self.values)
        return build_frame(self.cmd, body)

    @staticmethod
    def from_frame(frame: bytes) -> SpeedStretch:
        """SetStretch or SetSpeed, by the sub-command byte (both share the 12h decoder)."""
        if len(frame) < 9:
            raise ProtocolError("SetSpeed/SetStretch frames are at least 9 bytes")
        ics, _ = _bitmap_ics(frame[2:7], False)
        if len(frame) != 9 + len(ics):
            raise ProtocolError(f"SetSpeed/SetStretch for {len(ics)} servos: wrong frame length")
        sub = frame[7]
        values = zip(ics, frame[8:-1], strict=True)
        for kind in (SetStretch, SetSpeed):
            if kind.sub == sub:
                return kind(values)
        raise ProtocolError(f"12h sub-command {sub:02X} is neither 01 (stretch) nor 02 (speed)")

    @property
    def reply_data_size(self) -> int | None:
        return None


@dataclass(frozen=True, slots=True, init=False)
class SetStretch(SpeedStretch):
    """12h sub 01: servo stretch (holding gain) per servo; documented 1-127, any byte here."""

    sub: ClassVar[int] = 0x01


@dataclass(frozen=True, slots=True, init=False)
class SetSpeed(SpeedStretch):
    """12h sub 02: servo speed parameter per servo; documented 1-127, any byte here."""

    sub: ClassVar[int] = 0x02


# --------------------------------------------------------------------------- system


@dataclass(frozen=True, slots=True)
class GetVersionInfo:
    """FDh: ask for the 32-byte version string (``03 FD 00``)."""

    cmd: ClassVar[int] = Op.VERSION

    def encode(self) -> bytes:
        return b"\x03\xfd\x00"

    @classmethod
    def from_frame(cls, frame: bytes) -> GetVersionInfo:
        if frame != b"\x03\xfd\x00":
            raise ProtocolError("version request is 03 FD 00")
        return cls()

    @property
    def reply_data_size(self) -> int | None:
        return 32


@dataclass(frozen=True, slots=True)
class AcknowledgeCheck:
    """FEh: link check. ``03 FE 01``, or with ``long_form`` ``04 FE 06 08``."""

    long_form: bool = False
    cmd: ClassVar[int] = Op.ACK_CHECK

    def encode(self) -> bytes:
        return b"\x04\xfe\x06\x08" if self.long_form else b"\x03\xfe\x01"

    @classmethod
    def from_frame(cls, frame: bytes) -> AcknowledgeCheck:
        if frame == b"\x03\xfe\x01":
            return cls()
        if frame == b"\x04\xfe\x06\x08":
            return cls(long_form=True)
        raise ProtocolError("acknowledge check is 03 FE 01 or 04 FE 06 08")

    @property
    def reply_data_size(self) -> int | None:
        return None
