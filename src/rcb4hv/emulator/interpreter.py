"""The interpreter: one execution of every command, from COM (host) or ROM (the program).

Every data operation computes through :func:`~rcb4hv.emulator.alu.alu` and every JUMP/CALL
condition through :func:`~rcb4hv.emulator.alu.condition_table`. ROM instructions are decoded
by the protocol core (once per PC, cached until the ROM is written) and run at
``instructions_per_ms`` per millisecond of board time.

With ``accelerate=True`` the common pure-RAM instructions run as closures compiled by
:mod:`rcb4hv.emulator.accel` and idle polling loops are counted instead of stepped; both give
exactly what the plain path (``accelerate=False``) gives, which
``tests/emulator/test_emu_differential.py`` checks on random programs.
"""

from __future__ import annotations

import copy
import logging
from collections.abc import Callable
from typing import Any, Final

from rcb4hv.emulator import accel
from rcb4hv.emulator.alu import OP_OF, AluOp, alu, condition_table, set_flags
from rcb4hv.emulator.config import EmulatorConfig
from rcb4hv.emulator.events import Stop, StopKind, stop_kind
from rcb4hv.emulator.memmap import (
    AD_REFERENCE,
    AD_REFERENCE_END,
    ALLOC,
    CALL_DEPTH,
    NO_BLOCK,
    PC,
    RAM_SIZE,
    ROM_SIZE,
    ROMERR_BIT,
    SYS_ROM,
    SYS_VEC,
    SYSTEM,
    SYSTEM_HI,
    U24,
    UPDATE_FLAGS,
    UPDATE_FLAGS_END,
    VECTOR_TABLE,
    read_u16,
)
from rcb4hv.emulator.servos import Servos
from rcb4hv.emulator.vectors import Vectors
from rcb4hv.errors import EmulatedCommandError, EmulatedReset, ProtocolError
from rcb4hv.protocol import (
    Ack,
    AcknowledgeCheck,
    Call,
    Com,
    Command,
    CommunicateDevice,
    Data,
    DataReply,
    GetVersionInfo,
    Ics,
    Jump,
    Move,
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
    VersionReply,
    decode_command,
    encode_command,
    frame_at,
)
from rcb4hv.protocol.describe import describe_command
from rcb4hv.protocol.registry import COMMANDS

__all__ = ["STACK_DEPTH", "Interpreter"]

log = logging.getLogger(__name__)

STACK_DEPTH: Final = 16
_F0, _F1, _F2, _F3, _F4 = range(UPDATE_FLAGS, UPDATE_FLAGS_END)
_get_pc = U24.unpack_from
_put_pc = U24.pack_into
_VT0, _VT1 = VECTOR_TABLE, VECTOR_TABLE + 1
_RETURN_SIZE: Final = len(encode_command(Return()))

# instruction cache entries (accel.Entry): (command or None, size, kind, executor, error text)
OK: Final = 0
ROMERR: Final = 1
CMDERR: Final = 2
Entry = accel.Entry
Handler = Callable[[Any, int | None], Reply | None]
"""Runs one command (``next_pc`` None: from COM); the interpreter's dispatch is keyed by class."""
ServoCommand = RunSingleServo | RunConstFrameServo | RunSeriesServo
Operand = Ram | Ics | Rom | Data | Com


class Interpreter:
    """Executes commands over the board's RAM and ROM; runs the ROM program in board time."""

    def __init__(
        self,
        ram: bytearray,
        rom: bytearray,
        config: EmulatorConfig,
        servos: Servos,
        vectors: Vectors,
        *,
        on_rom_write: Callable[[], None],
        on_reset: Callable[[], None],
        on_ad_reference: Callable[[], None] = lambda: None,
        accelerate: bool = True,
    ) -> None:
        self.ram = ram
        self.rom = rom
        self.config = config
        self.servos = servos
        self.vectors = vectors
        self.accelerate = accelerate
        self._on_rom_write = on_rom_write
        self._on_reset = on_reset
        self._on_ad_reference = on_ad_reference  # an AD reference was written (spec 10.4)
        # 0Eh: (ICS number, bytes sent) -> the device's answer or None (set by the board)
        self.ics_comm: Callable[[int, bytes], bytes | None] | None = None
        self._any = config.branch_condition == "or"
        self._logic_clear = config.logic_carry == "clear"
        self.cache: dict[int, Entry] = {}
        self.loop_memo: dict[tuple[int, int], bool] = {}
        self.dispatch = self._dispatch_table()
        self.instructions_executed = 0
        self.reset(0)

    def __deepcopy__(self, memo: dict[int, Any]) -> Interpreter:
        """An interpreter in the same state over copied memory. The decoded instructions
        are left behind: their executors are closures over this interpreter and its RAM, so
        the copy decodes again as it runs (the same commands, the same results)."""
        new = object.__new__(type(self))
        memo[id(self)] = new
        for name, value in self.__dict__.items():
            if name not in ("cache", "dispatch"):
                setattr(new, name, copy.deepcopy(value, memo))
        new.cache = {}
        new.dispatch = new._dispatch_table()
        return new

    def reset(self, t_us: int) -> None:
        """Power-on: empty call stack, program time ``t_us``, no stop recorded."""
        self.stack = [0] * STACK_DEPTH
        self._host_frames = 0  # bit d: stack entry d was pushed by a host (COM) CALL
        self.prog_t = t_us
        self.credit = 0.0
        self.last_stop: Stop | None = None

    # ------------------------------------------------------------------ registers

    @property
    def pc(self) -> int:
        lo, hi = _get_pc(self.ram, PC)
        return int(lo | hi << 16)

    def set_pc(self, v: int) -> None:
        _put_pc(self.ram, PC, v & 0xFFFF, v >> 16)

    def holds(self, cond: int) -> bool:
        """Whether a JUMP/CALL condition nibble holds on the current Z/C flags."""
        return condition_table(cond, self._any)[self.ram[SYSTEM_HI] & 3]

    def push(self, addr: int, host: bool = False) -> None:
        d = self.ram[CALL_DEPTH]
        if d >= STACK_DEPTH:
            raise EmulatedCommandError("call stack overflow (17th nested CALL)", "stack-overflow")
        self.stack[d] = addr
        self._host_frames = (self._host_frames | 1 << d) if host else self._host_frames & ~(1 << d)
        self.ram[CALL_DEPTH] = d + 1

    def pop(self) -> tuple[int, bool]:
        """(return address, True if a host CALL pushed it)."""
        d = self.ram[CALL_DEPTH]
        if d == 0 or d > STACK_DEPTH:
            raise EmulatedCommandError("RETURN with an empty call stack", "stack-underflow")
        self.ram[CALL_DEPTH] = d - 1
        host = bool(self._host_frames >> (d - 1) & 1)
        self._host_frames &= ~(1 << (d - 1))
        return self.stack[d - 1], host

    # ------------------------------------------------------------------ operands

    def ram_address(self, op: Ram | Ics, size: int) -> int:
        if isinstance(op, Ram):
            a = op.address
        else:
            base = read_u16(self.ram, ALLOC + 2 * op.ics)
            if base == NO_BLOCK:
                raise EmulatedCommandError(f"ICS {op.ics} is not allocated")
            a = base + op.offset
        if a + size > RAM_SIZE:
            raise EmulatedCommandError(f"RAM {a:04X}h + {size} runs past the end")
        return a

    def read(self, op: Operand, size: int) -> bytes:
        if isinstance(op, Data):
            return op.data
        if isinstance(op, Rom):
            if op.address + size > ROM_SIZE:
                raise EmulatedCommandError("ROM read past the end")
            return bytes(self.rom[op.address : op.address + size])
        if isinstance(op, Com):
            return bytes(size)
        a = self.ram_address(op, size)
        return bytes(self.ram[a : a + size])

    def write(self, op: Ram | Ics | Rom | Com, data: bytes) -> None:
        n = len(data)
        if isinstance(op, Com):
            return
        if isinstance(op, Rom):
            if op.address + n > ROM_SIZE:
                raise EmulatedCommandError("ROM write past the end")
            self.rom[op.address : op.address + n] = data
            self.cache.clear()
            self.loop_memo.clear()
            self._on_rom_write()
            return
        a = self.ram_address(op, n)
        self.ram[a : a + n] = data
        self.servos.wrote(a, n)
        if a < AD_REFERENCE_END and a + n > AD_REFERENCE:
            self._on_ad_reference()

    # ------------------------------------------------------------------ execution

    def execute(self, cmd: Command, next_pc: int | None) -> Reply | None:
        """Run one command; ``next_pc`` is None from COM, else the address after it in ROM."""
        return self.dispatch[type(cmd)](cmd, next_pc)

    def _dispatch_table(self) -> dict[type, Handler]:
        """Class -> handler, one per row of the protocol's command table: the ALU commands
        (by command byte) run :meth:`_exec_alu`, the others their handler below (a row of
        the table without one is a KeyError when the board is built)."""
        handlers: dict[type, Handler] = {
            Move: self._exec_move,
            Jump: self._exec_jump,
            Call: self._exec_call,
            Return: self._exec_return,
            CommunicateDevice: self._exec_icscomm,
            RunSingleServo: self._exec_servo,
            RunConstFrameServo: self._exec_servo,
            RunSeriesServo: self._exec_servo,
            SetSpeed: self._exec_stretch,
            SetStretch: self._exec_stretch,
            GetVersionInfo: self._exec_version,
            AcknowledgeCheck: self._exec_ackcheck,
        }
        return {
            spec.cls: self._exec_alu if spec.cls in OP_OF else handlers[spec.cls]
            for spec in COMMANDS
        }

    def _exec_move(self, cmd: Move, next_pc: int | None) -> Reply | None:
        data = self.read(cmd.src, cmd.nbytes)
        if isinstance(cmd.dst, Com):
            return DataReply(cmd.cmd, data)
        self.write(cmd.dst, data)
        return Ack(cmd.cmd)

    def _exec_alu(self, cmd: accel.DataCommand, next_pc: int | None) -> Reply | None:
        result = self.data_op(cmd, OP_OF[type(cmd)])
        if self.config.logic_reply == "ack":
            return Ack(cmd.cmd)
        return DataReply(cmd.cmd, result)

    def _exec_servo(self, cmd: ServoCommand, next_pc: int | None) -> Reply | None:
        self.servos.command(cmd)
        return Ack(cmd.cmd)

    _exec_servos = _exec_series = _exec_servo

    def _exec_stretch(self, cmd: SetSpeed | SetStretch, next_pc: int | None) -> Reply | None:
        s = self.servos
        values = s.stretch if isinstance(cmd, SetStretch) else s.speed_parameter
        for ics, v in cmd.values:
            values[ics] = v
        return Ack(cmd.cmd)

    _exec_speed = _exec_stretch

    def _exec_jump(self, cmd: Jump, next_pc: int | None) -> Reply | None:
        if self.holds(cmd.condition.to_byte()):
            self.set_pc(cmd.address % ROM_SIZE)
        return Ack(cmd.cmd)

    def _exec_call(self, cmd: Call, next_pc: int | None) -> Reply | None:
        if self.holds(cmd.condition.to_byte()):
            self.push(self.pc if next_pc is None else next_pc, host=next_pc is None)
            self.set_pc(cmd.address % ROM_SIZE)
        return Ack(cmd.cmd)

    def _exec_return(self, cmd: Return, next_pc: int | None) -> Reply | None:
        target, host = self.pop()
        self.set_pc(target)
        if host and next_pc is not None:
            at = (next_pc - _RETURN_SIZE) % ROM_SIZE
            self._record("return-to-host", at, f"returned to {target:05X}h for the host", cmd)
        return Ack(cmd.cmd)

    def _exec_version(self, cmd: GetVersionInfo, next_pc: int | None) -> Reply | None:
        return VersionReply(self.config.version_string) if next_pc is None else None

    def _exec_ackcheck(self, cmd: AcknowledgeCheck, next_pc: int | None) -> Reply | None:
        return Ack(cmd.cmd) if next_pc is None else None

    def _exec_icscomm(self, cmd: CommunicateDevice, next_pc: int | None) -> Reply | None:
        answer = None
        if self.ics_comm is not None:
            answer = self.ics_comm(cmd.ics, self.read(Ram(cmd.tx_address), cmd.tx_count))
        if not answer:
            raise EmulatedCommandError("ICS communication (0Eh): no device answers")
        self.write(Ram(cmd.rx_address), answer)  # EmulatedCommandError (NAK) if it runs past RAM
        return Ack(cmd.cmd)

    def data_op(self, cmd: accel.DataCommand, op: AluOp) -> bytes:
        """AND..SHIFT: compute through the ALU, write back unless NW, set Z and C."""
        size = cmd.nbytes
        dv = int.from_bytes(self.read(cmd.dst, size), "little")
        if isinstance(cmd, Shift):
            sv = -cmd.right_bits if self.config.shift_direction == "inverted" else cmd.right_bits
        elif op is AluOp.NOT:
            sv = 0
        else:
            sv = int.from_bytes(self.read(cmd.src, size), "little")  # type: ignore[union-attr]
            if not sv and op in (AluOp.DIV, AluOp.MOD) and self.config.division_by_zero == "error":
                raise EmulatedCommandError("division by zero")
        r, z, c = alu(op, dv, sv, size)
        result = r.to_bytes(size, "little")
        if not cmd.no_write:
            self.write(cmd.dst, result)
        self.ram[SYSTEM_HI] = set_flags(self.ram[SYSTEM_HI], z, c, self._logic_clear)
        return result

    # ------------------------------------------------------------------ stops

    def _record(self, what: StopKind, where: int, why: str, cmd: Command | None) -> None:
        text = None if cmd is None else describe_command(cmd)
        line = f"{why}: {text}" if text else why
        self.last_stop = Stop(what, where, line, text)
        log.debug("ROM program %s at %05X: %s", what, where, line)

    def stop(self, what: StopKind, why: str, cmd: Command | None = None) -> None:
        """Stop the program at the current PC (clear ROM_F; a fetch error sets ROMERR)."""
        self.ram[SYSTEM] &= ~SYS_ROM
        if what == "romerr":
            self.ram[SYSTEM_HI] |= ROMERR_BIT
        self._record(what, self.pc, why, cmd)

    def suspended(self, cmd: Command) -> None:
        """A host command cleared ROM_F."""
        self._record("suspended", self.pc, "the host cleared ROM_F", cmd)

    # ------------------------------------------------------------------ the ROM program

    def fetch(self, pc: int) -> Entry:
        # Erased ROM (SIZE FF), a bad SIZE, a frame past the end, a bad checksum, and a PC past
        # the 256 KB ROM (a host can write any 24-bit value to RAM 0002h) are fetch errors:
        # ROMERR, the program stops.
        try:
            frame = frame_at(self.rom, pc)
        except ProtocolError as exc:
            return (None, 0, ROMERR, None, f"no valid frame in ROM ({exc})")
        try:
            cmd = decode_command(frame)
        except ProtocolError as exc:
            return (None, len(frame), CMDERR, None, f"not a command: {frame.hex(' ')} ({exc})")
        fn = accel.compile_command(cmd, self) if self.accelerate else None
        if fn is None:
            handler = self.dispatch[type(cmd)]

            def generic(nxt: int) -> object:
                return handler(cmd, nxt)

            fn = generic
        return (cmd, len(frame), OK, fn, "")

    def vector_jump(self) -> None:
        """Evaluate the vector-jump table (spec 11.3) and take the first matching package."""
        hit = self.vectors.evaluate()
        if hit is None:
            return
        i, target, is_call = hit
        self.ram[SYSTEM] &= ~SYS_VEC
        if is_call:
            try:
                self.push(self.pc)
            except EmulatedCommandError as exc:
                self.stop(stop_kind(exc.what), f"vector package {i}: {exc}")
                return
        self.set_pc(target)
        log.debug("vector package %d fired: PC <- %05X", i, target)

    def runnable(self) -> bool:
        """True when the program would run now (not stopped, not waiting on update flags,
        or a vector table that may fire)."""
        r = self.ram
        if not r[SYSTEM] & SYS_ROM:
            return False
        return not any(r[UPDATE_FLAGS:UPDATE_FLAGS_END]) or bool(
            r[SYSTEM] & SYS_VEC and read_u16(r, VECTOR_TABLE) != NO_BLOCK
        )

    def run(self, until: int) -> None:
        """Run the program up to board time ``until`` (microseconds)."""
        if until <= self.prog_t:
            return
        credit = self.credit + (until - self.prog_t) * self.config.instructions_per_ms / 1000
        self.prog_t = until
        r = self.ram
        cache = self.cache
        vectors = self.vectors
        fast_loops = self.accelerate
        seen_loop: tuple[int, int] | None = None
        seen_at = 0  # instructions_executed when seen_loop last closed
        while credit >= 1:
            sysw = r[SYSTEM]
            if not sysw & SYS_ROM:
                credit = 0.0
                break
            if sysw & SYS_VEC and (r[_VT0] != 0xFF or r[_VT1] != 0xFF):
                memo = vectors.memo
                if (
                    memo is None
                    or memo[0] != r[_VT0] | r[_VT1] << 8
                    or len(memo[1]) != 1
                    or r[memo[1][0][0] : memo[1][0][1]] != memo[2]
                ):
                    self.vector_jump()
            if r[_F0] or r[_F1] or r[_F2] or r[_F3] or r[_F4]:
                credit = 0.0
                break
            # one instruction
            lo, hi = _get_pc(r, PC)
            pc = lo | hi << 16
            entry = cache.get(pc)
            if entry is None:
                entry = self.fetch(pc)
                cache[pc] = entry
            fn = entry[3]
            if fn is None:
                self.stop("romerr" if entry[2] == ROMERR else "command-error", entry[4])
            else:
                self.instructions_executed += 1
                nxt = (pc + entry[1]) % ROM_SIZE
                _put_pc(r, PC, nxt & 0xFFFF, nxt >> 16)
                try:
                    fn(nxt)
                except EmulatedCommandError as exc:
                    self.set_pc(pc)
                    self.stop(stop_kind(exc.what), str(exc), entry[0])
                except EmulatedReset:
                    self._on_reset()
            credit -= 1
            lo, hi = _get_pc(r, PC)
            target = lo | hi << 16
            if target < pc and credit >= 1 and fast_loops:
                # A backward branch closed an iteration. Nothing but the program changes RAM
                # within this call, so once a whole iteration of a flags-only polling loop has
                # run here, every further iteration until `until` is identical: count them.
                # An iteration is as long as it ran (a conditional JUMP inside the loop may
                # skip part of its body), not as the loop's instructions laid out.
                loop = (target, pc)
                length = self.instructions_executed - seen_at
                if seen_loop == loop and accel.flags_only_loop(self, target, pc):
                    n = int(credit // length)
                    credit -= n * length
                    self.instructions_executed += n * length
                seen_loop = loop
                seen_at = self.instructions_executed
        self.credit = credit
