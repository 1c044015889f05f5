"""Vector-jump packages (spec 11.3): the RAM table the firmware checks before each instruction.

A table (address in RAM 008Ch, FFFFh = none) holds up to 32 eight-byte packages; each
compares two operands with the ALU's SUB and, if the package's condition holds on the
resulting Z/C, jumps or calls to its ROM address. The first match wins; evaluation never
touches the system register's flags.

Speed work kept here (``accelerate=True``): a no-match result is memoised on the exact RAM
bytes it read (see :meth:`Vectors.snapshot`); :meth:`Vectors.static` tells the period
skipper whether any package reads RAM that changes by itself.
"""

from __future__ import annotations

from rcb4hv.emulator.alu import AluOp, alu, condition_table
from rcb4hv.emulator.memmap import (
    ALLOC,
    NO_BLOCK,
    RAM_SIZE,
    ROM_SIZE,
    STATIC_VECTOR_RAM,
    U16,
    VEC,
    VECTOR_PACKAGE,
    VECTOR_PACKAGE_COUNT,
    VECTOR_TABLE,
    operand_ics,
    read_u16,
)
from rcb4hv.protocol import ICS_COUNT

__all__ = ["Memo", "Vectors"]

_u16 = U16.unpack_from
# (table address, RAM spans read, their bytes)
Memo = tuple[int, tuple[tuple[int, int], ...], bytes]


class Vectors:
    """The vector-jump unit over the board's RAM."""

    def __init__(self, ram: bytearray, accelerate: bool = True) -> None:
        self.ram = ram
        self.accelerate = accelerate
        self.memo: Memo | None = None
        self._static_memo: tuple[int, bytearray, bool] | None = None

    def table(self) -> int:
        return read_u16(self.ram, VECTOR_TABLE)

    def operand_address(self, w: int, size: int) -> int | None:
        """RAM address of a package operand word (direct or ICS-relative), None if invalid."""
        ics = operand_ics(w)
        if ics is not None:
            base = read_u16(self.ram, ALLOC + 2 * (ics[0] % ICS_COUNT))
            if base == NO_BLOCK:
                return None
            a = base + ics[1]
        else:
            a = w
        return a if a + size <= RAM_SIZE else None

    def evaluate(self) -> tuple[int, int, bool] | None:
        """``(package, ROM target, is a CALL)`` of the first matching package, or None.

        An invalid operand ends the evaluation with no match (nothing memoised).
        """
        table = _u16(self.ram, VECTOR_TABLE)[0]
        if self.accelerate and self.unchanged(table):
            return None
        self.memo = None
        r = self.ram
        for i in range(VECTOR_PACKAGE_COUNT):
            a = table + VEC.SIZE * i
            if a + VEC.SIZE > RAM_SIZE:
                return None
            c, dst, src, lo, hi = VECTOR_PACKAGE.unpack_from(r, a)
            size = 2 if c & VEC.WORD else 1
            da = self.operand_address(dst, size)
            if da is None:
                return None
            dv = int.from_bytes(r[da : da + size], "little")
            if c & VEC.LITERAL:
                sv = src & (0xFFFF if size == 2 else 0xFF)
            else:
                sa = self.operand_address(src, size)
                if sa is None:
                    return None
                sv = int.from_bytes(r[sa : sa + size], "little")
            _, z, carry = alu(AluOp.SUB, dv, sv, size)
            if condition_table(c & VEC.CONDITION)[int(z) | int(bool(carry)) << 1]:
                return i, (lo | hi << 16) % ROM_SIZE, not c & VEC.JUMP
            if c & VEC.EOF:
                break
        if self.accelerate:
            self.memo = self.snapshot(table)
        return None

    # ------------------------------------------------------------------ speed work

    def unchanged(self, table: int) -> bool:
        """True when the last evaluation found no match and nothing it read has changed."""
        memo = self.memo
        if memo is None or memo[0] != table:
            return False
        r = self.ram
        spans = memo[1]
        if len(spans) == 1:
            x, y = spans[0]
            return r[x:y] == memo[2]
        return b"".join(bytes(r[x:y]) for x, y in spans) == memo[2]

    def snapshot(self, table: int) -> Memo | None:
        """The RAM bytes a no-match evaluation of ``table`` depended on, or None when an
        operand is indirect (ICS) and so depends on more than its own bytes."""
        r = self.ram
        spans = []
        for i in range(VECTOR_PACKAGE_COUNT):
            a = table + VEC.SIZE * i
            if a + VEC.SIZE > RAM_SIZE:
                break
            c, dst, src, _, _ = VECTOR_PACKAGE.unpack_from(r, a)
            size = 2 if c & VEC.WORD else 1
            spans.append((a, a + VEC.SIZE))
            for w in (dst,) if c & VEC.LITERAL else (dst, src):
                if operand_ics(w) is not None or w + size > RAM_SIZE:
                    return None
                spans.append((w, w + size))
            if c & VEC.EOF:
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

    def static(self) -> bool:
        """True when no package reads RAM that changes by itself (memoised on the table's
        bytes: the answer depends on nothing else)."""
        table = self.table()
        if table == NO_BLOCK:
            return True
        if table < STATIC_VECTOR_RAM:
            return False
        span = VEC.SIZE * VECTOR_PACKAGE_COUNT
        snap = self.ram[table : table + span]
        memo = self._static_memo
        if memo is not None and memo[0] == table and memo[1] == snap:
            return memo[2]
        result = self._static_scan(table)
        self._static_memo = (table, snap, result)
        return result

    def _static_scan(self, table: int) -> bool:
        r = self.ram
        for i in range(VECTOR_PACKAGE_COUNT):
            a = table + VEC.SIZE * i
            if a + VEC.SIZE > RAM_SIZE:
                return True
            c, dst, src, _, _ = VECTOR_PACKAGE.unpack_from(r, a)
            for w in (dst,) if c & VEC.LITERAL else (dst, src):
                if operand_ics(w) is not None or w < STATIC_VECTOR_RAM or w + 2 > RAM_SIZE:
                    return False
            if c & VEC.EOF:
                return True
        return True
