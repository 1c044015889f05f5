"""Typed description of a HeartToHeart4 2.2 ROM image, its builder and its parser.

:class:`ImageDescription` says *what* a board holds (system register, servo configurations per
ICS number, AD references, KRI-3 settings, vector packages / button bindings, startup motion,
priority motions, motions as frame lists at slot n); :func:`build_image` lays it out as the
256 KB image HeartToHeart4 2.2 would write (spec 11.2, with the choices documented in
:mod:`rcb4hv.rom.layout`), and :func:`parse_image` reads an image back into a description.
``parse_image(build_image(d)) == d`` for every valid description.

Every instruction is built with the protocol core (:func:`rcb4hv.protocol.encode_command`).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Final, Literal

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol import (
    ALWAYS,
    Button,
    Call,
    Command,
    Condition,
    Data,
    Jump,
    Move,
    Ram,
    Return,
    Rom,
    RunConstFrameServo,
    Sub,
    check_frame,
    decode_command,
    encode_command,
    frame_at,
)
from rcb4hv.protocol.commands import POSITION_FREE
from rcb4hv.protocol.memory import SYS
from rcb4hv.rom import layout as L

__all__ = [
    "Compare",
    "ImageDescription",
    "Kri3Config",
    "Motion",
    "PriorityMotion",
    "ServoConfig",
    "VectorPackage",
    "build_image",
    "parse_image",
]

Compare = Literal["eq", "ne", "lt", "le", "gt", "ge"]

HOLD: Final = 0x7FFF



def _check(name: str, value: int, lo: int, hi: int) -> None:
    if not isinstance(value, int) or isinstance(value, bool) or not lo <= value <= hi:
        raise ValueError(f"{name} {value!r} out of range {lo}..{hi}")


@dataclass(frozen=True, slots=True)
class ServoConfig:
    """One servo: its ICS number, the ID stored in its block, trim (base), home and mixing."""

    ics: int
    servo_id: int | None = None
    trim: int = 0
    home: int = 7500
    mix1_source: int = 0xFFFF
    mix1_method: int = 0
    mix2_source: int = 0xFFFF
    mix2_method: int = 0

    def __post_init__(self) -> None:
        _check("ICS number", self.ics, 0, 34)
        if self.servo_id is None:
            object.__setattr__(self, "servo_id", self.ics // 2)
        _check("servo ID", self.servo_id, 0, 0xFF)  # type: ignore[arg-type]
        _check("trim", self.trim, -0x8000, 0x7FFF)
        _check("home", self.home, 0, 0xFFFF)
        for n in ("mix1_source", "mix2_source"):
            _check(n, getattr(self, n), 0, 0xFFFF)
        for n in ("mix1_method", "mix2_method"):
            _check(n, getattr(self, n), 0, 0xFF)

    def block(self) -> bytes:
        """The 20-byte servo block image (output free until the boot sequence homes it)."""
        b = bytearray(20)
        b[0] = 0
        b[1] = self.servo_id or 0
        b[2:4] = (self.trim & 0xFFFF).to_bytes(2, "little")
        b[6:8] = POSITION_FREE.to_bytes(2, "little")
        b[9:11] = POSITION_FREE.to_bytes(2, "little")
        b[14:16] = self.mix1_source.to_bytes(2, "little")
        b[16] = self.mix1_method
        b[17:19] = self.mix2_source.to_bytes(2, "little")
        b[19] = self.mix2_method
        return bytes(b)


def _empty_block(ics: int) -> bytes:
    b = bytearray(20)
    b[1] = ics // 2
    b[6:8] = POSITION_FREE.to_bytes(2, "little")
    b[9:11] = POSITION_FREE.to_bytes(2, "little")
    b[14:16] = b"\xff\xff"
    b[17:19] = b"\xff\xff"
    return bytes(b)


@dataclass(frozen=True, slots=True)
class Kri3Config:
    """The KRI-3 / KRR receiver slot (ICS 35): its 11-byte block copied to RAM 034Ch."""

    block: bytes = bytes((1, 31)) + bytes(9)

    def __post_init__(self) -> None:
        if not isinstance(self.block, bytes):
            object.__setattr__(self, "block", bytes(self.block))
        if len(self.block) != L.KRI3_BLOCK_SIZE:
            raise ValueError("the KRI-3 block is 11 bytes")


@dataclass(frozen=True, slots=True)
class VectorPackage:
    """One 8-byte vector-jump package (spec 11.3); EOF is set by the builder on the last."""

    destination: int
    source: int
    target: int
    compare_z: bool = True
    z: bool = True
    compare_c: bool = False
    c: bool = False
    literal: bool = True
    word: bool = True
    jump: bool = False

    def __post_init__(self) -> None:
        _check("destination", self.destination, 0, 0xFFFF)
        _check("source", self.source, 0, 0xFFFF)
        _check("target", self.target, 0, 0xFFFFFF)  # 24 bits, as on the wire

    @classmethod
    def button(cls, buttons: int, target: int, *, jump: bool = False) -> VectorPackage:
        """Branch to ``target`` when the button word equals ``buttons`` (e.g. Button.CIRCLE)."""
        _check("buttons", int(buttons), 0, 0xFFFF)
        raw = int.from_bytes(Button(int(buttons) & 0x1F7F).to_ram(), "little")
        return cls(L.RAM_BUTTONS, raw, target, jump=jump)

    def cond_byte(self, last: bool) -> int:
        return (
            int(self.z)
            | int(self.c) << 1
            | int(self.compare_z) << 2
            | int(self.compare_c) << 3
            | int(self.literal) << 4
            | int(self.word) << 5
            | int(self.jump) << 6
            | int(last) << 7
        )

    def to_bytes(self, last: bool) -> bytes:
        t = self.target
        return (
            bytes((self.cond_byte(last),))
            + self.destination.to_bytes(2, "little")
            + self.source.to_bytes(2, "little")
            + bytes((t & 0xFF, (t >> 8) & 0xFF, t >> 16))
        )

    @classmethod
    def from_bytes(cls, data: bytes) -> tuple[VectorPackage, bool]:
        c = data[0]
        pkg = cls(
            destination=data[1] | data[2] << 8,
            source=data[3] | data[4] << 8,
            target=data[5] | data[6] << 8 | data[7] << 16,
            z=bool(c & 1),
            c=bool(c & 2),
            compare_z=bool(c & 4),
            compare_c=bool(c & 8),
            literal=bool(c & 0x10),
            word=bool(c & 0x20),
            jump=bool(c & 0x40),
        )
        return pkg, bool(c & 0x80)


_COND: Final[dict[str, tuple[Condition, int]]] = {
    "eq": (Condition.if_zero(), 0),
    "ne": (Condition.if_not_zero(), 0),
    "ge": (Condition.if_carry(), 0),
    "lt": (Condition.if_not_carry(), 0),
}


@dataclass(frozen=True, slots=True)
class PriorityMotion:
    """A main-loop check: CALL ``target`` when RAM ``source`` compares to ``value``.

    ``le`` / ``gt`` are normalised to ``lt`` / ``ge`` with ``value + 1`` (the board only
    has Z and C), so a description round-trips through an image unchanged.
    """

    source: int
    compare: Compare
    value: int
    target: int
    size: int = 2

    def __post_init__(self) -> None:
        _check("source", self.source, 0, 0x048F)
        _check("size", self.size, 1, 2)
        _check("value", self.value, 0, (1 << (8 * self.size)) - 1)
        _check("target", self.target, 0, 0xFFFFFF)  # 24 bits, as on the wire
        if self.compare in ("le", "gt"):
            if self.value >= (1 << (8 * self.size)) - 1:
                raise ValueError(f"{self.compare} {self.value} cannot be expressed")
            object.__setattr__(self, "compare", "lt" if self.compare == "le" else "ge")
            object.__setattr__(self, "value", self.value + 1)
        elif self.compare not in _COND:
            raise ValueError(f"unknown comparison {self.compare!r}")


@dataclass(frozen=True, slots=True)
class Motion:
    """A motion: command frames laid out from the start of slot ``slot`` (1-120).

    Jump targets inside a motion are absolute ROM addresses (use :meth:`address`). A RETURN is
    appended if the last frame is not one.
    """

    slot: int
    frames: tuple[bytes, ...]

    def __init__(self, slot: int, frames: Iterable[Command | bytes]) -> None:
        _check("motion slot", slot, 1, L.MOTION_COUNT)
        out: list[bytes] = []
        for f in frames:
            fb = bytes(f) if isinstance(f, (bytes, bytearray)) else encode_command(f)
            check_frame(fb)
            out.append(fb)
        if not out or out[-1] != b"\x03\x0d\x10":
            out.append(encode_command(Return()))
        if sum(map(len, out)) > L.MOTION_SIZE:
            raise ValueError(f"motion {slot} does not fit its {L.MOTION_SIZE}-byte slot")
        object.__setattr__(self, "slot", slot)
        object.__setattr__(self, "frames", tuple(out))

    @property
    def address(self) -> int:
        return L.motion_address(self.slot)

    def commands(self) -> list[Command]:
        return [decode_command(f) for f in self.frames]


@dataclass(frozen=True, slots=True)
class ImageDescription:
    """Everything a HeartToHeart4 2.2 image holds, typed."""

    system_register: int = 0x409B
    pio_direction: int = 0x03FF
    pio_data: int = 0
    ad_references: tuple[int, ...] = (0,) * 11
    servos: tuple[ServoConfig, ...] = ()
    kri3: Kri3Config | None = field(default_factory=Kri3Config)
    vector_packages: tuple[VectorPackage, ...] = ()
    title: str = ""
    startup_motion: int | None = None
    startup_wait: int = L.TIMER_WAIT_COUNT
    home_speed: int = 10
    priority_motions: tuple[PriorityMotion | None, ...] = ()
    motions: tuple[Motion, ...] = ()

    def __post_init__(self) -> None:
        _check("system register", self.system_register, 0, 0xFFFF)
        _check("PIO direction", self.pio_direction, 0, 0xFFFF)
        _check("PIO data", self.pio_data, 0, 0xFFFF)
        for name in ("ad_references", "servos", "vector_packages", "priority_motions"):
            object.__setattr__(self, name, tuple(getattr(self, name)))
        if len(self.ad_references) != 11:
            raise ValueError("there are 11 AD reference values")
        for v in self.ad_references:
            _check("AD reference", v, 0, 0xFFFF)
        seen = [s.ics for s in self.servos]
        if len(set(seen)) != len(seen):
            raise ValueError("an ICS number is configured twice")
        object.__setattr__(self, "servos", tuple(sorted(self.servos, key=lambda s: s.ics)))
        if len(self.vector_packages) > L.VECTOR_PACKAGE_COUNT:
            raise ValueError("at most 32 vector packages")
        if len(self.priority_motions) > L.PRIORITY_COUNT:
            raise ValueError("at most 13 priority motions")
        pm = list(self.priority_motions)
        while pm and pm[-1] is None:
            pm.pop()
        object.__setattr__(self, "priority_motions", tuple(pm))
        if len(self.title.encode("cp932")) > L.TITLE_SIZE:
            raise ValueError("the title is at most 32 bytes (cp932)")
        if "\x00" in self.title:
            raise ValueError("the title cannot contain NUL")
        if self.startup_motion is not None:
            _check("startup motion address", self.startup_motion, 0, 0xFFFFFF)
        _check("startup wait", self.startup_wait, 0, 0x7FFF)
        _check("home speed", self.home_speed, 0, 255)
        motions = sorted(self.motions, key=lambda m: m.slot)
        if len({m.slot for m in motions}) != len(motions):
            raise ValueError("a motion slot is used twice")
        object.__setattr__(self, "motions", tuple(motions))

    def servo(self, ics: int) -> ServoConfig | None:
        for s in self.servos:
            if s.ics == ics:
                return s
        return None

    @property
    def ics_numbers(self) -> tuple[int, ...]:
        return tuple(s.ics for s in self.servos)


# ----------------------------------------------------------------------------- building


def _lit(address: int, value: int, size: int = 2) -> bytes:
    return encode_command(Move(Ram(address), Data(value.to_bytes(size, "little"))))


def _copy(rom: int, ram: int, size: int) -> bytes:
    return encode_command(Move(Ram(ram), Rom(rom), size))


def _servo_frame(speed: int, positions: dict[int, int]) -> bytes:
    return encode_command(RunConstFrameServo(speed, positions))


def _priority_bytes(pm: PriorityMotion | None, slot_addr: int, sysreg: int) -> bytes:
    if pm is None:
        jump = encode_command(Jump(slot_addr + L.PRIORITY_SIZE, ALWAYS))
        return jump + bytes([L.ERASED]) * (L.PRIORITY_SIZE - len(jump))
    cond, _ = _COND[pm.compare]
    out = (
        encode_command(Sub(Ram(pm.source), Data(pm.value.to_bytes(pm.size, "little")), None, True))
        + encode_command(Call(pm.target, cond))
        + _lit(0, sysreg)
    )
    assert len(out) == L.PRIORITY_SIZE + (pm.size - 2)
    return out.ljust(L.PRIORITY_SIZE, bytes([L.ERASED]))


def build_image(desc: ImageDescription) -> bytes:
    """The 256 KB ROM image of ``desc`` (erased bytes are FF)."""
    rom = bytearray([L.ERASED]) * L.ROM_SIZE

    def put(addr: int, data: bytes) -> None:
        rom[addr : addr + len(data)] = data

    sysreg = desc.system_register
    put(L.CONFIG_WRITE, _lit(0x0000, sysreg & ~SYS.ICS_OUTPUT))
    put(L.PIO_DIRECTION_WRITE, _lit(0x0038, desc.pio_direction))
    put(L.PIO_DATA_WRITE, _lit(0x003A, desc.pio_data))
    put(L.AD_REFERENCE_COPY, _copy(L.AD_REFERENCE_IMAGE, 0x000C, 22))
    for n in range(L.SERVO_BLOCK_COPY_COUNT):
        put(
            L.SERVO_BLOCK_COPIES + 11 * n,
            _copy(L.SERVO_BLOCK_IMAGES + 20 * n, L.RAM_SERVO_BLOCKS + 20 * n, 20),
        )
    put(L.ALLOC_COPY, _copy(L.ALLOC_IMAGE, L.RAM_ALLOC, 72))
    put(L.KRI3_ALLOC_COPY, _copy(L.KRI3_ALLOC_IMAGE, L.RAM_KRI3_ALLOC, 2))
    put(L.KRI3_BLOCK_COPY, _copy(L.KRI3_BLOCK_IMAGE, L.RAM_KRI3_BLOCK, L.KRI3_BLOCK_SIZE))
    for i in range(L.VECTOR_PACKAGE_COUNT):
        put(
            L.VECTOR_PACKAGE_COPIES + 11 * i,
            _copy(L.VECTOR_PACKAGE_IMAGES + 8 * i, L.RAM_VECTOR_PACKAGES + 8 * i, 8),
        )
    put(L.VECTOR_ADDRESS_COPY, _copy(L.VECTOR_ADDRESS_IMAGE, L.RAM_VECTOR_ADDRESS, 2))
    put(L.SYSTEM_REGISTER_COPY, _copy(L.SYSTEM_REGISTER_IMAGE, 0x0000, 2))
    all_ics = range(L.SERVO_BLOCK_COPY_COUNT)
    put(L.ALL_FREE, _servo_frame(1, dict.fromkeys(all_ics, POSITION_FREE)))
    t0 = 0x003C
    wait = (
        _lit(t0, desc.startup_wait)
        + encode_command(Sub(Ram(t0), Data(b"\x00\x80"), None, True))
        + encode_command(Jump(L.TIMER_WAIT + 9, Condition.if_not_zero()))
    )
    put(L.TIMER_WAIT, wait)
    put(L.ALL_HOLD, _servo_frame(1, dict.fromkeys(all_ics, HOLD)))
    homes = {n: (s.home if (s := desc.servo(n)) else 7500) for n in all_ics}
    put(L.ALL_HOME, _servo_frame(desc.home_speed, homes))
    startup = L.STARTUP_STUB if desc.startup_motion is None else desc.startup_motion
    put(L.STARTUP_CALL, encode_command(Call(startup, ALWAYS)))
    put(L.MAIN_LOOP, _lit(0x0000, sysreg))
    put(L.PIO_SWITCHES, encode_command(Jump(L.PRIORITY_CHECKS, ALWAYS)))
    for i in range(L.PRIORITY_COUNT):
        pm = desc.priority_motions[i] if i < len(desc.priority_motions) else None
        slot = L.PRIORITY_CHECKS + L.PRIORITY_SIZE * i
        code = _priority_bytes(pm, slot, sysreg)
        put(slot, code)
        put(L.PRIORITY_IMAGES + L.PRIORITY_SIZE * i, code)
    put(L.MAIN_LOOP_JUMP, encode_command(Jump(L.MAIN_LOOP, ALWAYS)))

    put(L.SYSTEM_REGISTER_IMAGE, sysreg.to_bytes(2, "little"))
    alloc = bytearray(b"\xff" * 72)
    for s in desc.servos:
        alloc[2 * s.ics : 2 * s.ics + 2] = (L.RAM_SERVO_BLOCKS + 20 * s.ics).to_bytes(2, "little")
    kri_alloc = L.RAM_KRI3_BLOCK if desc.kri3 is not None else 0xFFFF
    alloc[70:72] = kri_alloc.to_bytes(2, "little")
    put(L.ALLOC_IMAGE, bytes(alloc))
    for n in range(L.SERVO_BLOCK_IMAGE_COUNT):
        s = desc.servo(n)
        put(L.SERVO_BLOCK_IMAGES + 20 * n, s.block() if s else _empty_block(n))
    put(L.AD_REFERENCE_IMAGE, b"".join(v.to_bytes(2, "little") for v in desc.ad_references))
    put(L.KRI3_ALLOC_IMAGE, kri_alloc.to_bytes(2, "little"))
    put(L.KRI3_BLOCK_IMAGE, desc.kri3.block if desc.kri3 is not None else bytes(11))
    vaddr = L.RAM_VECTOR_PACKAGES if desc.vector_packages else 0xFFFF
    put(L.VECTOR_ADDRESS_IMAGE, vaddr.to_bytes(2, "little"))
    pk = desc.vector_packages
    for i, p in enumerate(pk):
        put(L.VECTOR_PACKAGE_IMAGES + 8 * i, p.to_bytes(last=i == len(pk) - 1))
    put(L.TITLE, desc.title.encode("cp932").ljust(L.TITLE_SIZE, b"\x00"))
    for m in desc.motions:
        put(m.address, b"".join(m.frames))
    put(L.STARTUP_STUB, encode_command(Return()))
    return bytes(rom)


# ----------------------------------------------------------------------------- parsing


def _literal_of(rom: bytes, addr: int) -> int:
    cmd = decode_command(frame_at(rom, addr))
    if not isinstance(cmd, Move) or not isinstance(cmd.src, Data):
        raise ProtocolError(f"expected a literal MOVE at {addr:05X}h")
    return int.from_bytes(cmd.src.data, "little")


def _w(rom: bytes, addr: int) -> int:
    return rom[addr] | rom[addr + 1] << 8


def _s16(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v


def parse_image(rom: bytes | bytearray) -> ImageDescription:
    """Read a HeartToHeart4 2.2 image back into a description; ProtocolError if it is not one."""
    rom = bytes(rom)
    if len(rom) != L.ROM_SIZE:
        raise ValueError(f"a ROM image is {L.ROM_SIZE} bytes, not {len(rom)}")
    sysreg = _w(rom, L.SYSTEM_REGISTER_IMAGE)
    home_cmd = decode_command(frame_at(rom, L.ALL_HOME))
    if not isinstance(home_cmd, RunConstFrameServo):
        raise ProtocolError("no all-servos-home frame at 003F5h")
    homes = dict(home_cmd.positions)
    servos: list[ServoConfig] = []
    for n in range(35):
        a = _w(rom, L.ALLOC_IMAGE + 2 * n)
        if a == 0xFFFF:
            continue
        b = rom[L.SERVO_BLOCK_IMAGES + 20 * n : L.SERVO_BLOCK_IMAGES + 20 * n + 20]
        servos.append(
            ServoConfig(
                ics=n,
                servo_id=b[1],
                trim=_s16(b[2] | b[3] << 8),
                home=homes.get(n, 7500),
                mix1_source=b[14] | b[15] << 8,
                mix1_method=b[16],
                mix2_source=b[17] | b[18] << 8,
                mix2_method=b[19],
            )
        )
    kri3 = None
    if _w(rom, L.ALLOC_IMAGE + 70) != 0xFFFF:
        kri3 = Kri3Config(rom[L.KRI3_BLOCK_IMAGE : L.KRI3_BLOCK_IMAGE + L.KRI3_BLOCK_SIZE])
    packages: list[VectorPackage] = []
    if _w(rom, L.VECTOR_ADDRESS_IMAGE) != 0xFFFF:
        for i in range(L.VECTOR_PACKAGE_COUNT):
            a = L.VECTOR_PACKAGE_IMAGES + 8 * i
            pkg, last = VectorPackage.from_bytes(rom[a : a + 8])
            packages.append(pkg)
            if last:
                break
    title = rom[L.TITLE : L.TITLE + L.TITLE_SIZE].split(b"\x00", 1)[0].decode("cp932")
    start = decode_command(frame_at(rom, L.STARTUP_CALL))
    if not isinstance(start, Call):
        raise ProtocolError("no startup CALL at 00444h")
    startup = None if start.address == L.STARTUP_STUB else start.address
    priority: list[PriorityMotion | None] = []
    for i in range(L.PRIORITY_COUNT):
        slot = L.PRIORITY_CHECKS + L.PRIORITY_SIZE * i
        first = decode_command(frame_at(rom, slot))
        if isinstance(first, Jump):
            priority.append(None)
            continue
        call = decode_command(frame_at(rom, slot + rom[slot]))
        if not isinstance(first, Sub) or not isinstance(call, Call):
            raise ProtocolError(f"unrecognised priority check at {slot:05X}h")
        if not isinstance(first.dst, Ram) or not isinstance(first.src, Data):
            raise ProtocolError(f"unrecognised priority comparison at {slot:05X}h")
        compare = next(k for k, (c, _) in _COND.items() if c == call.condition)
        priority.append(
            PriorityMotion(
                first.dst.address,
                compare,  # type: ignore[arg-type]
                int.from_bytes(first.src.data, "little"),
                call.address,
                first.nbytes,
            )
        )
    motions: list[Motion] = []
    for n in range(1, L.MOTION_COUNT + 1):
        base = L.motion_address(n)
        end = base + L.MOTION_SIZE
        frames: list[bytes] = []
        pc = base
        while pc < end and rom[pc] != L.ERASED:
            try:
                f = frame_at(rom, pc)
            except ProtocolError:
                break
            if pc + len(f) > end:
                break
            frames.append(f)
            pc += len(f)
        if frames:
            motions.append(Motion(n, frames))
    ad = tuple(_w(rom, L.AD_REFERENCE_IMAGE + 2 * i) for i in range(11))
    return ImageDescription(
        system_register=sysreg,
        pio_direction=_literal_of(rom, L.PIO_DIRECTION_WRITE),
        pio_data=_literal_of(rom, L.PIO_DATA_WRITE),
        ad_references=ad,
        servos=tuple(servos),
        kri3=kri3,
        vector_packages=tuple(packages),
        title=title,
        startup_motion=startup,
        startup_wait=_literal_of(rom, L.TIMER_WAIT),
        home_speed=home_cmd.speed,
        priority_motions=tuple(priority),
        motions=tuple(motions),
    )
