"""The RCB-4HV board model: bytes in, bytes out, driven by an injected clock.

See the package docstring (:mod:`rcb4hv.emulator`) for the exact bad-input rules and the model
of time. Every frame is decoded by the protocol core (:class:`~rcb4hv.protocol.FrameDecoder`,
:func:`~rcb4hv.protocol.decode_command`) and every reply built by
:func:`~rcb4hv.protocol.encode_reply`; ROM instructions are decoded the same way (once per PC,
cached until the ROM is written).
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path
from typing import Final

from rcb4hv.emulator.clock import Clock, VirtualClock
from rcb4hv.emulator.config import EmulatorConfig
from rcb4hv.emulator.romstore import RomStore
from rcb4hv.errors import ChecksumError, FrameError, ProtocolError
from rcb4hv.protocol import (
    ADDR,
    FRAME_PERIODS_MS,
    ICS_COUNT,
    NEED_DATA,
    POSITION_FREE,
    POSITION_HOLD,
    RAM_SIZE,
    ROM_SIZE,
    SYS,
    Ack,
    AcknowledgeCheck,
    Add,
    And,
    Call,
    Com,
    Command,
    CommunicateDevice,
    Condition,
    Data,
    DataReply,
    Div,
    FrameDecoder,
    GetVersionInfo,
    Ics,
    Jump,
    Mod,
    Move,
    Mul,
    Nak,
    Not,
    Or,
    Ram,
    Reply,
    Return,
    Rom,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
    Shift,
    Sub,
    VersionReply,
    Xor,
    decode_command,
    encode_reply,
    frame_at,
)

__all__ = ["Board", "ServoState"]

log = logging.getLogger(__name__)

ALLOC: Final = ADDR.ICS_ALLOC
STACK_DEPTH: Final = 16
TIMER_PERIOD_US: Final = 100_000
FRAME_US: Final = tuple(ms * 1000 for ms in FRAME_PERIODS_MS)
FREE: Final = POSITION_FREE
HOLD: Final = POSITION_HOLD
# the system-register bits as the hot paths test them: low byte ram[0], high byte ram[1]
SYS_ICS: Final = SYS.ICS_OUTPUT
SYS_ROM: Final = SYS.ROM_RUN
SYS_VEC: Final = SYS.VECTOR_JUMP
Z_BIT: Final = SYS.ZERO >> 8
C_BIT: Final = SYS.CARRY >> 8
ROMERR_BIT: Final = SYS.ROM_ERROR >> 8
STATIC_VECTOR_RAM: Final = 0x0350  # vector operands from here up never change by themselves

# cache entries for ROM instructions: (command or None, size, kind)
_OK: Final = 0
_ROMERR: Final = 1
_CMDERR: Final = 2

OutputListener = Callable[[float, dict[int, int]], None]
Executor = Callable[[int], object]
Entry = tuple[Command | None, int, int, Executor | None]


# the binary operations ROM instructions run through a specialised closure (see _compile)
_FAST_BINARY: Final[dict[type, int]] = {And: 0, Or: 1, Xor: 2, Add: 3, Sub: 4, Mul: 5}


class _CommandError(Exception):
    """A command that cannot execute: NAK from COM, program stop from ROM."""


class _Reset(Exception):
    """The board resets (config series_servo='reset')."""


@dataclass(frozen=True, slots=True)
class ServoState:
    """What one ICS channel is doing at the last output period."""

    ics: int
    output: int
    sent: int
    position: int
    torque: bool
    moving: bool


def _s16(v: int) -> int:
    return v - 0x10000 if v & 0x8000 else v


def _ramp(end: int, width: int, remaining: int, speed: int) -> int:
    """Output with ``remaining`` of ``speed`` steps left (spec 9): end -/+ |width|*rem/speed,
    ``width`` given as its raw 16-bit two's-complement word."""
    if width & 0x8000:
        return (end + (0x10000 - width) * remaining // speed) & 0xFFFF
    return (end - width * remaining // speed) & 0xFFFF


class Board:
    """An emulated RCB-4HV (HeartToHeart4 2.2 firmware behaviour)."""

    def __init__(
        self,
        config: EmulatorConfig | None = None,
        *,
        clock: Clock | None = None,
        rom_image: bytes | bytearray | None = None,
        rom_path: str | Path | None = None,
    ) -> None:
        self.config = config if config is not None else EmulatorConfig()
        self.clock: Clock = clock if clock is not None else VirtualClock()
        self._store: RomStore | None = None
        image: bytes | None = None
        if rom_path is not None:
            self._store = RomStore(rom_path, ROM_SIZE, self.config.rom_flush_delay_s)
            image = self._store.load()
        if image is None and rom_image is not None:
            if len(rom_image) > ROM_SIZE:
                raise ValueError(f"ROM image of {len(rom_image)} bytes exceeds {ROM_SIZE}")
            image = bytes(rom_image).ljust(ROM_SIZE, b"\xff")
        if image is None:
            from rcb4hv.rom.default import default_image

            image = default_image()
        self.rom = bytearray(image)
        if self._store is not None and not self._store.path.exists():
            self._store.flush(self.rom)
        self.ram = bytearray(RAM_SIZE)
        self._decoder = FrameDecoder(resync="frame")
        self._discard = 0
        self._discard_cmd: int | None = None
        self._last_rx = 0.0
        self._output = bytearray()
        self._listeners: list[OutputListener] = []
        self._cache: dict[int, Entry] = {}
        self._vector_memo: tuple[int, tuple[tuple[int, int], ...], bytes] | None = None
        self._static_memo: tuple[int, bytearray, bool] | None = None
        self._loop_memo: dict[tuple[int, int], int] = {}
        self.stretch: dict[int, int] = {}
        self.speed_parameter: dict[int, int] = {}
        self.frames_handled = 0
        self.instructions_executed = 0
        self.periods = 0
        self._closed = False
        self.power_on()

    # ------------------------------------------------------------------ lifecycle

    def power_on(self) -> None:
        """Reset RAM and the program state to the power-on values (spec 10.1)."""
        cfg = self.config
        r = self.ram
        r[:] = bytes(RAM_SIZE)
        r[0:2] = cfg.power_on_system_register.to_bytes(2, "little")
        r[0x0022:0x0024] = cfg.ad0.to_bytes(2, "little")
        for i, v in enumerate(cfg.ad_values):
            r[0x0024 + 2 * i : 0x0026 + 2 * i] = v.to_bytes(2, "little")
        r[0x0038:0x003A] = (0x03FF).to_bytes(2, "little")
        for t in range(4):
            r[0x003C + 2 * t : 0x003E + 2 * t] = FREE.to_bytes(2, "little")
        r[ALLOC : ALLOC + 72] = b"\xff" * 72
        r[0x008C:0x008E] = b"\xff\xff"
        self._stack = [0] * STACK_DEPTH
        t = self._us(self.clock.now())
        self._now = t
        self._prog_t = t
        self._credit = 0.0
        self._next_period = t + self._period_us()
        self._next_timer = t + TIMER_PERIOD_US
        self._active: set[int] = set()
        self._dirty = True
        # Block-address cache (see _rescan): valid while the layout is "safe" and not dirty.
        self._safe = False
        self._blocks: list[int | None] = [None] * 36
        self._vs_blocks: list[tuple[int, int]] = []
        self._vs_mixing = False
        self._dirty_lo = ALLOC
        self._dirty_hi = RAM_SIZE + 1
        self._physical = dict.fromkeys(cfg.virtual_servos, cfg.servo_initial_position)
        self._torque = dict.fromkeys(range(36), False)
        self._decoder.reset()
        self._discard = 0
        self._discard_cmd = None

    def close(self) -> None:
        """Flush a persistent ROM image."""
        if self._store is not None and self._store.dirty:
            self._store.flush(self.rom)
        self._closed = True

    def __enter__(self) -> Board:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def flush_rom(self) -> None:
        """Write the persistent ROM image now (no-op without ``rom_path``)."""
        if self._store is not None and self._store.dirty:
            self._store.flush(self.rom)

    # ------------------------------------------------------------------ time

    @staticmethod
    def _us(seconds: float) -> int:
        return int(seconds * 1_000_000)

    def _period_us(self) -> int:
        return FRAME_US[(self.ram[0] >> 4) & 3]

    @property
    def now(self) -> float:
        """Board time (seconds) the model has been brought up to."""
        return self._now / 1_000_000

    @property
    def output_period(self) -> float:
        """The current output period in seconds (system register bits 5-4)."""
        return self._period_us() / 1_000_000

    def tick(self) -> None:
        """Bring the model up to ``clock.now()``; may queue a NAK for a timed-out frame."""
        now = self.clock.now()
        self._advance(int(now * 1_000_000))
        if self._discard or self._decoder.pending:
            self._check_frame_timeout(now)
        if self._store is not None:
            self._store.maybe_flush(self.rom)

    def run_for(self, seconds: float) -> None:
        """Virtual clock only: advance the clock by ``seconds`` and tick."""
        if not isinstance(self.clock, VirtualClock):
            raise TypeError("run_for needs a VirtualClock")
        self.clock.advance(seconds)
        self.tick()

    def poll_timeout(self) -> float | None:
        """Real seconds a server may wait before the next tick is needed (None: no need)."""
        speed = float(getattr(self.clock, "speed", 1.0))
        now = self.clock.now()
        waits: list[float] = []
        if self._program_runnable() or self._active:
            waits.append(max(0.0, (self._next_period / 1e6 - now) / speed))
        if self._decoder.pending or self._discard:
            due = self._last_rx + self.config.frame_timeout_s * speed
            waits.append(max(0.0, (due - now) / speed))
        if self._store is not None:
            w = self._store.seconds_until_flush()
            if w is not None:
                waits.append(w)
        return min(waits) if waits else None

    def _advance(self, t: int) -> None:
        while True:
            np, nt = self._next_period, self._next_timer
            nxt = np if np < nt else nt
            if nxt > t:
                break
            self._run_program(nxt)
            do_timer = nt <= np
            if np <= nt:  # (a skip past nt is fine: the timers are all stopped then)
                r = self.ram
                timers_idle = r[0x3D] & r[0x3F] & r[0x41] & r[0x43] & 0x80
                np = self._skip_periods(np, t if timers_idle else min(t, nt))
                self._run_program(np)
                self._now = np
                self._period()
                self._next_period = np + self._period_us()
                do_timer = np == nt
                if np > nt:  # skipped past stopped timers: keep their 100 ms grid
                    self._next_timer = nt + (np - nt) // TIMER_PERIOD_US * TIMER_PERIOD_US
                    do_timer = False
            if do_timer:
                self._now = nt
                self._timers()
                self._next_timer = nt + TIMER_PERIOD_US
        self._run_program(t)
        self._now = t

    # ------------------------------------------------------------------ input / output

    def feed(self, data: bytes | bytearray) -> bytes:
        """Process received bytes; return the reply bytes of every complete frame."""
        self.tick()
        out = bytearray()
        if data:
            self._last_rx = self.clock.now()
            self._consume(bytes(data), out)
        return bytes(out)

    def reset_input(self) -> None:
        """Drop partial input silently (the link was closed)."""
        self._decoder.reset()
        self._discard = 0
        self._discard_cmd = None

    def take_output(self) -> bytes:
        """Bytes produced outside :meth:`feed` (a NAK after a frame timeout)."""
        out = bytes(self._output)
        self._output.clear()
        return out

    def _queue(self, data: bytes) -> None:
        self._output += data
        excess = len(self._output) - self.config.max_pending_output
        if excess > 0:
            del self._output[:excess]

    def _nak(self, cmd: int) -> bytes:
        return encode_reply(Nak(cmd))

    def _consume(self, data: bytes, out: bytearray) -> None:
        dec = self._decoder
        while data:
            if self._discard:
                take = data[: self._discard]
                if self._discard_cmd is None:
                    self._discard_cmd = take[0]
                self._discard -= len(take)
                data = data[len(take) :]
                if not self._discard:
                    if self.config.oversize_frame == "nak":
                        out += self._nak(self._discard_cmd)
                    self._discard_cmd = None
                continue
            dec.receive_data(data)
            data = b""
            while True:
                head = dec.pending[:1]
                try:
                    frame = dec.next_frame()
                except ChecksumError as exc:
                    log.debug("checksum error in %s", exc.frame.hex(" "))
                    out += self._nak(exc.frame[1])
                    continue
                except FrameError:
                    size = head[0]
                    if size > 128:
                        log.debug("oversize frame (SIZE %d): swallowed", size)
                        data = dec.reset()
                        self._discard = size - 1
                        self._discard_cmd = None
                        break
                    log.debug("dropped byte %02X that cannot start a frame", size)
                    continue
                if frame is NEED_DATA:
                    break
                assert isinstance(frame, bytes)
                out += self._handle_frame(frame)

    def _check_frame_timeout(self, now: float) -> None:
        if not (self._decoder.pending or self._discard):
            return
        speed = float(getattr(self.clock, "speed", 1.0))
        if now - self._last_rx < self.config.frame_timeout_s * speed:
            return
        partial = self._decoder.reset()
        cmd = partial[1] if len(partial) >= 2 else self._discard_cmd
        self._discard = 0
        self._discard_cmd = None
        log.debug("frame timeout with %d partial bytes", len(partial))
        if cmd is not None and self.config.partial_frame_reply == "nak":
            self._queue(self._nak(cmd))

    def _handle_frame(self, frame: bytes) -> bytes:
        self.frames_handled += 1
        try:
            cmd = decode_command(frame)
        except ProtocolError as exc:
            log.debug("NAK for undecodable frame %s: %s", frame.hex(" "), exc)
            return self._nak(frame[1])
        try:
            reply = self._execute(cmd, None)
        except _CommandError as exc:
            log.debug("NAK for %s: %s", frame.hex(" "), exc)
            return self._nak(frame[1])
        except _Reset:
            log.info("board reset by %s", frame.hex(" "))
            self.power_on()
            return b""
        except Exception:
            log.exception("internal error while executing %s; answering NAK", frame.hex(" "))
            return self._nak(frame[1])
        return encode_reply(reply) if reply is not None else b""

    # ------------------------------------------------------------------ memory helpers

    def _w(self, a: int) -> int:
        r = self.ram
        return r[a] | r[a + 1] << 8

    def _set_w(self, a: int, v: int) -> None:
        self.ram[a] = v & 0xFF
        self.ram[a + 1] = (v >> 8) & 0xFF

    @property
    def pc(self) -> int:
        r = self.ram
        return r[2] | r[3] << 8 | r[4] << 16

    def _set_pc(self, v: int) -> None:
        r = self.ram
        r[2] = v & 0xFF
        r[3] = (v >> 8) & 0xFF
        r[4] = (v >> 16) & 0xFF

    @property
    def system_register(self) -> int:
        r = self.ram
        return r[0] | r[1] << 8

    @property
    def call_stack(self) -> list[int]:
        """The return addresses currently on the stack (depth from RAM 0005h)."""
        return self._stack[: min(self.ram[5], STACK_DEPTH)]

    def alloc(self, ics: int) -> int:
        """``alloc[ics]``: RAM address of the device block of ICS ``ics`` (FFFF = none)."""
        r = self.ram
        a = ALLOC + 2 * ics
        return r[a] | r[a + 1] << 8

    def _touch(self, a: int, n: int) -> None:
        """A host hook wrote RAM ``a``..``a+n-1`` directly: keep the block cache honest."""
        if self._safe and a + n > self._dirty_lo and a < self._dirty_hi:
            self._dirty = True

    def _ram_address(self, op: Ram | Ics, size: int) -> int:
        if isinstance(op, Ram):
            a = op.address
        else:
            base = self._w(ALLOC + 2 * op.ics)
            if base == 0xFFFF:
                raise _CommandError(f"ICS {op.ics} is not allocated")
            a = base + op.offset
        if a + size > RAM_SIZE:
            raise _CommandError(f"RAM {a:04X}h + {size} runs past the end")
        return a

    def _read(self, op: Ram | Ics | Rom | Data | Com, size: int) -> bytes:
        if isinstance(op, Data):
            return op.data
        if isinstance(op, Rom):
            if op.address + size > ROM_SIZE:
                raise _CommandError("ROM read past the end")
            return bytes(self.rom[op.address : op.address + size])
        if isinstance(op, Com):
            return bytes(size)
        a = self._ram_address(op, size)
        return bytes(self.ram[a : a + size])

    def _write(self, op: Ram | Ics | Rom | Com, data: bytes) -> None:
        n = len(data)
        if isinstance(op, Com):
            return
        if isinstance(op, Rom):
            if op.address + n > ROM_SIZE:
                raise _CommandError("ROM write past the end")
            self.rom[op.address : op.address + n] = data
            self._cache.clear()
            self._loop_memo.clear()
            if self._store is not None:
                self._store.mark_dirty()
            return
        a = self._ram_address(op, n)
        self.ram[a : a + n] = data
        if a + n > self._dirty_lo and a < self._dirty_hi:
            self._dirty = True

    def _set_flags(self, z: bool | None, c: bool | None) -> None:
        hi = self.ram[1]
        if z is not None:
            hi = (hi | Z_BIT) if z else (hi & ~Z_BIT)
        if c is not None:
            hi = (hi | C_BIT) if c else (hi & ~C_BIT)
        self.ram[1] = hi

    def _holds(self, cond: Condition) -> bool:
        hi = self.ram[1]
        return self._holds_zc(cond, bool(hi & Z_BIT), bool(hi & C_BIT))

    def _holds_zc(self, cond: Condition, z: bool, c: bool) -> bool:
        if self.config.branch_condition == "and":
            return cond.holds(z, c)
        checks = []
        if cond.compare_z:
            checks.append(z == cond.z)
        if cond.compare_c:
            checks.append(c == cond.c)
        return not checks or any(checks)

    # ------------------------------------------------------------------ execution

    def _execute(self, cmd: Command, next_pc: int | None) -> Reply | None:
        """Run one command; ``next_pc`` is None from COM, else the address after it in ROM."""
        from_com = next_pc is None
        if isinstance(cmd, Move):
            data = self._read(cmd.src, cmd.nbytes)
            if isinstance(cmd.dst, Com):
                return DataReply(cmd.cmd, data)
            self._write(cmd.dst, data)
            return Ack(cmd.cmd)
        if isinstance(cmd, (And, Or, Xor, Add, Sub, Mul, Div, Mod, Not, Shift)):
            result = self._data_op(cmd)
            if self.config.logic_reply == "ack":
                return Ack(cmd.cmd)
            return DataReply(cmd.cmd, result)
        if isinstance(cmd, (RunSingleServo, RunConstFrameServo, RunSeriesServo)):
            self._servo_command(cmd)
            return Ack(cmd.cmd)
        if isinstance(cmd, (SetSpeed, SetStretch)):
            target = self.stretch if isinstance(cmd, SetStretch) else self.speed_parameter
            for ics, v in cmd.values:
                target[ics] = v
            return Ack(cmd.cmd)
        if isinstance(cmd, Jump):
            if self._holds(cmd.condition):
                self._set_pc(cmd.address % ROM_SIZE)
            return Ack(cmd.cmd)
        if isinstance(cmd, Call):
            if self._holds(cmd.condition):
                self._push(self.pc if from_com else next_pc)  # type: ignore[arg-type]
                self._set_pc(cmd.address % ROM_SIZE)
            return Ack(cmd.cmd)
        if isinstance(cmd, Return):
            self._set_pc(self._pop())
            return Ack(cmd.cmd)
        if isinstance(cmd, GetVersionInfo):
            return VersionReply(self.config.version_string) if from_com else None
        if isinstance(cmd, AcknowledgeCheck):
            return Ack(cmd.cmd) if from_com else None
        if isinstance(cmd, CommunicateDevice):
            raise _CommandError("ICS communication (0Eh): no device answers")
        raise _CommandError(f"unsupported command {cmd!r}")  # pragma: no cover

    def _push(self, addr: int) -> None:
        d = self.ram[5]
        if d >= STACK_DEPTH:
            raise _CommandError("call stack overflow (17th nested CALL)")
        self._stack[d] = addr
        self.ram[5] = d + 1

    def _pop(self) -> int:
        d = self.ram[5]
        if d == 0 or d > STACK_DEPTH:
            raise _CommandError("RETURN with an empty call stack")
        self.ram[5] = d - 1
        return self._stack[d - 1]

    def _data_op(self, cmd: And | Or | Xor | Add | Sub | Mul | Div | Mod | Not | Shift) -> bytes:
        size = cmd.nbytes
        dst = cmd.dst
        dv = int.from_bytes(self._read(dst, size), "little")
        bits = 8 * size
        mask = (1 << bits) - 1
        z: bool
        c: bool | None = None
        if isinstance(cmd, (Not, Shift)):
            if isinstance(cmd, Not):
                r = ~dv & mask
            else:
                k = cmd.right_bits
                if self.config.shift_direction == "inverted":
                    k = -k
                if k > 0:
                    r = dv >> k
                    c = bool(dv >> (k - 1) & 1)
                elif k < 0:
                    k = -k
                    r = (dv << k) & mask
                    c = bool(dv >> (bits - k) & 1) if k <= bits else False
                else:
                    r = dv
        else:
            sv = int.from_bytes(self._read(cmd.src, size), "little")
            if isinstance(cmd, And):
                r = dv & sv
            elif isinstance(cmd, Or):
                r = dv | sv
            elif isinstance(cmd, Xor):
                r = dv ^ sv
            elif isinstance(cmd, Add):
                full = dv + sv
                r, c = full & mask, full > mask
            elif isinstance(cmd, Sub):
                r, c = (dv - sv) & mask, dv >= sv
            elif isinstance(cmd, Mul):
                full = dv * sv
                r, c = full & mask, full > mask
            else:
                if sv == 0:
                    if self.config.division_by_zero == "error":
                        raise _CommandError("division by zero")
                    r = 0
                else:
                    r = dv // sv if isinstance(cmd, Div) else dv % sv
                c = False
        if c is None and self.config.logic_carry == "clear":
            c = False
        z = r == 0
        result = r.to_bytes(size, "little")
        if not cmd.no_write:
            self._write(dst, result)
        self._set_flags(z, c)
        return result

    # ------------------------------------------------------------------ servos

    def _block(self, ics: int) -> int | None:
        if self._safe and not self._dirty:
            return self._blocks[ics]
        a = self._w(ALLOC + 2 * ics)
        if a == 0xFFFF or a + 20 > RAM_SIZE or self.ram[a] != 0:
            return None
        return a

    def _start_move(self, ics: int, speed: int, pos: int) -> bool:
        """Start a move on ICS ``ics``; True if it interpolates (its update flag may be set)."""
        blk = self._block(ics)
        if blk is None:
            return False
        r = self.ram
        if speed == 0 and self.config.speed_zero == "one":
            speed = 1
        lo, hi = pos & 0xFF, (pos >> 8) & 0xFF
        if pos in (FREE, HOLD) or speed == 0:
            r[blk + 6] = lo
            r[blk + 7] = hi
            r[blk + 9] = lo
            r[blk + 10] = hi
            r[blk + 8] = 0
            r[blk + 11] = 0
            r[blk + 12] = 0
            r[blk + 13] = 0
            self._active.discard(ics)
            return False
        cur = r[blk + 6] | r[blk + 7] << 8
        if cur in (FREE, HOLD):
            phys = self._physical.get(ics)
            cur = pos if phys is None else (phys - _s16(self._w(blk + 2)) - self._mix(blk))
            cur &= 0xFFFF
            r[blk + 6] = cur & 0xFF
            r[blk + 7] = cur >> 8
        r[blk + 9] = lo
        r[blk + 10] = hi
        r[blk + 8] = speed
        r[blk + 11] = speed
        d = pos - cur
        r[blk + 12] = d & 0xFF
        r[blk + 13] = (d >> 8) & 0xFF
        self._active.add(ics)
        return True

    def _servo_command(self, cmd: RunSingleServo | RunConstFrameServo | RunSeriesServo) -> None:
        flags = int.from_bytes(self.ram[7:12], "little")
        if isinstance(cmd, RunSingleServo):
            # ICS 36-127 (bits 6-0 of the ICS byte) have no allocation entry: skipped like an
            # unallocated slot
            moving = cmd.ics < ICS_COUNT and self._start_move(cmd.ics, cmd.speed, cmd.position)
            if cmd.set_update_flag:
                flags = (1 << cmd.ics) if moving else 0
        else:
            if isinstance(cmd, RunSeriesServo):
                if self.config.series_servo == "nak":
                    raise _CommandError("RunSeriesServo disabled by configuration")
                if self.config.series_servo == "reset":
                    raise _Reset
                moves = cmd.moves
            else:
                moves = tuple((k, cmd.speed, p) for k, p in cmd.positions)
            if cmd.set_update_flag and self.config.unselected_update_flags == "clear":
                flags = 0
            for ics, speed, pos in moves:
                moving = self._start_move(ics, speed, pos)
                if moving and cmd.set_update_flag:
                    flags |= 1 << ics
                elif not moving:
                    flags &= ~(1 << ics)
        self.ram[7:12] = flags.to_bytes(5, "little")

    def _mix(self, blk: int) -> int:
        total = 0
        r = self.ram
        for off in (14, 17):
            src = r[blk + off] | r[blk + off + 1] << 8
            method = r[blk + off + 2]
            if src == 0xFFFF or not method & 0x7F:
                continue
            if src & 0x8000:
                base = self._w(ALLOC + 2 * (((src >> 8) & 0x3F) % 36))
                if base == 0xFFFF:
                    continue
                a = base + (src & 0xFF)
            else:
                a = src & 0x0FFF
            word = bool(src & 0x4000)
            if a + (2 if word else 1) > RAM_SIZE:
                continue
            v = _s16(r[a] | r[a + 1] << 8) if word else (r[a] ^ 0x80) - 0x80
            m = method & 0x7F
            total += -v * m if method & 0x80 else v * m
        return total

    def _rescan(self) -> None:
        """Rebuild the set of moving servos and the block-address cache.

        The layout is *safe* when every allocated block (20 bytes) lies past the allocation
        table and no two blocks overlap. Then only writes through :meth:`_write` (and the host
        hooks) into the table or a block can change what :meth:`_block` answers or which
        servos move, so the cache holds until such a write marks the board dirty, and writes
        elsewhere need no rescan. Other layouts keep the original, uncached behaviour.
        """
        r = self.ram
        self._dirty = True  # _block resolves from RAM while rebuilding
        self._safe = False
        blocks: list[int | None] = []
        spans: list[int] = []
        for ics in range(36):
            a = r[ALLOC + 2 * ics] | r[ALLOC + 2 * ics + 1] << 8
            if a == 0xFFFF or a + 20 > RAM_SIZE:
                blocks.append(None)
                continue
            spans.append(a)
            blocks.append(None if r[a] != 0 else a)
        active = set()
        for ics in range(36):
            blk = blocks[ics]
            if blk is not None and r[blk + 8]:
                active.add(ics)
        self._active = active
        spans.sort()
        safe = all(a >= 0x008C for a in spans) and all(y - x >= 20 for x, y in pairwise(spans))
        self._blocks = blocks
        self._vs_blocks = [
            (ics, blk) for ics in self.config.virtual_servos if (blk := blocks[ics]) is not None
        ]
        self._vs_mixing = any(r[b + 14] != 0xFF or r[b + 17] != 0xFF for _, b in self._vs_blocks)
        if safe:
            self._dirty_lo = ALLOC
            self._dirty_hi = spans[-1] + 20 if spans else 0x008C
        else:
            self._dirty_lo = ALLOC
            self._dirty_hi = RAM_SIZE + 1
        self._safe = safe
        self._dirty = False

    def _period(self) -> None:
        """One output period: interpolation (spec 9), then the servos report (+4)."""
        self.periods += 1
        if self._dirty:
            self._rescan()
        r = self.ram
        block = self._blocks.__getitem__ if self._safe else self._block
        active = self._active
        flags_cleared = 0
        for ics in list(active):
            blk = block(ics)
            if blk is None or not r[blk + 8]:
                active.discard(ics)
                continue
            rem = r[blk + 11]
            if rem == 0:
                r[blk + 8] = 0
                r[blk + 6] = r[blk + 9]
                r[blk + 7] = r[blk + 10]
                flags_cleared |= 1 << ics
                active.discard(ics)
                continue
            rem -= 1
            r[blk + 11] = rem
            out = _ramp(
                r[blk + 9] | r[blk + 10] << 8, r[blk + 12] | r[blk + 13] << 8, rem, r[blk + 8]
            )
            r[blk + 6] = out & 0xFF
            r[blk + 7] = out >> 8
        if flags_cleared:
            flags = int.from_bytes(r[7:12], "little") & ~flags_cleared
            r[7:12] = flags.to_bytes(5, "little")
        if r[0] & SYS_ICS:
            self._report()
        if self._listeners:
            t = self._now / 1e6
            outs = self.servo_outputs()
            for cb in self._listeners:
                cb(t, outs)

    def _report(self) -> None:
        """Virtual servos follow their sent value and report position - base into +4."""
        r = self.ram
        hold_is_free = self.config.position_7fff == "free"
        physical = self._physical
        torque = self._torque
        if self._safe:
            pairs = self._vs_blocks
        else:
            pairs = [
                (k, b) for k in self.config.virtual_servos if (b := self._block(k)) is not None
            ]
        for ics, blk in pairs:
            out = r[blk + 6] | r[blk + 7] << 8
            base = r[blk + 2] | r[blk + 3] << 8
            if base & 0x8000:
                base -= 0x10000
            if out == FREE or (out == HOLD and hold_is_free):
                torque[ics] = False
                p = physical[ics]
            elif out == HOLD:
                torque[ics] = True
                p = physical[ics]
            else:
                v = out + base
                if r[blk + 14] != 0xFF or r[blk + 17] != 0xFF:
                    v += self._mix(blk)
                p = 0 if v < 0 else (v if v <= 0xFFFF else 0xFFFF)
                physical[ics] = p
                torque[ics] = True
            m = (p - base) & 0xFFFF
            r[blk + 4] = m & 0xFF
            r[blk + 5] = m >> 8

    def _timers(self) -> None:
        r = self.ram
        for a in (0x003C, 0x003E, 0x0040, 0x0042):
            v = r[a] | r[a + 1] << 8
            if v & 0x8000:
                continue
            v = (v - 1) & 0x7FFF if v else 0
            if v == 0:
                v = 0x8000
            r[a] = v & 0xFF
            r[a + 1] = v >> 8

    # ------------------------------------------------------------------ fast-forward

    def _skip_periods(self, np: int, horizon: int) -> int:
        """Apply in closed form the periods that nobody can observe; return the next to run.

        Allowed only while the ROM program cannot run before ``horizon`` (stopped, or
        waiting on update flags with no time-dependent vector jump), with no output listener
        and no mixing on a reporting servo. The last period before ``horizon`` (or the one
        that clears the last update flag) is left to :meth:`_period`, so RAM ends exactly as
        if every period had been stepped.
        """
        if self._listeners or horizon - np < 2 * FRAME_US[0]:
            return np
        r = self.ram
        sysw = r[0]
        if sysw & SYS_ROM:
            flags = int.from_bytes(r[7:12], "little")
            if not flags:
                return np
            if sysw & SYS_VEC and not self._vector_static():
                return np
        else:
            flags = 0
        if self._dirty:
            self._rescan()
        block: Callable[[int], int | None]
        if self._safe:
            if self._vs_mixing:
                return np
            block = self._blocks.__getitem__
        else:
            for ics in self.config.virtual_servos:
                blk = self._block(ics)
                if blk is not None and (r[blk + 14] != 0xFF or r[blk + 17] != 0xFF):
                    return np
            block = self._block
        T = self._period_us()
        n = (horizon - np) // T + 1
        info: list[tuple[int, int]] = []
        unblock = 0
        for ics in self._active:
            blk = block(ics)
            if blk is None:
                return np
            info.append((ics, blk))
            if flags >> ics & 1:
                unblock = max(unblock, r[blk + 11] + 1)
        if flags:
            pending = flags
            for ics, _ in info:
                pending &= ~(1 << ics)
            k = n if pending else min(n, unblock)
        else:
            k = n
        skip = k - 1
        if skip <= 0:
            return np
        cleared = 0
        for ics, blk in info:
            rem = r[blk + 11]
            if skip > rem:
                r[blk + 8] = 0
                r[blk + 6] = r[blk + 9]
                r[blk + 7] = r[blk + 10]
                r[blk + 11] = 0
                cleared |= 1 << ics
                self._active.discard(ics)
            else:
                rem -= skip
                r[blk + 11] = rem
                end = r[blk + 9] | r[blk + 10] << 8
                out = _ramp(end, r[blk + 12] | r[blk + 13] << 8, rem, r[blk + 8])
                r[blk + 6] = out & 0xFF
                r[blk + 7] = out >> 8
        if cleared:
            f = int.from_bytes(r[7:12], "little") & ~cleared
            r[7:12] = f.to_bytes(5, "little")
        self.periods += skip
        return np + skip * T

    def _vector_static(self) -> bool:
        """True when no vector package reads RAM that changes by itself (memoised on the
        table's bytes: the answer depends on nothing else)."""
        table = self._w(0x008C)
        if table == 0xFFFF:
            return True
        if table < STATIC_VECTOR_RAM:
            return False
        snap = self.ram[table : table + 256]
        memo = self._static_memo
        if memo is not None and memo[0] == table and memo[1] == snap:
            return memo[2]
        result = self._vector_static_scan(table)
        self._static_memo = (table, snap, result)
        return result

    def _vector_static_scan(self, table: int) -> bool:
        for i in range(32):
            a = table + 8 * i
            if a + 8 > RAM_SIZE:
                return True
            c = self.ram[a]
            for off, is_src in ((1, False), (3, True)):
                if is_src and c & 0x10:
                    continue
                w = self._w(a + off)
                if w & 0x8000 or w < STATIC_VECTOR_RAM or w + 2 > RAM_SIZE:
                    return False
            if c & 0x80:
                return True
        return True

    # ------------------------------------------------------------------ ROM program

    def _program_runnable(self) -> bool:
        r = self.ram
        if not r[0] & SYS_ROM:
            return False
        return not any(r[7:12]) or bool(r[0] & SYS_VEC and self._w(0x008C) != 0xFFFF)

    def _run_program(self, until: int) -> None:
        if until <= self._prog_t:
            return
        credit = self._credit + (until - self._prog_t) * self.config.instructions_per_ms / 1000
        self._prog_t = until
        r = self.ram
        cache = self._cache
        seen_loop: tuple[int, int] | None = None
        while credit >= 1:
            sysw = r[0]
            if not sysw & SYS_ROM:
                credit = 0.0
                break
            if sysw & SYS_VEC and (r[0x8C] != 0xFF or r[0x8D] != 0xFF):
                memo = self._vector_memo
                if (
                    memo is None
                    or memo[0] != r[0x8C] | r[0x8D] << 8
                    or len(memo[1]) != 1
                    or r[memo[1][0][0] : memo[1][0][1]] != memo[2]
                ):
                    self._vector_jump()
            if r[7] or r[8] or r[9] or r[10] or r[11]:
                credit = 0.0
                break
            # one instruction (_step, inlined)
            pc = r[2] | r[3] << 8 | r[4] << 16
            entry = cache.get(pc)
            if entry is None:
                entry = self._fetch(pc)
                cache[pc] = entry
            fn = entry[3]
            if fn is None:
                romerr = entry[2] == _ROMERR
                self._stop(romerr, "checksum error" if romerr else "bad instruction")
            else:
                self.instructions_executed += 1
                nxt = (pc + entry[1]) % ROM_SIZE
                r[2] = nxt & 0xFF
                r[3] = (nxt >> 8) & 0xFF
                r[4] = nxt >> 16
                try:
                    fn(nxt)
                except _CommandError as exc:
                    self._set_pc(pc)
                    self._stop(False, str(exc))
                except _Reset:
                    self.power_on()
            credit -= 1
            target = r[2] | r[3] << 8 | r[4] << 16
            if target < pc and credit >= 1:
                # A backward branch closed an iteration. Nothing but the program changes RAM
                # within this call, so once a whole iteration of a flags-only polling loop has
                # run here, every further iteration until `until` is identical: count them.
                loop = (target, pc)
                if seen_loop == loop:
                    length = self._polling_loop_length(target, pc)
                    if length:
                        n = int(credit // length)
                        credit -= n * length
                        self.instructions_executed += n * length
                seen_loop = loop
        self._credit = credit

    def _polling_loop_length(self, start: int, jump_pc: int) -> int:
        """Instructions in the loop ``start``..``jump_pc`` if it only reads memory and sets
        flags (no-write-back data ops, Not/Shift without write-back, conditional JUMPs),
        else 0. Memoised; the instruction cache is invalidated with ROM writes, and so is this."""
        key = (start, jump_pc)
        known = self._loop_memo.get(key)
        if known is not None:
            return known
        count, pc = 0, start
        while pc <= jump_pc and count < 64:
            entry = self._cache.get(pc)
            if entry is None or entry[0] is None:
                count = 0
                break
            cmd = entry[0]
            pure = isinstance(cmd, Jump) or (
                getattr(cmd, "no_write", False) and not isinstance(getattr(cmd, "dst", None), Com)
            )
            if not pure:
                count = 0
                break
            count += 1
            if pc == jump_pc:
                break
            pc += entry[1]
        if pc != jump_pc:
            count = 0
        self._loop_memo[key] = count
        return count

    def _fetch(self, pc: int) -> Entry:
        # Erased ROM (SIZE FF), a bad SIZE, a frame past the end, a bad checksum, and a PC past
        # the 256 KB ROM (a host can write any 24-bit value to RAM 0002h) are fetch errors:
        # ROMERR, the program stops.
        try:
            frame = frame_at(self.rom, pc)
        except ProtocolError:
            return (None, 0, _ROMERR, None)
        try:
            cmd = decode_command(frame)
        except ProtocolError:
            return (None, len(frame), _CMDERR, None)
        return (cmd, len(frame), _OK, self._compile(cmd))

    def _compile(self, cmd: Command) -> Executor:
        """An executor of ``cmd`` from ROM (its reply is not needed): a closure specialised
        on the operands for the common pure-RAM forms, else :meth:`_execute` itself. Only
        forms that cannot fail are specialised, so results and errors are identical."""
        t = type(cmd)
        if t is Jump:
            assert isinstance(cmd, Jump)
            return self._compile_jump(cmd)
        if t is Move:
            assert isinstance(cmd, Move)
            fast = self._compile_move(cmd)
            if fast is not None:
                return fast
        elif t in _FAST_BINARY:
            assert isinstance(cmd, (And, Or, Xor, Add, Sub, Mul))
            fast = self._compile_binary(cmd)
            if fast is not None:
                return fast

        def generic(nxt: int) -> object:
            return self._execute(cmd, nxt)

        return generic

    def _compile_jump(self, cmd: Jump) -> Executor:
        cond = cmd.condition
        taken = tuple(self._holds_zc(cond, bool(hi & Z_BIT), bool(hi & C_BIT)) for hi in range(4))
        target = cmd.address % ROM_SIZE
        lo, mid, top = target & 0xFF, (target >> 8) & 0xFF, (target >> 16) & 0xFF
        ram = self.ram

        def jump(nxt: int) -> object:
            if taken[ram[1] & 3]:
                ram[2] = lo
                ram[3] = mid
                ram[4] = top
            return None

        return jump

    def _compile_move(self, cmd: Move) -> Executor | None:
        dst, src = cmd.dst, cmd.src
        if type(dst) is not Ram:
            return None
        a = dst.address
        ram = self.ram
        if type(src) is Data:
            data = src.data
            n = len(data)
            if a + n > RAM_SIZE:
                return None

            def move_data(nxt: int) -> object:
                ram[a : a + n] = data
                if a + n > self._dirty_lo and a < self._dirty_hi:
                    self._dirty = True
                return None

            return move_data
        if type(src) is Ram:
            b = src.address
            n = cmd.nbytes
            if a + n > RAM_SIZE or b + n > RAM_SIZE:
                return None

            def move_ram(nxt: int) -> object:
                ram[a : a + n] = ram[b : b + n]
                if a + n > self._dirty_lo and a < self._dirty_hi:
                    self._dirty = True
                return None

            return move_ram
        return None

    def _compile_binary(self, cmd: And | Or | Xor | Add | Sub | Mul) -> Executor | None:
        dst, src = cmd.dst, cmd.src
        size = cmd.nbytes
        if type(dst) is not Ram or dst.address + size > RAM_SIZE:
            return None
        a = dst.address
        const: int | None = None
        b = 0
        if type(src) is Data:
            const = int.from_bytes(src.data, "little")
        elif type(src) is Ram and src.address + size <= RAM_SIZE:
            b = src.address
        else:
            return None
        mask = (1 << (8 * size)) - 1
        op = _FAST_BINARY[type(cmd)]
        write = not cmd.no_write
        logic_clear = self.config.logic_carry == "clear"
        ram = self.ram

        def binary(nxt: int) -> object:
            dv = int.from_bytes(ram[a : a + size], "little")
            sv = const if const is not None else int.from_bytes(ram[b : b + size], "little")
            c: bool | None
            if op == 0:
                res, c = dv & sv, None
            elif op == 1:
                res, c = dv | sv, None
            elif op == 2:
                res, c = dv ^ sv, None
            elif op == 3:
                full = dv + sv
                res, c = full & mask, full > mask
            elif op == 4:
                res, c = (dv - sv) & mask, dv >= sv
            else:
                full = dv * sv
                res, c = full & mask, full > mask
            if write:
                ram[a : a + size] = res.to_bytes(size, "little")
                if a + size > self._dirty_lo and a < self._dirty_hi:
                    self._dirty = True
            hi = ram[1]
            hi = (hi & ~Z_BIT) if res else (hi | Z_BIT)
            if c is None:
                if logic_clear:
                    hi &= ~C_BIT
            else:
                hi = (hi | C_BIT) if c else (hi & ~C_BIT)
            ram[1] = hi
            return None

        return binary

    def _stop(self, rom_error: bool, why: str) -> None:
        self.ram[0] &= ~SYS_ROM
        if rom_error:
            self.ram[1] |= ROMERR_BIT
        log.debug("ROM program stopped at %05X: %s", self.pc, why)

    def _vec_operand(self, word: int, size: int) -> int:
        if word & 0x8000:
            a = self._ram_address(Ics(word & 0xFF, ((word >> 8) & 0x7F) % 36), size)
        else:
            a = word
            if a + size > RAM_SIZE:
                raise _CommandError("vector operand out of range")
        return int.from_bytes(self.ram[a : a + size], "little")

    def _vector_snapshot(self, table: int) -> tuple[int, tuple[tuple[int, int], ...], bytes] | None:
        """The RAM bytes a no-match evaluation of ``table`` depended on, or None when an
        operand is indirect (ICS) and so depends on more than its own bytes."""
        r = self.ram
        spans = []
        for i in range(32):
            a = table + 8 * i
            if a + 8 > RAM_SIZE:
                break
            c = r[a]
            size = 2 if c & 0x20 else 1
            spans.append((a, a + 8))
            for word, literal in ((self._w(a + 1), False), (self._w(a + 3), bool(c & 0x10))):
                if literal:
                    continue
                if word & 0x8000 or word + size > RAM_SIZE:
                    return None
                spans.append((word, word + size))
            if c & 0x80:
                break
        merged: list[tuple[int, int]] = []
        for x, y in sorted(spans):
            # bytes between two spans may join the snapshot: a change there only costs a
            # re-evaluation, and one slice compares faster than several
            if merged and x <= merged[-1][1] + 32:
                merged[-1] = (merged[-1][0], max(merged[-1][1], y))
            else:
                merged.append((x, y))
        key = tuple(merged)
        return table, key, b"".join(bytes(r[x:y]) for x, y in key)

    def _vector_unchanged(self, table: int) -> bool:
        """True when the last evaluation found no match and nothing it read has changed."""
        memo = self._vector_memo
        if memo is None or memo[0] != table:
            return False
        r = self.ram
        spans = memo[1]
        if len(spans) == 1:
            x, y = spans[0]
            return r[x:y] == memo[2]
        return b"".join(bytes(r[x:y]) for x, y in spans) == memo[2]

    def _vector_jump(self) -> None:
        """Evaluate the vector-jump table (spec 11.3); the first matching package wins.

        A no-match result is memoised on the exact RAM bytes it read (the packages and their
        direct operands), so an idle main loop does not re-evaluate an unchanged table before
        every instruction; any change to those bytes re-evaluates. Results are identical.
        """
        table = self._w(0x008C)
        if self._vector_unchanged(table):
            return
        self._vector_memo = None
        r = self.ram
        for i in range(32):
            a = table + 8 * i
            if a + 8 > RAM_SIZE:
                return
            c = r[a]
            size = 2 if c & 0x20 else 1
            try:
                dv = self._vec_operand(self._w(a + 1), size)
                src = self._w(a + 3)
                sv = (
                    (src & (0xFFFF if size == 2 else 0xFF))
                    if c & 0x10
                    else (self._vec_operand(src, size))
                )
            except _CommandError:
                return
            diff = dv - sv
            z, cf = diff == 0, diff >= 0
            ok = not (c & 0x04 and z != bool(c & 0x01)) and not (c & 0x08 and cf != bool(c & 0x02))
            if ok:
                target = (r[a + 5] | r[a + 6] << 8 | r[a + 7] << 16) % ROM_SIZE
                r[0] &= ~SYS_VEC
                if not c & 0x40:
                    try:
                        self._push(self.pc)
                    except _CommandError as exc:
                        self._stop(False, str(exc))
                        return
                self._set_pc(target)
                log.debug("vector package %d fired: PC <- %05X", i, target)
                return
            if c & 0x80:
                break
        self._vector_memo = self._vector_snapshot(table)

    # ------------------------------------------------------------------ test / host hooks

    def load_rom(self, address: int, data: bytes) -> None:
        """Write ``data`` into ROM at ``address`` (as a MOVE to ROM would; persisted)."""
        if not 0 <= address <= ROM_SIZE - len(data):
            raise ValueError("ROM write out of range")
        self._write(Rom(address), bytes(data)) if data else None

    def set_buttons(self, buttons: int) -> None:
        """Set the remote button word (RAM 0350h, high byte first)."""
        if not 0 <= int(buttons) <= 0xFFFF:
            raise ValueError("the button word is 16 bits")
        self.tick()
        self.ram[0x0350:0x0352] = int(buttons).to_bytes(2, "big")
        self._touch(0x0350, 2)

    def set_pa(self, n: int, value: int) -> None:
        """Set analog pad value PA1-PA4 (one byte each at 0352h-0355h)."""
        if not 1 <= n <= 4 or not 0 <= value <= 0xFF:
            raise ValueError("PA1-PA4 take 0..255")
        self.tick()
        self.ram[0x0351 + n] = value
        self._touch(0x0351 + n, 1)

    def set_ad(self, channel: int, value: int) -> None:
        """Set the measured value of AD0-AD10."""
        if not 0 <= channel <= 10 or not 0 <= value <= 1023:
            raise ValueError("AD channels 0-10 take 0..1023")
        self.tick()
        self._set_w(0x0022 + 2 * channel, value)
        self._touch(0x0022 + 2 * channel, 2)

    def set_servo_position(self, ics: int, position: int) -> None:
        """Move a virtual servo by hand (as if pushed while free)."""
        if ics not in self._physical or not 0 <= position <= 0xFFFF:
            raise ValueError(f"ICS {ics} has no virtual servo, or position out of range")
        self.tick()
        self._physical[ics] = position

    def add_output_listener(self, callback: OutputListener) -> None:
        """Call ``callback(board_time_s, {ics: sent value})`` after every output period."""
        self._listeners.append(callback)

    def remove_output_listener(self, callback: OutputListener) -> None:
        self._listeners.remove(callback)

    def _sent(self, blk: int) -> int:
        out = self._w(blk + 6)
        if out in (FREE, HOLD) and self.config.free_hold_base == "omit":
            return out
        return (out + _s16(self._w(blk + 2)) + self._mix(blk)) & 0xFFFF

    def servo_outputs(self) -> dict[int, int]:
        """The value sent to each allocated servo: output + base + mixing (spec 9)."""
        out = {}
        for ics in range(36):
            blk = self._block(ics)
            if blk is not None:
                out[ics] = self._sent(blk)
        return out

    def servo_state(self, ics: int) -> ServoState | None:
        blk = self._block(ics)
        if blk is None:
            return None
        out = self._w(blk + 6)
        return ServoState(
            ics=ics,
            output=out,
            sent=self._sent(blk),
            position=self._physical.get(ics, out),
            torque=self._torque.get(ics, False),
            moving=bool(self.ram[blk + 8]),
        )
