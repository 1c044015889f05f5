"""Servo blocks, interpolation (spec 9), mixing and the virtual servos that report back.

A servo is driven through its 20-byte block at ``alloc[ics]`` (type 0 only). Each output
period moves every interpolating servo one step (:meth:`Servos.period`); while ICS_F is set
the virtual servos follow the value sent and report ``position - base`` into the block.

Speed work kept here: a block-address cache and the set of moving servos, valid while the
layout is *safe* (see :meth:`Servos.rescan`) and no write touched the table or a block. With
``accelerate=False`` the unit rescans RAM every period (the plain model).
"""

from __future__ import annotations

from collections.abc import Callable, Collection
from dataclasses import dataclass
from itertools import pairwise

from rcb4hv.emulator.config import DEFAULT_SERVOS, EmulatorConfig
from rcb4hv.emulator.memmap import (
    ALLOC,
    ALLOC_END,
    B_BASE,
    B_END,
    B_END_HI,
    B_MEASURED,
    B_MEASURED_HI,
    B_MIX1,
    B_MIX2,
    B_OUTPUT,
    B_OUTPUT_HI,
    B_REMAINING,
    B_SPEED,
    B_TYPE,
    B_WIDTH,
    B_WIDTH_HI,
    BLOCK_SIZE,
    FREE,
    HOLD,
    NO_BLOCK,
    RAM_SIZE,
    S16,
    SERVO,
    U16,
    UPDATE_FLAGS,
    UPDATE_FLAGS_END,
    mix_rate,
    mix_source,
)
from rcb4hv.errors import ArgumentError, ArgumentTypeError, EmulatedCommandError, EmulatedReset
from rcb4hv.protocol import ICS_COUNT, RunConstFrameServo, RunSeriesServo, RunSingleServo
from rcb4hv.protocol.servomode import ServoMode, output_mode
from rcb4hv.values import as_index, plain

__all__ = ["ServoState", "Servos", "check_reading", "ramp"]

ServoCommand = RunSingleServo | RunConstFrameServo | RunSeriesServo
_u16 = U16.unpack_from
_s16 = S16.unpack_from


@dataclass(frozen=True, slots=True)
class ServoState:
    """What one ICS channel is doing at the last output period."""

    ics: int
    output: int
    sent: int
    position: int
    torque: bool
    moving: bool


def ramp(end: int, width: int, remaining: int, speed: int) -> int:
    """Output with ``remaining`` of ``speed`` steps left (spec 9): end -/+ |width|*rem/speed,
    ``width`` given as its raw 16-bit two's-complement word."""
    if width & 0x8000:
        return (end + (0x10000 - width) * remaining // speed) & 0xFFFF
    return (end - width * remaining // speed) & 0xFFFF


def update_flags(ram: bytearray) -> int:
    return int.from_bytes(ram[UPDATE_FLAGS:UPDATE_FLAGS_END], "little")


def set_update_flags(ram: bytearray, flags: int) -> None:
    ram[UPDATE_FLAGS:UPDATE_FLAGS_END] = flags.to_bytes(5, "little")


def servo_slots(config: EmulatorConfig, rom: bytes | bytearray) -> tuple[int, ...]:
    """The ICS numbers with a virtual servo: ``config.virtual_servos``, else the servos the ROM
    image's allocation table configures (the robot its project was made for; the board reads
    it at power-on), else the default humanoid's."""
    if config.virtual_servos is not None:
        return config.virtual_servos
    from rcb4hv.rom.calibration import image_servos

    return image_servos(rom) or DEFAULT_SERVOS


def check_reading(
    ics: object, position: object, virtual: Collection[int] | None = None
) -> tuple[int, int]:
    """``(ics, position)`` as ints: the one rule for a servo position a host hook sets
    (:meth:`Board.measure`, :meth:`Board.set_servo_position`). The ICS number is 0..35 (one
    of the ``virtual`` servos, when given) and the position a value the 16-bit register holds
    (0..65535); :class:`~rcb4hv.errors.ArgumentTypeError` (a TypeError) for one that is not
    an int, :class:`~rcb4hv.errors.ArgumentError` (a ValueError) for one out of range."""
    k = as_index(ics)
    if k is None:
        raise ArgumentTypeError(f"ICS number must be an int, not {plain(ics)}")
    if not 0 <= k < ICS_COUNT:
        raise ArgumentError(f"ICS number {k} outside 0..{ICS_COUNT - 1}")
    if virtual is not None and k not in virtual:
        raise ArgumentError(f"ICS {k} has no virtual servo (those with one: {sorted(virtual)})")
    p = as_index(position)
    if p is None:
        raise ArgumentTypeError(f"ICS {k}: position must be an int, not {plain(position)}")
    if not 0 <= p <= 0xFFFF:
        raise ArgumentError(f"ICS {k}: position {p} is not 16 bits (0..65535)")
    return k, p


class Servos:
    """The servo unit over the board's RAM."""

    def __init__(self, ram: bytearray, config: EmulatorConfig, accelerate: bool = True) -> None:
        self.ram = ram
        self.config = config
        self.accelerate = accelerate
        self.stretch: dict[int, int] = {}
        self.speed_parameter: dict[int, int] = {}
        self.periods = 0
        # a servo backend (physics) measures the positions: report() never makes a powered
        # servo follow its sent value, it reports ``physical`` as the backend set it
        self.external = False
        self.reset(config.virtual_servos or DEFAULT_SERVOS)

    def reset(self, ics: tuple[int, ...]) -> None:
        """Power-on state with virtual servos at ICS numbers ``ics``."""
        cfg = self.config
        self.ics = ics
        self.active: set[int] = set()
        self.dirty = True
        # block-address cache (see rescan): valid while the layout is "safe" and not dirty
        self.safe = False
        self.blocks: list[int | None] = [None] * ICS_COUNT
        self.vs_blocks: list[tuple[int, int]] = []
        self.vs_mixing = False
        self.out_blocks: list[tuple[int, int, bool]] = []
        self.dirty_lo = ALLOC
        self.dirty_hi = RAM_SIZE + 1
        self.physical = dict.fromkeys(ics, cfg.servo_initial_position)
        self.torque = dict.fromkeys(range(ICS_COUNT), False)

    def follow(self, ics: tuple[int, ...]) -> None:
        """The virtual servos become ``ics`` (an image for another robot was written): the new
        ones stand at the initial position, the others keep theirs."""
        if ics != self.ics:
            self.ics, old = ics, self.physical
            self.physical = {k: old.get(k, self.config.servo_initial_position) for k in ics}
            self.dirty = True

    # ------------------------------------------------------------------ write tracking

    def wrote(self, a: int, n: int) -> None:
        """RAM ``a``..``a+n-1`` was written: drop the cache if that may move a servo."""
        if a + n > self.dirty_lo and a < self.dirty_hi:
            self.dirty = True

    def block(self, ics: int) -> int | None:
        """RAM address of ICS ``ics``'s servo block, or None (unallocated, not type 0)."""
        if self.safe and not self.dirty:
            return self.blocks[ics]
        r = self.ram
        a: int = _u16(r, ALLOC + 2 * ics)[0]
        if a == NO_BLOCK or a + BLOCK_SIZE > RAM_SIZE or r[a + B_TYPE] != 0:
            return None
        return a

    def rescan(self) -> None:
        """Rebuild the set of moving servos and the block-address cache.

        The layout is *safe* when every allocated block (20 bytes) lies past the allocation
        table and no two blocks overlap. Then only writes into the table or a block (all
        reported through :meth:`wrote`) can change what :meth:`block` answers or which servos
        move, so the cache holds until such a write, and writes elsewhere need no rescan.
        Other layouts (and the plain model) keep the uncached behaviour.
        """
        r = self.ram
        self.dirty = True  # block() resolves from RAM while rebuilding
        self.safe = False
        blocks: list[int | None] = []
        spans: list[int] = []
        for ics in range(ICS_COUNT):
            a = _u16(r, ALLOC + 2 * ics)[0]
            if a == NO_BLOCK or a + BLOCK_SIZE > RAM_SIZE:
                blocks.append(None)
                continue
            spans.append(a)
            blocks.append(None if r[a + B_TYPE] != 0 else a)
        self.active = {
            ics for ics in range(ICS_COUNT) if (b := blocks[ics]) is not None and r[b + B_SPEED]
        }
        spans.sort()
        safe = (
            self.accelerate
            and all(a >= ALLOC_END for a in spans)
            and all(y - x >= BLOCK_SIZE for x, y in pairwise(spans))
        )
        self.blocks = blocks
        self.vs_blocks = [(ics, blk) for ics in self.ics if (blk := blocks[ics]) is not None]
        self.vs_mixing = any(self.mixes(b) for _, b in self.vs_blocks)
        # (ics, block, mixes) of every type-0 block: outputs() reads only these while the
        # cache holds (a write into a block, its mixing words included, makes it dirty)
        self.out_blocks = [
            (ics, blk, self.mixes(blk)) for ics, blk in enumerate(blocks) if blk is not None
        ]
        if safe:
            self.dirty_lo = ALLOC
            self.dirty_hi = spans[-1] + BLOCK_SIZE if spans else ALLOC_END
        else:  # a block may lie anywhere, below the table too (over the AD registers, say)
            self.dirty_lo = 0
            self.dirty_hi = RAM_SIZE + 1
        self.safe = safe
        self.dirty = False

    # ------------------------------------------------------------------ commands

    def start_move(self, ics: int, speed: int, pos: int) -> bool:
        """Start a move on ICS ``ics``; True if it interpolates (its update flag may be set)."""
        blk = self.block(ics)
        if blk is None:
            return False
        r = self.ram
        if speed == 0 and self.config.speed_zero == "one":
            speed = 1
        lo, hi = pos & 0xFF, (pos >> 8) & 0xFF
        if pos in (FREE, HOLD) or speed == 0:
            r[blk + B_OUTPUT] = lo
            r[blk + B_OUTPUT_HI] = hi
            r[blk + B_END] = lo
            r[blk + B_END_HI] = hi
            r[blk + B_SPEED] = 0
            r[blk + B_REMAINING] = 0
            r[blk + B_WIDTH] = 0
            r[blk + B_WIDTH_HI] = 0
            self.active.discard(ics)
            return False
        cur = _u16(r, blk + B_OUTPUT)[0]
        if cur in (FREE, HOLD):
            phys = self.physical.get(ics)
            cur = pos if phys is None else (phys - _s16(r, blk + B_BASE)[0] - self.mix(blk))
            cur &= 0xFFFF
            r[blk + B_OUTPUT] = cur & 0xFF
            r[blk + B_OUTPUT_HI] = cur >> 8
        r[blk + B_END] = lo
        r[blk + B_END_HI] = hi
        r[blk + B_SPEED] = speed
        r[blk + B_REMAINING] = speed
        d = pos - cur
        r[blk + B_WIDTH] = d & 0xFF
        r[blk + B_WIDTH_HI] = (d >> 8) & 0xFF
        self.active.add(ics)
        return True

    def command(self, cmd: ServoCommand) -> None:
        """Run a servo command (0Fh, 10h, 11h) and update the update flags."""
        r = self.ram
        flags = int.from_bytes(r[UPDATE_FLAGS:UPDATE_FLAGS_END], "little")
        if isinstance(cmd, RunSingleServo):
            # ICS 36-127 (bits 6-0 of the ICS byte) have no allocation entry: skipped like an
            # unallocated slot
            moving = cmd.ics < ICS_COUNT and self.start_move(cmd.ics, cmd.speed, cmd.position)
            if cmd.set_update_flag:
                flags = (1 << cmd.ics) if moving else 0
        else:
            if isinstance(cmd, RunSeriesServo):
                if self.config.series_servo == "nak":
                    raise EmulatedCommandError("RunSeriesServo disabled by configuration")
                if self.config.series_servo == "reset":
                    raise EmulatedReset
                moves = cmd.moves
            else:
                moves = tuple((k, cmd.speed, p) for k, p in cmd.positions)
            if cmd.set_update_flag and self.config.unselected_update_flags == "clear":
                flags = 0
            for ics, speed, pos in moves:
                moving = self.start_move(ics, speed, pos)
                if moving and cmd.set_update_flag:
                    flags |= 1 << ics
                elif not moving:
                    flags &= ~(1 << ics)
        r[UPDATE_FLAGS:UPDATE_FLAGS_END] = flags.to_bytes(5, "little")

    # ------------------------------------------------------------------ mixing

    def mixes(self, blk: int) -> bool:
        """True if the block names a mixing source (spec 9: a source word of FFFF is none);
        :meth:`mix` is 0 otherwise, so callers skip it."""
        r = self.ram
        one: int = _u16(r, blk + B_MIX1)[0]
        two: int = _u16(r, blk + B_MIX2)[0]
        return one != NO_BLOCK or two != NO_BLOCK

    def mix(self, blk: int) -> int:
        """The sum of the block's two mixing terms (source value x factor, signed)."""
        total = 0
        r = self.ram
        for src_off, method_off in SERVO.MIXES:
            src = _u16(r, blk + src_off)[0]
            rate = mix_rate(r[blk + method_off])
            if src == NO_BLOCK or not rate:
                continue
            is_ics, is_word, operand = mix_source(src)
            if is_ics:
                base = _u16(r, ALLOC + 2 * ((operand >> 8) % ICS_COUNT))[0]
                if base == NO_BLOCK:
                    continue
                a = base + (operand & 0xFF)
            else:
                a = operand
            if a + (2 if is_word else 1) > RAM_SIZE:
                continue
            v = _s16(r, a)[0] if is_word else (r[a] ^ 0x80) - 0x80
            total += v * rate
        return total

    # ------------------------------------------------------------------ output periods

    def period(self) -> None:
        """One output period: interpolation (spec 9), then the servos report (+4)."""
        self.periods += 1
        if self.dirty or not self.accelerate:
            self.rescan()
        r = self.ram
        block: Callable[[int], int | None] = self.blocks.__getitem__ if self.safe else self.block
        active = self.active
        flags_cleared = 0
        for ics in sorted(active):
            blk = block(ics)
            if blk is None or not r[blk + B_SPEED]:
                active.discard(ics)
                continue
            rem = r[blk + B_REMAINING]
            if rem == 0:
                r[blk + B_SPEED] = 0
                r[blk + B_OUTPUT] = r[blk + B_END]
                r[blk + B_OUTPUT_HI] = r[blk + B_END_HI]
                flags_cleared |= 1 << ics
                active.discard(ics)
                continue
            rem -= 1
            r[blk + B_REMAINING] = rem
            out = ramp(_u16(r, blk + B_END)[0], _u16(r, blk + B_WIDTH)[0], rem, r[blk + B_SPEED])
            r[blk + B_OUTPUT] = out & 0xFF
            r[blk + B_OUTPUT_HI] = out >> 8
        if flags_cleared:
            set_update_flags(r, update_flags(r) & ~flags_cleared)

    def report(self) -> None:
        """Virtual servos follow their sent value and report position - base into +4 (with a
        servo backend, :attr:`external`, they report the positions it measured)."""
        r = self.ram
        hold_is_free = self.config.position_7fff == "free"
        physical = self.physical
        torque = self.torque
        external = self.external
        if self.safe:
            pairs = self.vs_blocks
        else:
            pairs = [(k, b) for k in self.ics if (b := self.block(k)) is not None]
        if external:  # the backend set every position: report it, powered unless freed
            for ics, blk in pairs:
                torque[ics] = output_mode(_u16(r, blk + B_OUTPUT)[0], hold_is_free) != "free"
                m = (physical[ics] - _s16(r, blk + B_BASE)[0]) & 0xFFFF
                r[blk + B_MEASURED] = m & 0xFF
                r[blk + B_MEASURED_HI] = m >> 8
            return
        for ics, blk in pairs:
            out = _u16(r, blk + B_OUTPUT)[0]
            base = _s16(r, blk + B_BASE)[0]
            mode = output_mode(out, hold_is_free)
            if mode == "free":
                torque[ics] = False
                p = physical[ics]
            elif mode == "hold":
                torque[ics] = True
                p = physical[ics]
            else:
                v = out + base
                if self.mixes(blk):
                    v += self.mix(blk)
                p = 0 if v < 0 else (v if v <= 0xFFFF else 0xFFFF)
                physical[ics] = p
                torque[ics] = True
            m = (p - base) & 0xFFFF
            r[blk + B_MEASURED] = m & 0xFF
            r[blk + B_MEASURED_HI] = m >> 8

    # ------------------------------------------------------------------ host views

    def sent(self, blk: int, mixing: bool | None = None) -> int:
        """The value sent from block ``blk``: output + base + mixing (spec 9); ``mixing``:
        whether the block mixes, when the caller knows (else read from the block)."""
        out: int = _u16(self.ram, blk + B_OUTPUT)[0]
        if out in (FREE, HOLD) and self.config.free_hold_base == "omit":
            return out
        base: int = _s16(self.ram, blk + B_BASE)[0]
        if mixing is None:
            mixing = self.mixes(blk)
        return (out + base + (self.mix(blk) if mixing else 0)) & 0xFFFF

    def outputs(self) -> dict[int, int]:
        """The value sent to each allocated servo: output + base + mixing (spec 9)."""
        if self.safe and not self.dirty:  # the cached blocks and their mixing flags
            return {ics: self.sent(blk, mixing) for ics, blk, mixing in self.out_blocks}
        out = {}
        for ics in range(ICS_COUNT):
            blk = self.block(ics)
            if blk is not None:
                out[ics] = self.sent(blk)
        return out

    def mode(self, ics: int) -> ServoMode | None:
        """:func:`output_mode` of ICS ``ics``'s block under this board's config (None: no
        type-0 block)."""
        blk = self.block(ics)
        if blk is None:
            return None
        return output_mode(_u16(self.ram, blk + B_OUTPUT)[0], self.config.position_7fff == "free")

    def flag_wait(self, flags: int) -> int | None:
        """Output periods until every update flag in ``flags`` has cleared: one more than the
        longest remaining count of the flagged servos' moves (0: no flag set). None when a
        flagged servo has no move in progress, so its flag never clears. The one rule for how
        long the program waits on update flags: the accelerator skips these periods
        (:func:`rcb4hv.emulator.accel.skip_periods`) and the simulator steps over them."""
        r = self.ram
        longest = 0
        while flags:
            low = flags & -flags
            ics = low.bit_length() - 1
            flags ^= low
            blk = self.block(ics) if ics < ICS_COUNT else None
            if blk is None or not r[blk + B_SPEED]:
                return None
            longest = max(longest, r[blk + B_REMAINING] + 1)
        return longest

    def state(self, ics: int) -> ServoState | None:
        blk = self.block(ics)
        if blk is None:
            return None
        out = _u16(self.ram, blk + B_OUTPUT)[0]
        return ServoState(
            ics=ics,
            output=out,
            sent=self.sent(blk),
            position=self.physical.get(ics, out),
            torque=self.torque.get(ics, False),
            moving=bool(self.ram[blk + B_SPEED]),
        )
