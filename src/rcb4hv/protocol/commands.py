"""One frozen dataclass per command of the RCB-4HV command reference, with encode/decode.

Every class validates its fields on construction (``ValueError`` for anything out of range),
:func:`encode_command` turns a command into its frame and :func:`decode_command` turns a frame
back into a command, raising :class:`~rcb4hv.errors.ProtocolError` for anything that is not a
valid command frame. ``decode_command(encode_command(c)) == c`` and
``encode_command(decode_command(f)) == f`` hold for every command and every valid frame.

Operands of the data commands (spec section 4) are small typed objects: :class:`Ram`,
:class:`Ics`, :class:`Rom` and :class:`Com` as destinations, :class:`Ram`, :class:`Ics`,
:class:`Rom` and :class:`Data` (literal bytes carried in the frame) as sources.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import ClassVar, Final, cast

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol.frame import MAX_FRAME_SIZE, build_frame, check_frame
from rcb4hv.protocol.servoframes import pack_const_frame, pack_single_servo, servo_set

__all__ = [
    "ALWAYS",
    "AcknowledgeCheck",
    "Add",
    "And",
    "Call",
    "Com",
    "Command",
    "CommunicateDevice",
    "Condition",
    "Data",
    "Destination",
    "Div",
    "GetVersionInfo",
    "Ics",
    "Jump",
    "Mod",
    "Move",
    "Mul",
    "Not",
    "Op",
    "Or",
    "Ram",
    "Return",
    "Rom",
    "RunConstFrameServo",
    "RunSeriesServo",
    "RunSingleServo",
    "SetSpeed",
    "SetStretch",
    "Shift",
    "Source",
    "Sub",
    "Xor",
    "decode_command",
    "encode_command",
    "is_valid_position",
]


class Op:
    """Command bytes (the CMD field of a frame)."""

    MOVE: Final = 0x00
    AND: Final = 0x01
    OR: Final = 0x02
    XOR: Final = 0x03
    NOT: Final = 0x04
    SHIFT: Final = 0x05
    ADD: Final = 0x06
    SUB: Final = 0x07
    MUL: Final = 0x08
    DIV: Final = 0x09
    MOD: Final = 0x0A
    JUMP: Final = 0x0B
    CALL: Final = 0x0C
    RETURN: Final = 0x0D
    ICS_COMM: Final = 0x0E
    SINGLE_SERVO: Final = 0x0F
    CONST_FRAME_SERVO: Final = 0x10
    SERIES_SERVO: Final = 0x11
    SPEED_STRETCH: Final = 0x12
    VERSION: Final = 0xFD
    ACK_CHECK: Final = 0xFE


RAM_SIZE: Final = 0x0490
ROM_SIZE: Final = 0x40000
ICS_COUNT: Final = 36
MAX_LITERAL: Final = MAX_FRAME_SIZE - 7
POSITION_MIN: Final = 3500
POSITION_MAX: Final = 11500
POSITION_HOLD: Final = 0x7FFF
POSITION_FREE: Final = 0x8000

# operand kind codes of the type byte
KIND_RAM: Final = 0
KIND_ICS: Final = 1
KIND_COM: Final = 2
KIND_ROM: Final = 3
_KIND_NAMES: Final = ("RAM", "ICS", "COM", "ROM")


def _check_int(name: str, value: int, lo: int, hi: int) -> None:
    if not isinstance(value, int) or isinstance(value, bool):
        raise ValueError(f"{name} must be an int, not {type(value).__name__}")
    if not lo <= value <= hi:
        raise ValueError(f"{name} {value!r} out of range {lo}..{hi}")


def _check_ics(ics: int) -> None:
    _check_int("ICS number", ics, 0, ICS_COUNT - 1)


def is_valid_position(position: int) -> bool:
    """True for 3500..11500 and the special values 0x7FFF (hold) and 0x8000 (free)."""
    return POSITION_MIN <= position <= POSITION_MAX or position in (POSITION_HOLD, POSITION_FREE)


def _check_position(position: int) -> None:
    # The wire carries any 16-bit value and real HeartToHeart4 projects use values outside the
    # documented 3500..11500 (e.g. 2100, 12700), so the command layer accepts the full range;
    # the robot-level client applies the documented range (see is_valid_position).
    _check_int("position", position, 0, 0xFFFF)


# --------------------------------------------------------------------------- operands


@dataclass(frozen=True, slots=True)
class Ram:
    """RAM address 0000h-048Fh."""

    address: int
    kind: ClassVar[int] = KIND_RAM

    def __post_init__(self) -> None:
        _check_int("RAM address", self.address, 0, RAM_SIZE - 1)

    def span_ok(self, size: int) -> bool:
        return self.address + size <= RAM_SIZE


@dataclass(frozen=True, slots=True)
class Ics:
    """Byte ``offset`` inside the device block of ICS number ``ics`` (RAM alloc[ics] + offset)."""

    offset: int
    ics: int
    kind: ClassVar[int] = KIND_ICS

    def __post_init__(self) -> None:
        _check_int("ICS offset", self.offset, 0, 0xFF)
        _check_ics(self.ics)

    def span_ok(self, size: int) -> bool:
        return True


@dataclass(frozen=True, slots=True)
class Rom:
    """ROM (EEPROM) address 000000h-03FFFFh."""

    address: int
    kind: ClassVar[int] = KIND_ROM

    def __post_init__(self) -> None:
        _check_int("ROM address", self.address, 0, ROM_SIZE - 1)

    def span_ok(self, size: int) -> bool:
        return self.address + size <= ROM_SIZE


@dataclass(frozen=True, slots=True)
class Com:
    """The host: as a destination, the result is sent back in the reply."""

    kind: ClassVar[int] = KIND_COM

    def span_ok(self, size: int) -> bool:
        return True


@dataclass(frozen=True, slots=True)
class Data:
    """Literal bytes carried in the frame (source kind COM)."""

    data: bytes
    kind: ClassVar[int] = KIND_COM

    def __post_init__(self) -> None:
        if not isinstance(self.data, bytes):
            object.__setattr__(self, "data", bytes(self.data))
        if not 1 <= len(self.data) <= MAX_LITERAL:
            raise ValueError(f"literal of {len(self.data)} bytes; must be 1..{MAX_LITERAL}")

    def span_ok(self, size: int) -> bool:
        return True


Destination = Ram | Ics | Com | Rom
Source = Ram | Ics | Rom | Data


def _dst_bytes(dst: Destination) -> bytes:
    if isinstance(dst, Ram):
        return bytes((dst.address & 0xFF, dst.address >> 8, 0))
    if isinstance(dst, Ics):
        return bytes((dst.offset, dst.ics, 0))
    if isinstance(dst, Rom):
        a = dst.address
        return bytes((a & 0xFF, (a >> 8) & 0xFF, a >> 16))
    return b"\x00\x00\x00"


def _src_bytes(src: Source, size: int) -> bytes:
    if isinstance(src, Data):
        return src.data
    if isinstance(src, Ram):
        return bytes((src.address & 0xFF, src.address >> 8, size))
    if isinstance(src, Ics):
        return bytes((src.offset, src.ics, size))
    a = src.address
    return bytes((a & 0xFF, (a >> 8) & 0xFF, a >> 16, size))


# --------------------------------------------------------------------------- data commands


def _validate_operands(
    name: str,
    dst: Destination,
    src: Source | None,
    size: int,
    max_size: int,
    allowed_dst: tuple[type, ...],
) -> None:
    if not isinstance(dst, allowed_dst):
        raise ValueError(f"{name}: destination {type(dst).__name__} is not allowed")
    if src is not None and not isinstance(src, (Ram, Ics, Rom, Data)):
        raise ValueError(f"{name}: source must be Ram, Ics, Rom or Data")
    _check_int(f"{name} size", size, 1, max_size)
    if not dst.span_ok(size):
        raise ValueError(f"{name}: destination {dst} + {size} bytes runs past the end")
    if src is not None and not src.span_ok(size):
        raise ValueError(f"{name}: source {src} + {size} bytes runs past the end")


def _resolve_size(src: Source, size: int | None) -> int:
    if isinstance(src, Data):
        if size is not None and size != len(src.data):
            raise ValueError(f"size {size} does not match the {len(src.data)}-byte literal")
        return len(src.data)
    if size is None:
        raise ValueError("size is required unless the source is a Data literal")
    return size


@dataclass(frozen=True, slots=True)
class Move:
    """00h MOVE: ``dst <- src`` over ``size`` bytes. ``dst=Com()`` reads data to the host."""

    dst: Destination
    src: Source
    size: int | None = None
    cmd: ClassVar[int] = Op.MOVE

    def __post_init__(self) -> None:
        size = _resolve_size(self.src, self.size)
        object.__setattr__(self, "size", size)
        _validate_operands("MOVE", self.dst, self.src, size, 128, (Ram, Ics, Com, Rom))

    @property
    def nbytes(self) -> int:
        """The operation size in bytes."""
        assert self.size is not None
        return self.size

    def encode(self) -> bytes:
        t = (self.dst.kind << 4) | self.src.kind
        return build_frame(
            self.cmd, bytes((t,)) + _dst_bytes(self.dst) + _src_bytes(self.src, self.nbytes)
        )

    @property
    def reply_data_size(self) -> int | None:
        """Bytes of data in the reply (None: the reply is an ACK)."""
        return self.nbytes if isinstance(self.dst, Com) else None


@dataclass(frozen=True, slots=True)
class _BinaryOp:
    dst: Destination
    src: Source
    size: int | None = None
    no_write: bool = False
    cmd: ClassVar[int] = -1
    name: ClassVar[str] = ""
    max_size: ClassVar[int] = 128
    allowed_dst: ClassVar[tuple[type, ...]] = (Ram, Ics, Rom)

    def __post_init__(self) -> None:
        size = _resolve_size(self.src, self.size)
        object.__setattr__(self, "size", size)
        if not isinstance(self.no_write, bool):
            raise ValueError("no_write must be a bool")
        _validate_operands(self.name, self.dst, self.src, size, self.max_size, self.allowed_dst)

    @property
    def nbytes(self) -> int:
        assert self.size is not None
        return self.size

    def encode(self) -> bytes:
        t = (0x80 if self.no_write else 0) | (self.dst.kind << 4) | self.src.kind
        return build_frame(
            self.cmd, bytes((t,)) + _dst_bytes(self.dst) + _src_bytes(self.src, self.nbytes)
        )

    @property
    def reply_data_size(self) -> int | None:
        return self.nbytes


@dataclass(frozen=True, slots=True)
class And(_BinaryOp):
    """01h AND: ``dst &= src``; Z = result is zero."""

    cmd: ClassVar[int] = Op.AND
    name: ClassVar[str] = "AND"


@dataclass(frozen=True, slots=True)
class Or(_BinaryOp):
    """02h OR: ``dst |= src``; Z = result is zero."""

    cmd: ClassVar[int] = Op.OR
    name: ClassVar[str] = "OR"


@dataclass(frozen=True, slots=True)
class Xor(_BinaryOp):
    """03h XOR: ``dst ^= src``; Z = result is zero."""

    cmd: ClassVar[int] = Op.XOR
    name: ClassVar[str] = "XOR"


_ARITH_DST: Final = (Ram, Ics, Com, Rom)


@dataclass(frozen=True, slots=True)
class Add(_BinaryOp):
    """06h ADD (1 or 2 bytes): C = carry out of the width."""

    cmd: ClassVar[int] = Op.ADD
    name: ClassVar[str] = "ADD"
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Sub(_BinaryOp):
    """07h SUB (1 or 2 bytes): C = 1 unless it borrowed (C = dst >= src)."""

    cmd: ClassVar[int] = Op.SUB
    name: ClassVar[str] = "SUB"
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Mul(_BinaryOp):
    """08h MUL (1 or 2 bytes, low bytes kept): C = the product overflowed."""

    cmd: ClassVar[int] = Op.MUL
    name: ClassVar[str] = "MUL"
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Div(_BinaryOp):
    """09h DIV (1 or 2 bytes, unsigned integer division)."""

    cmd: ClassVar[int] = Op.DIV
    name: ClassVar[str] = "DIV"
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class Mod(_BinaryOp):
    """0Ah MOD (1 or 2 bytes, unsigned remainder)."""

    cmd: ClassVar[int] = Op.MOD
    name: ClassVar[str] = "MOD"
    max_size: ClassVar[int] = 2
    allowed_dst: ClassVar[tuple[type, ...]] = _ARITH_DST


@dataclass(frozen=True, slots=True)
class _UnaryOp:
    dst: Destination
    size: int
    no_write: bool = False
    cmd: ClassVar[int] = -1
    name: ClassVar[str] = ""

    def __post_init__(self) -> None:
        if not isinstance(self.no_write, bool):
            raise ValueError("no_write must be a bool")
        _validate_operands(self.name, self.dst, None, self.size, 128, (Ram, Ics, Rom))

    @property
    def nbytes(self) -> int:
        return self.size

    def _operand_byte(self) -> int:
        return 0

    def encode(self) -> bytes:
        t = (0x80 if self.no_write else 0) | (self.dst.kind << 4)
        return build_frame(
            self.cmd,
            bytes((t,)) + _dst_bytes(self.dst) + bytes((0, self._operand_byte(), self.size)),
        )

    @property
    def reply_data_size(self) -> int | None:
        return self.size


@dataclass(frozen=True, slots=True)
class Not(_UnaryOp):
    """04h NOT: ``dst = ~dst`` (frame ``0A 04 TYPE D0 D1 D2 00 00 SIZE SUM``)."""

    cmd: ClassVar[int] = Op.NOT
    name: ClassVar[str] = "NOT"


@dataclass(frozen=True, slots=True)
class Shift(_UnaryOp):
    """05h SHIFT: count 1-127 shifts right by count, 128-255 left by 256 - count; 0 no shift.

    Frame ``0A 05 TYPE D0 D1 D2 00 COUNT SIZE SUM``. The whole ``size``-byte value shifts
    as one little-endian integer; C = the last bit shifted out.
    """

    count: int = 0
    cmd: ClassVar[int] = Op.SHIFT
    name: ClassVar[str] = "SHIFT"

    def __post_init__(self) -> None:
        _check_int("SHIFT count", self.count, 0, 0xFF)
        _UnaryOp.__post_init__(self)

    def _operand_byte(self) -> int:
        return self.count

    @property
    def right_bits(self) -> int:
        """Signed shift: positive = right by that many bits, negative = left."""
        return self.count if self.count < 128 else self.count - 256

    @classmethod
    def right(cls, dst: Destination, bits: int, size: int, no_write: bool = False) -> Shift:
        """Shift right by 0..127 bits."""
        _check_int("right shift", bits, 0, 127)
        return cls(dst, size, no_write, bits)

    @classmethod
    def left(cls, dst: Destination, bits: int, size: int, no_write: bool = False) -> Shift:
        """Shift left by 1..128 bits (count byte 256 - bits)."""
        _check_int("left shift", bits, 1, 128)
        return cls(dst, size, no_write, 256 - bits)


# --------------------------------------------------------------------------- control flow


@dataclass(frozen=True, slots=True)
class Condition:
    """The COND byte of JUMP/CALL: each enabled comparison must match (AND)."""

    compare_z: bool = False
    z: bool = False
    compare_c: bool = False
    c: bool = False

    @classmethod
    def from_byte(cls, value: int) -> Condition:
        _check_int("condition byte", value, 0, 0x0F)
        return cls(bool(value & 4), bool(value & 1), bool(value & 8), bool(value & 2))

    def to_byte(self) -> int:
        return (
            (1 if self.z else 0)
            | (2 if self.c else 0)
            | (4 if self.compare_z else 0)
            | (8 if self.compare_c else 0)
        )

    def holds(self, z: bool, c: bool) -> bool:
        """Whether the branch is taken for flags ``z`` and ``c``."""
        if self.compare_z and z != self.z:
            return False
        return not (self.compare_c and c != self.c)

    @classmethod
    def if_zero(cls) -> Condition:
        return cls(compare_z=True, z=True)

    @classmethod
    def if_not_zero(cls) -> Condition:
        return cls(compare_z=True, z=False)

    @classmethod
    def if_carry(cls) -> Condition:
        return cls(compare_c=True, c=True)

    @classmethod
    def if_not_carry(cls) -> Condition:
        return cls(compare_c=True, c=False)

    def __str__(self) -> str:
        parts = []
        if self.compare_z:
            parts.append("Z" if self.z else "NZ")
        if self.compare_c:
            parts.append("C" if self.c else "NC")
        return "&".join(parts) if parts else "ALWAYS"


ALWAYS: Final = Condition()


@dataclass(frozen=True, slots=True)
class _Branch:
    address: int
    condition: Condition = ALWAYS
    cmd: ClassVar[int] = -1

    def __post_init__(self) -> None:
        # 24 bits on the wire; HeartToHeart4 flowcharts hold FFFFFF for unresolved targets.
        _check_int("branch address", self.address, 0, 0xFFFFFF)
        if not isinstance(self.condition, Condition):
            raise ValueError("condition must be a Condition")

    def encode(self) -> bytes:
        a = self.address
        return build_frame(
            self.cmd, bytes((a & 0xFF, (a >> 8) & 0xFF, a >> 16, self.condition.to_byte()))
        )

    @property
    def reply_data_size(self) -> int | None:
        return None


@dataclass(frozen=True, slots=True)
class Jump(_Branch):
    """0Bh JUMP: PC <- address if the condition holds."""

    cmd: ClassVar[int] = Op.JUMP


@dataclass(frozen=True, slots=True)
class Call(_Branch):
    """0Ch CALL: push the next PC and jump if the condition holds (16 levels)."""

    cmd: ClassVar[int] = Op.CALL


@dataclass(frozen=True, slots=True)
class Return:
    """0Dh RETURN: pop the PC (``03 0D 10``)."""

    cmd: ClassVar[int] = Op.RETURN

    def encode(self) -> bytes:
        return b"\x03\x0d\x10"

    @property
    def reply_data_size(self) -> int | None:
        return None


@dataclass(frozen=True, slots=True)
class CommunicateDevice:
    """0Eh ICS communication: send ``tx_count`` bytes from RAM ``tx_address`` to a device.

    The reference says this command has a specification problem and must not be used.
    """

    ics: int
    tx_count: int
    tx_address: int
    rx_address: int
    cmd: ClassVar[int] = Op.ICS_COMM

    def __post_init__(self) -> None:
        _check_ics(self.ics)
        _check_int("TX count", self.tx_count, 1, 64)
        _check_int("TX address", self.tx_address, 0, RAM_SIZE - self.tx_count)
        _check_int("RX address", self.rx_address, 0, RAM_SIZE - 1)

    def encode(self) -> bytes:
        tx, rx = self.tx_address, self.rx_address
        return build_frame(
            self.cmd, bytes((self.ics, self.tx_count, tx & 0xFF, tx >> 8, rx & 0xFF, rx >> 8))
        )

    @property
    def reply_data_size(self) -> int | None:
        return None


# --------------------------------------------------------------------------- servo commands


def _bitmap(ics_numbers: Iterable[int], flag: bool) -> bytes:
    m = 0
    for k in ics_numbers:
        m |= 1 << k
    if flag:
        m |= 1 << 39
    return m.to_bytes(5, "little")


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
        _check_ics(ics)
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
        _check_int("ICS number", ics, 0, 0x7F)
        _check_int("speed", speed, 0, 255)
        _check_position(position)

    def encode(self) -> bytes:
        return pack_single_servo(self.ics, self.speed, self.position, bool(self.set_update_flag))

    @property
    def reply_data_size(self) -> int | None:
        return None


def _check_speed(v: int) -> None:
    _check_int("speed", v, 0, 255)


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
            pairs = _normalise_pairs("RunConstFrameServo", positions, _check_position)
        object.__setattr__(self, "speed", speed)
        object.__setattr__(self, "positions", pairs)
        object.__setattr__(self, "set_update_flag", bool(set_update_flag))

    def encode(self) -> bytes:
        pairs = self.positions
        if not pairs:
            return pack_const_frame(self.speed, (), (), self.set_update_flag)
        ics, positions = zip(*pairs, strict=True)
        return pack_const_frame(self.speed, ics, positions, self.set_update_flag)

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
            _check_ics(ics)
            if ics in seen:
                raise ValueError(f"RunSeriesServo: ICS {ics} given twice")
            seen.add(ics)
            _check_speed(speed)
            _check_position(pos)
            out.append((ics, speed, pos))
        out.sort()
        object.__setattr__(self, "moves", tuple(out))
        object.__setattr__(self, "set_update_flag", bool(set_update_flag))

    def encode(self) -> bytes:
        body = bytearray(_bitmap((k for k, _, _ in self.moves), not self.set_update_flag))
        for _, s, p in self.moves:
            body += bytes((s, p & 0xFF, p >> 8))
        return build_frame(self.cmd, body)

    @property
    def reply_data_size(self) -> int | None:
        return None


def _check_stretch_value(v: int) -> None:
    # Any byte: the reference documents 1-127, but real HeartToHeart4 motions hold 0 and the
    # board runs them. The documented range lives in rcb4hv.protocol.ranges (robot level, lint).
    _check_int("value", v, 0, 0xFF)


@dataclass(frozen=True, slots=True)
class _SpeedStretch:
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

    @property
    def reply_data_size(self) -> int | None:
        return None


@dataclass(frozen=True, slots=True, init=False)
class SetStretch(_SpeedStretch):
    """12h sub 01: servo stretch (holding gain) per servo; documented 1-127, any byte here."""

    sub: ClassVar[int] = 0x01


@dataclass(frozen=True, slots=True, init=False)
class SetSpeed(_SpeedStretch):
    """12h sub 02: servo speed parameter per servo; documented 1-127, any byte here."""

    sub: ClassVar[int] = 0x02


# --------------------------------------------------------------------------- system


@dataclass(frozen=True, slots=True)
class GetVersionInfo:
    """FDh: ask for the 32-byte version string (``03 FD 00``)."""

    cmd: ClassVar[int] = Op.VERSION

    def encode(self) -> bytes:
        return b"\x03\xfd\x00"

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

    @property
    def reply_data_size(self) -> int | None:
        return None


Command = (
    Move
    | And
    | Or
    | Xor
    | Not
    | Shift
    | Add
    | Sub
    | Mul
    | Div
    | Mod
    | Jump
    | Call
    | Return
    | CommunicateDevice
    | RunSingleServo
    | RunConstFrameServo
    | RunSeriesServo
    | SetStretch
    | SetSpeed
    | GetVersionInfo
    | AcknowledgeCheck
)


def encode_command(cmd: Command) -> bytes:
    """The frame of ``cmd``."""
    return cmd.encode()


# --------------------------------------------------------------------------- decoding


def _decode_dst(kind: int, b: bytes) -> Destination:
    if kind == KIND_RAM:
        if b[2]:
            raise ProtocolError("RAM destination: third address byte must be 00")
        return Ram(b[0] | b[1] << 8)
    if kind == KIND_ICS:
        if b[2]:
            raise ProtocolError("ICS destination: third address byte must be 00")
        return Ics(b[0], b[1])
    if kind == KIND_COM:
        if b != b"\x00\x00\x00":
            raise ProtocolError("COM destination: address bytes must be 00 00 00")
        return Com()
    return Rom(b[0] | b[1] << 8 | b[2] << 16)


def _decode_data_command(frame: bytes) -> Command:
    n = len(frame)
    if n < 8:
        raise ProtocolError(f"data command frame of {n} bytes is too short")
    cmd, t = frame[1], frame[2]
    if t & 0x4C:
        raise ProtocolError(f"type byte {t:02X}: bits 6, 3 and 2 must be 0")
    nw = bool(t & 0x80)
    dst = _decode_dst((t >> 4) & 3, frame[3:6])
    src_kind = t & 3
    if cmd in (Op.NOT, Op.SHIFT):
        if n != 10 or src_kind != KIND_RAM or frame[6] != 0 or (cmd == Op.NOT and frame[7]):
            raise ProtocolError(f"malformed {'NOT' if cmd == Op.NOT else 'SHIFT'} frame")
        if cmd == Op.NOT:
            return Not(dst, frame[8], nw)
        return Shift(dst, frame[8], nw, frame[7])
    src: Source
    size: int | None
    if src_kind == KIND_COM:
        src, size = Data(frame[6:-1]), None
    elif src_kind == KIND_ROM:
        if n != 11:
            raise ProtocolError("ROM source needs an 11-byte frame")
        src, size = Rom(frame[6] | frame[7] << 8 | frame[8] << 16), frame[9]
    else:
        if n != 10:
            raise ProtocolError("RAM/ICS source needs a 10-byte frame")
        src = Ram(frame[6] | frame[7] << 8) if src_kind == KIND_RAM else Ics(frame[6], frame[7])
        size = frame[8]
    if cmd == Op.MOVE:
        if nw:
            raise ProtocolError("MOVE does not take the no-write-back flag")
        return Move(dst, src, size)
    return cast(Command, _BINARY[cmd](dst, src, size, nw))


_BINARY: Final[dict[int, type[_BinaryOp]]] = {
    Op.AND: And,
    Op.OR: Or,
    Op.XOR: Xor,
    Op.ADD: Add,
    Op.SUB: Sub,
    Op.MUL: Mul,
    Op.DIV: Div,
    Op.MOD: Mod,
}


def _decode_branch(frame: bytes) -> Command:
    if len(frame) != 7:
        raise ProtocolError("JUMP/CALL frames are 7 bytes")
    if frame[5] & 0xF0:
        raise ProtocolError(f"condition byte {frame[5]:02X}: bits 7-4 must be 0")
    addr = frame[2] | frame[3] << 8 | frame[4] << 16
    cond = Condition.from_byte(frame[5])
    return Jump(addr, cond) if frame[1] == Op.JUMP else Call(addr, cond)


def _decode_return(frame: bytes) -> Command:
    if len(frame) != 3:
        raise ProtocolError("RETURN is 3 bytes")
    return Return()


def _decode_ics_comm(frame: bytes) -> Command:
    if len(frame) != 9:
        raise ProtocolError("ICS communication frames are 9 bytes")
    return CommunicateDevice(frame[2], frame[3], frame[4] | frame[5] << 8, frame[6] | frame[7] << 8)


def _bitmap_ics(m: bytes, allow_flag: bool) -> tuple[list[int], bool]:
    value = int.from_bytes(m, "little")
    if value & (0x7 << 36):
        raise ProtocolError("servo bitmap: M4 bits 4-6 must be 0")
    flag = bool(value & (1 << 39))
    if flag and not allow_flag:
        raise ProtocolError("servo bitmap: M4 bit 7 must be 0 for this command")
    return [k for k in range(ICS_COUNT) if value >> k & 1], flag


def _decode_single(frame: bytes) -> Command:
    if len(frame) != 7:
        raise ProtocolError("RunSingleServo frames are 7 bytes")
    b = frame[2]
    return RunSingleServo(b & 0x7F, frame[3], frame[4] | frame[5] << 8, not b & 0x80)


def _decode_const(frame: bytes) -> Command:
    ics, flag = _bitmap_ics(frame[2:7], True)
    if len(frame) != 9 + 2 * len(ics):
        raise ProtocolError(f"RunConstFrameServo for {len(ics)} servos: wrong frame length")
    pos = [frame[8 + 2 * i] | frame[9 + 2 * i] << 8 for i in range(len(ics))]
    return RunConstFrameServo(frame[7], zip(ics, pos, strict=True), not flag)


def _decode_series(frame: bytes) -> Command:
    ics, flag = _bitmap_ics(frame[2:7] if len(frame) >= 8 else b"", True)
    if len(frame) != 8 + 3 * len(ics):
        raise ProtocolError(f"RunSeriesServo for {len(ics)} servos: wrong frame length")
    moves = [
        (k, frame[7 + 3 * i], frame[8 + 3 * i] | frame[9 + 3 * i] << 8) for i, k in enumerate(ics)
    ]
    return RunSeriesServo(moves, not flag)


def _decode_speed_stretch(frame: bytes) -> Command:
    if len(frame) < 9:
        raise ProtocolError("SetSpeed/SetStretch frames are at least 9 bytes")
    ics, _ = _bitmap_ics(frame[2:7], False)
    if len(frame) != 9 + len(ics):
        raise ProtocolError(f"SetSpeed/SetStretch for {len(ics)} servos: wrong frame length")
    sub = frame[7]
    values = zip(ics, frame[8:-1], strict=True)
    if sub == SetStretch.sub:
        return SetStretch(values)
    if sub == SetSpeed.sub:
        return SetSpeed(values)
    raise ProtocolError(f"12h sub-command {sub:02X} is neither 01 (stretch) nor 02 (speed)")


def _decode_version(frame: bytes) -> Command:
    if frame != b"\x03\xfd\x00":
        raise ProtocolError("version request is 03 FD 00")
    return GetVersionInfo()


def _decode_ack(frame: bytes) -> Command:
    if frame == b"\x03\xfe\x01":
        return AcknowledgeCheck()
    if frame == b"\x04\xfe\x06\x08":
        return AcknowledgeCheck(long_form=True)
    raise ProtocolError("acknowledge check is 03 FE 01 or 04 FE 06 08")


_DECODERS: Final[dict[int, Callable[[bytes], Command]]] = {
    **{c: _decode_data_command for c in range(0x0B)},
    Op.JUMP: _decode_branch,
    Op.CALL: _decode_branch,
    Op.RETURN: _decode_return,
    Op.ICS_COMM: _decode_ics_comm,
    Op.SINGLE_SERVO: _decode_single,
    Op.CONST_FRAME_SERVO: _decode_const,
    Op.SERIES_SERVO: _decode_series,
    Op.SPEED_STRETCH: _decode_speed_stretch,
    Op.VERSION: _decode_version,
    Op.ACK_CHECK: _decode_ack,
}


def decode_command(frame: bytes | bytearray | memoryview) -> Command:
    """Decode one whole command frame; raise ProtocolError if it is not a valid command."""
    frame = bytes(frame)
    check_frame(frame)
    decoder = _DECODERS.get(frame[1])
    if decoder is None:
        raise ProtocolError(f"unknown command byte {frame[1]:02X}")
    try:
        return decoder(frame)
    except ValueError as exc:
        raise ProtocolError(f"invalid {frame[1]:02X}h command: {exc}") from exc
