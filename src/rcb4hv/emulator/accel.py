"""The accelerator layer: speed work that must give exactly what the plain model gives.

* :func:`compile_command`: closures specialised on their operands for the common pure-RAM
  ROM instructions (JUMP, MOVE, and AND..MUL), computing through the same ALU table and
  condition evaluator as :meth:`Interpreter.execute`. Only forms that cannot fail are
  compiled, so results and errors are identical.
* :func:`flags_only_loop`: a flags-only polling loop is counted, not stepped.
* :func:`skip_periods`: output periods nobody can observe are applied in closed form.

(The vector-table memo lives in :mod:`rcb4hv.emulator.vectors`, the servo block cache in
:mod:`rcb4hv.emulator.servos`.) A board built with ``accelerate=False`` uses none of this;
``tests/emulator/test_emu_differential.py`` runs random programs on both and compares.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Final, Protocol

from rcb4hv.emulator.alu import ALU, C_BIT, OP_OF, Z_BIT, AluOp, condition_table
from rcb4hv.emulator.config import EmulatorConfig
from rcb4hv.emulator.memmap import (
    AD_REFERENCE,
    AD_REFERENCE_END,
    B_END,
    B_END_HI,
    B_OUTPUT,
    B_OUTPUT_HI,
    B_REMAINING,
    B_SPEED,
    B_WIDTH,
    PC,
    RAM_SIZE,
    ROM_SIZE,
    SYS_ROM,
    SYS_VEC,
    U16,
)
from rcb4hv.emulator.servos import Servos, ramp, set_update_flags, update_flags
from rcb4hv.emulator.vectors import Vectors
from rcb4hv.protocol import (
    Add,
    And,
    Com,
    Command,
    Data,
    Div,
    Jump,
    Mod,
    Move,
    Mul,
    Not,
    Or,
    Ram,
    Shift,
    Sub,
    Xor,
)

__all__ = [
    "DataCommand",
    "Entry",
    "Executor",
    "Machine",
    "compile_command",
    "flags_only_loop",
    "skip_periods",
]

Executor = Callable[[int], object]
Entry = tuple[Command | None, int, int, Executor | None, str]
"""An instruction cache entry: (command or None, size, kind, executor or None, error text)."""


class Machine(Protocol):
    """What the accelerator may touch of the interpreter it compiles for (the interpreter is
    one): RAM, the configuration, the servo unit's dirty window, the instruction cache and
    the polling-loop memo."""

    @property
    def ram(self) -> bytearray: ...

    @property
    def config(self) -> EmulatorConfig: ...

    @property
    def servos(self) -> Servos: ...

    @property
    def cache(self) -> Mapping[int, Entry]: ...

    @property
    def loop_memo(self) -> dict[tuple[int, int], bool]: ...


_u16 = U16.unpack_from
DataCommand = And | Or | Xor | Add | Sub | Mul | Div | Mod | Not | Shift

# the binary operations compiled to a closure: they cannot fail on in-range RAM operands
_COMPILED_OPS: Final = frozenset((AluOp.AND, AluOp.OR, AluOp.XOR, AluOp.ADD, AluOp.SUB, AluOp.MUL))


def compile_command(cmd: Command, interp: Machine) -> Executor | None:
    """A closure running ROM instruction ``cmd``, or None (run it through ``execute``)."""
    t = type(cmd)
    if t is Jump:
        assert isinstance(cmd, Jump)
        return _compile_jump(cmd, interp)
    if t is Move:
        assert isinstance(cmd, Move)
        return _compile_move(cmd, interp)
    op = OP_OF.get(t)
    if op in _COMPILED_OPS:
        assert isinstance(cmd, (And, Or, Xor, Add, Sub, Mul)) and op is not None
        return _compile_binary(cmd, op, interp)
    return None


def _compile_jump(cmd: Jump, interp: Machine) -> Executor:
    taken = condition_table(cmd.condition.to_byte(), interp.config.branch_condition == "or")
    target = cmd.address % ROM_SIZE
    lo, mid, top = target & 0xFF, (target >> 8) & 0xFF, (target >> 16) & 0xFF
    ram = interp.ram
    pc0, pc1, pc2 = PC, PC + 1, PC + 2

    def jump(nxt: int) -> object:
        if taken[ram[1] & 3]:
            ram[pc0] = lo
            ram[pc1] = mid
            ram[pc2] = top
        return None

    return jump


def _writes_ad_reference(a: int, n: int) -> bool:
    """A write to an AD reference makes the board sample its inputs (spec 10.4): such a
    command runs through ``execute`` (:meth:`Interpreter.write` tells the board)."""
    return a < AD_REFERENCE_END and a + n > AD_REFERENCE


def _compile_move(cmd: Move, interp: Machine) -> Executor | None:
    dst, src = cmd.dst, cmd.src
    if type(dst) is not Ram or _writes_ad_reference(dst.address, cmd.nbytes):
        return None
    a = dst.address
    ram = interp.ram
    servos = interp.servos
    if type(src) is Data:
        data = src.data
        n = len(data)
        if a + n > RAM_SIZE:
            return None

        def move_data(nxt: int) -> object:
            ram[a : a + n] = data
            if a + n > servos.dirty_lo and a < servos.dirty_hi:
                servos.dirty = True
            return None

        return move_data
    if type(src) is Ram:
        b = src.address
        n = cmd.nbytes
        if a + n > RAM_SIZE or b + n > RAM_SIZE:
            return None

        def move_ram(nxt: int) -> object:
            ram[a : a + n] = ram[b : b + n]
            if a + n > servos.dirty_lo and a < servos.dirty_hi:
                servos.dirty = True
            return None

        return move_ram
    return None


def _compile_binary(
    cmd: And | Or | Xor | Add | Sub | Mul, op: AluOp, interp: Machine
) -> Executor | None:
    dst, src = cmd.dst, cmd.src
    size = cmd.nbytes
    if type(dst) is not Ram or dst.address + size > RAM_SIZE:
        return None
    if not cmd.no_write and _writes_ad_reference(dst.address, size):
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
    fn = ALU[op]
    write = not cmd.no_write
    logic_clear = interp.config.logic_carry == "clear"
    ram = interp.ram
    servos = interp.servos
    end = a + size

    def binary(nxt: int) -> object:
        dv = int.from_bytes(ram[a:end], "little")
        sv = const if const is not None else int.from_bytes(ram[b : b + size], "little")
        res, c = fn(dv, sv, mask)
        if write:
            ram[a:end] = res.to_bytes(size, "little")
            if end > servos.dirty_lo and a < servos.dirty_hi:
                servos.dirty = True
        # the flags exactly as alu.set_flags sets them, inlined
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


def _reads_flags(cmd: object) -> bool:
    """Whether an operand of ``cmd`` covers the system register (RAM 0000h-0001h), where the
    Z and C flags live: an op that reads them sets them from what the iteration before set
    (OR of the register's high byte with 0 flips Z every pass), so its iterations differ."""
    return any(
        isinstance(op, Ram) and op.address < 2
        for op in (getattr(cmd, "dst", None), getattr(cmd, "src", None))
    )


def flags_only_loop(interp: Machine, start: int, jump_pc: int) -> bool:
    """The loop ``start``..``jump_pc`` only reads memory and sets flags (no-write-back data
    ops, Not/Shift without write-back, conditional JUMPs; at most 64 instructions), so every
    iteration is the one before. The caller counts an iteration as long as one ran (a
    conditional JUMP inside may skip part of the body). Memoised; the instruction cache is
    invalidated with ROM writes, and so is this."""
    key = (start, jump_pc)
    known = interp.loop_memo.get(key)
    if known is not None:
        return known
    count, pc, pure = 0, start, True
    while pc <= jump_pc and count < 64:
        entry = interp.cache.get(pc)
        if entry is None:
            pure = False
            break
        cmd = entry[0]
        pure = isinstance(cmd, Jump) or (
            getattr(cmd, "no_write", False)
            and not isinstance(getattr(cmd, "dst", None), Com)
            and not _reads_flags(cmd)
        )
        if not pure or pc == jump_pc:
            break
        count += 1
        pc += entry[1]
    found = pure and pc == jump_pc
    interp.loop_memo[key] = found
    return found


def skip_periods(
    servos: Servos, vectors: Vectors, np: int, horizon: int, period_us: int, min_span: int
) -> int:
    """Apply in closed form the periods that nobody can observe; return the next to run.

    Allowed only while the ROM program cannot run before ``horizon`` (stopped, or waiting
    on update flags with no time-dependent vector jump), with no mixing on a reporting servo
    and a safe servo layout (the caller checks that no output listener is attached). The
    last period before ``horizon`` (or the one that clears the last update flag) is left to
    :meth:`Servos.period`, so RAM ends exactly as if every period had been stepped.
    """
    if horizon - np < min_span:
        return np
    r = servos.ram
    sysw = r[0]
    if sysw & SYS_ROM:
        flags = update_flags(r)
        if not flags:
            return np
        if sysw & SYS_VEC and not vectors.static():
            return np
    else:
        flags = 0
    if servos.dirty:
        servos.rescan()
    if not servos.safe or servos.vs_mixing:
        return np
    blocks = servos.blocks
    n = (horizon - np) // period_us + 1
    info: list[tuple[int, int]] = []
    for ics in servos.active:
        blk = blocks[ics]
        if blk is None:
            return np
        info.append((ics, blk))
    unblock = servos.flag_wait(flags) if flags else None
    k = n if unblock is None else min(n, unblock)
    skip = k - 1
    if skip <= 0:
        return np
    cleared = 0
    for ics, blk in info:
        rem = r[blk + B_REMAINING]
        if skip > rem:
            r[blk + B_SPEED] = 0
            r[blk + B_OUTPUT] = r[blk + B_END]
            r[blk + B_OUTPUT_HI] = r[blk + B_END_HI]
            r[blk + B_REMAINING] = 0
            cleared |= 1 << ics
            servos.active.discard(ics)
        else:
            rem -= skip
            r[blk + B_REMAINING] = rem
            out = ramp(_u16(r, blk + B_END)[0], _u16(r, blk + B_WIDTH)[0], rem, r[blk + B_SPEED])
            r[blk + B_OUTPUT] = out & 0xFF
            r[blk + B_OUTPUT_HI] = out >> 8
    if cleared:
        set_update_flags(r, update_flags(r) & ~cleared)
    servos.periods += skip
    return np + skip * period_us
