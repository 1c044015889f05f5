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
    ICS_COUNT,
    POSITION_FREE,
    RAM_SIZE,
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
from rcb4hv.protocol.memory import (
    ADDR,
    NO_BLOCK,
    SERVO,
    SYS,
    VEC,
    ServoBlock,
    VectorPackage,
    pack_alloc,
    read_alloc,
    read_u16,
    u16_bytes,
)
from rcb4hv.rom import layout as L
from rcb4hv.rom.calibration import ad_references
from rcb4hv.rom.slots import scan_slot

__all__ = [
    "Compare",
    "ImageDescription",
    "ImageMotion",
    "ImagePriorityMotion",
    "ImageServo",
    "Kri3Config",
    "VectorPackage",
    "build_image",
    "parse_image",
    "priority_bytes",
    "word_write",
]

Compare = Literal["eq", "ne", "lt", "le", "gt", "ge"]

HOLD: Final = 0x7FFF
KRI3_ICS: Final = 35
"""The allocation-table slot of the KRI-3 receiver block."""
VEC_SIZE: Final = VEC.SIZE


def _vector_ram(i: int) -> int:
    """RAM address of vector package ``i`` in HeartToHeart4's table."""
    return ADDR.VECTOR_PACKAGES + VEC.SIZE * i


def _check(name: str, value: int, lo: int, hi: int) -> None:
    if not isinstance(value, int) or isinstance(value, bool) or not lo <= value <= hi:
        raise ValueError(f"{name} {value!r} out of range {lo}..{hi}")


@dataclass(frozen=True, slots=True)
class ImageServo:
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

    def servo_block(self) -> ServoBlock:
        """The servo block as the image holds it (output free until boot homes it)."""
        return ServoBlock.configured(
            self.servo_id or 0,
            self.trim,
            (self.mix1_source, self.mix1_method),
            (self.mix2_source, self.mix2_method),
        )

    def block(self) -> bytes:
        """The 20-byte servo block image (output free until the boot sequence homes it)."""
        return self.servo_block().to_bytes()

    @classmethod
    def from_block(cls, ics: int, block: ServoBlock, home: int = 7500) -> ImageServo:
        """The configuration of ``ics`` read back from its servo block image."""
        return cls(
            ics=ics,
            servo_id=block.ics_id,
            trim=block.base,
            home=home,
            mix1_source=block.mix1_source,
            mix1_method=block.mix1_method,
            mix2_source=block.mix2_source,
            mix2_method=block.mix2_method,
        )


def _empty_block(ics: int) -> bytes:
    return ServoBlock.configured(ics // 2).to_bytes()


@dataclass(frozen=True, slots=True)
class Kri3Config:
    """The KRI-3 / KRR receiver slot (ICS 35): its 11-byte block copied to RAM 034Ch."""

    block: bytes = bytes((1, 31)) + bytes(9)

    def __post_init__(self) -> None:
        if not isinstance(self.block, bytes):
            object.__setattr__(self, "block", bytes(self.block))
        if len(self.block) != ADDR.KRI3_BLOCK_SIZE:
            raise ValueError("the KRI-3 block is 11 bytes")


_COND: Final[dict[str, tuple[Condition, int]]] = {
    "eq": (Condition.if_zero(), 0),
    "ne": (Condition.if_not_zero(), 0),
    "ge": (Condition.if_carry(), 0),
    "lt": (Condition.if_not_carry(), 0),
}


@dataclass(frozen=True, slots=True)
class ImagePriorityMotion:
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
        _check("source", self.source, 0, RAM_SIZE - 1)
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
class ImageMotion:
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
    servos: tuple[ImageServo, ...] = ()
    kri3: Kri3Config | None = field(default_factory=Kri3Config)
    vector_packages: tuple[VectorPackage, ...] = ()
    title: str = ""
    startup_motion: int | None = None
    startup_wait: int = L.TIMER_WAIT_COUNT
    home_speed: int = 10
    priority_motions: tuple[ImagePriorityMotion | None, ...] = ()
    motions: tuple[ImageMotion, ...] = ()

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

    def servo(self, ics: int) -> ImageServo | None:
        for s in self.servos:
            if s.ics == ics:
                return s
        return None

    @property
    def ics_numbers(self) -> tuple[int, ...]:
        return tuple(s.ics for s in self.servos)


# ----------------------------------------------------------------------------- building


def word_write(address: int, value: int) -> bytes:
    """A literal MOVE of a 16-bit word to RAM ``address``."""
    return encode_command(Move(Ram(address), Data(u16_bytes(value))))


def _copy(rom: int, ram: int, size: int) -> bytes:
    return encode_command(Move(Ram(ram), Rom(rom), size))


def _servo_frame(speed: int, positions: dict[int, int]) -> bytes:
    return encode_command(RunConstFrameServo(speed, positions))


def priority_bytes(pm: ImagePriorityMotion | None, slot_addr: int, sysreg: int) -> bytes:
    if pm is None:
        jump = encode_command(Jump(slot_addr + L.PRIORITY_SIZE, ALWAYS))
        return jump + bytes([L.ERASED]) * (L.PRIORITY_SIZE - len(jump))
    cond, _ = _COND[pm.compare]
    out = (
        encode_command(Sub(Ram(pm.source), Data(pm.value.to_bytes(pm.size, "little")), None, True))
        + encode_command(Call(pm.target, cond))
        + word_write(ADDR.SYSTEM, sysreg)
    )
    assert len(out) == L.PRIORITY_SIZE + (pm.size - 2)
    return out.ljust(L.PRIORITY_SIZE, bytes([L.ERASED]))


def build_image(desc: ImageDescription) -> bytes:
    """The 256 KB ROM image of ``desc`` (erased bytes are FF)."""
    rom = bytearray([L.ERASED]) * L.ROM_SIZE

    def put(addr: int, data: bytes) -> None:
        rom[addr : addr + len(data)] = data

    sysreg = desc.system_register
    put(L.CONFIG_WRITE, word_write(ADDR.SYSTEM, sysreg & ~SYS.ICS_OUTPUT))
    put(L.PIO_DIRECTION_WRITE, word_write(ADDR.PIO_DIRECTION, desc.pio_direction))
    put(L.PIO_DATA_WRITE, word_write(ADDR.PIO_DATA, desc.pio_data))
    put(L.AD_REFERENCE_COPY, _copy(L.AD_REFERENCE_IMAGE, ADDR.AD_REFERENCE, 2 * ADDR.AD_COUNT))
    size = SERVO.SIZE
    for n in range(L.SERVO_BLOCK_COPY_COUNT):
        put(
            L.SERVO_BLOCK_COPIES + 11 * n,
            _copy(L.SERVO_BLOCK_IMAGES + size * n, ADDR.servo_block(n), size),
        )
    put(L.ALLOC_COPY, _copy(L.ALLOC_IMAGE, ADDR.ICS_ALLOC, 2 * ICS_COUNT))
    put(L.KRI3_ALLOC_COPY, _copy(L.KRI3_ALLOC_IMAGE, ADDR.KRI3_ALLOC, 2))
    put(L.KRI3_BLOCK_COPY, _copy(L.KRI3_BLOCK_IMAGE, ADDR.KRI3_BLOCK, ADDR.KRI3_BLOCK_SIZE))
    for i in range(L.VECTOR_PACKAGE_COUNT):
        put(
            L.VECTOR_PACKAGE_COPIES + 11 * i,
            _copy(L.VECTOR_PACKAGE_IMAGES + VEC_SIZE * i, _vector_ram(i), VEC_SIZE),
        )
    put(L.VECTOR_ADDRESS_COPY, _copy(L.VECTOR_ADDRESS_IMAGE, ADDR.VECTOR_TABLE, 2))
    put(L.SYSTEM_REGISTER_COPY, _copy(L.SYSTEM_REGISTER_IMAGE, ADDR.SYSTEM, 2))
    all_ics = range(L.SERVO_BLOCK_COPY_COUNT)
    put(L.ALL_FREE, _servo_frame(1, dict.fromkeys(all_ics, POSITION_FREE)))
    t0 = ADDR.timer(0)
    wait = (
        word_write(t0, desc.startup_wait)
        + encode_command(Sub(Ram(t0), Data(b"\x00\x80"), None, True))
        + encode_command(Jump(L.TIMER_WAIT + 9, Condition.if_not_zero()))
    )
    put(L.TIMER_WAIT, wait)
    put(L.ALL_HOLD, _servo_frame(1, dict.fromkeys(all_ics, HOLD)))
    homes = {n: (s.home if (s := desc.servo(n)) else 7500) for n in all_ics}
    put(L.ALL_HOME, _servo_frame(desc.home_speed, homes))
    startup = L.STARTUP_STUB if desc.startup_motion is None else desc.startup_motion
    put(L.STARTUP_CALL, encode_command(Call(startup, ALWAYS)))
    put(L.MAIN_LOOP, word_write(ADDR.SYSTEM, sysreg))
    put(L.PIO_SWITCHES, encode_command(Jump(L.PRIORITY_CHECKS, ALWAYS)))
    for i in range(L.PRIORITY_COUNT):
        pm = desc.priority_motions[i] if i < len(desc.priority_motions) else None
        slot = L.PRIORITY_CHECKS + L.PRIORITY_SIZE * i
        code = priority_bytes(pm, slot, sysreg)
        put(slot, code)
        put(L.PRIORITY_IMAGES + L.PRIORITY_SIZE * i, code)
    put(L.MAIN_LOOP_JUMP, encode_command(Jump(L.MAIN_LOOP, ALWAYS)))

    put(L.SYSTEM_REGISTER_IMAGE, u16_bytes(sysreg))
    alloc: list[int | None] = [None] * ICS_COUNT
    for s in desc.servos:
        alloc[s.ics] = ADDR.servo_block(s.ics)
    kri_alloc = ADDR.KRI3_BLOCK if desc.kri3 is not None else NO_BLOCK
    alloc[KRI3_ICS] = kri_alloc
    put(L.ALLOC_IMAGE, pack_alloc(alloc))
    for n in range(L.SERVO_BLOCK_IMAGE_COUNT):
        s = desc.servo(n)
        put(L.SERVO_BLOCK_IMAGES + size * n, s.block() if s else _empty_block(n))
    put(L.AD_REFERENCE_IMAGE, b"".join(u16_bytes(v) for v in desc.ad_references))
    put(L.KRI3_ALLOC_IMAGE, u16_bytes(kri_alloc))
    kri3 = desc.kri3.block if desc.kri3 is not None else bytes(ADDR.KRI3_BLOCK_SIZE)
    put(L.KRI3_BLOCK_IMAGE, kri3)
    vaddr = ADDR.VECTOR_PACKAGES if desc.vector_packages else NO_BLOCK
    put(L.VECTOR_ADDRESS_IMAGE, u16_bytes(vaddr))
    pk = desc.vector_packages
    for i, p in enumerate(pk):
        p.pack(rom, L.VECTOR_PACKAGE_IMAGES + VEC_SIZE * i, last=i == len(pk) - 1)
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


def parse_image(rom: bytes | bytearray) -> ImageDescription:
    """Read a HeartToHeart4 2.2 image back into a description; ProtocolError if it is not one."""
    rom = bytes(rom)
    if len(rom) != L.ROM_SIZE:
        raise ValueError(f"a ROM image is {L.ROM_SIZE} bytes, not {len(rom)}")
    sysreg = read_u16(rom, L.SYSTEM_REGISTER_IMAGE)
    home_cmd = decode_command(frame_at(rom, L.ALL_HOME))
    if not isinstance(home_cmd, RunConstFrameServo):
        raise ProtocolError("no all-servos-home frame at 003F5h")
    homes = dict(home_cmd.positions)
    servos: list[ImageServo] = []
    for n in range(L.SERVO_BLOCK_COPY_COUNT):
        if read_alloc(rom, n, at=L.ALLOC_IMAGE) == NO_BLOCK:
            continue
        block = ServoBlock.unpack(rom, L.SERVO_BLOCK_IMAGES + SERVO.SIZE * n)
        servos.append(ImageServo.from_block(n, block, homes.get(n, 7500)))
    kri3 = None
    if read_alloc(rom, KRI3_ICS, at=L.ALLOC_IMAGE) != NO_BLOCK:
        kri3 = Kri3Config(rom[L.KRI3_BLOCK_IMAGE : L.KRI3_BLOCK_IMAGE + ADDR.KRI3_BLOCK_SIZE])
    packages: list[VectorPackage] = []
    if read_u16(rom, L.VECTOR_ADDRESS_IMAGE) != NO_BLOCK:
        for i in range(L.VECTOR_PACKAGE_COUNT):
            pkg, last = VectorPackage.unpack(rom, L.VECTOR_PACKAGE_IMAGES + VEC_SIZE * i)
            packages.append(pkg)
            if last:
                break
    title = rom[L.TITLE : L.TITLE + L.TITLE_SIZE].split(b"\x00", 1)[0].decode("cp932")
    start = decode_command(frame_at(rom, L.STARTUP_CALL))
    if not isinstance(start, Call):
        raise ProtocolError("no startup CALL at 00444h")
    startup = None if start.address == L.STARTUP_STUB else start.address
    priority: list[ImagePriorityMotion | None] = []
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
            ImagePriorityMotion(
                first.dst.address,
                compare,  # type: ignore[arg-type]
                int.from_bytes(first.src.data, "little"),
                call.address,
                first.nbytes,
            )
        )
    motions: list[ImageMotion] = []
    for n in range(1, L.MOTION_COUNT + 1):
        frames, _ = scan_slot(rom, L.motion_address(n), L.MOTION_SIZE)
        if frames:
            motions.append(ImageMotion(n, frames))
    ad = ad_references(rom)
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
