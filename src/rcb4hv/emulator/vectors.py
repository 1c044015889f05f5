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
    RAM_SIZE,
    ROM_SIZE,
    STATIC_VECTOR_RAM,
    V_COND,
    V_DST,
    V_ICS_OPERAND,
    V_JUMP,
    V_LAST,
    V_LITERAL,
    V_SRC,
    V_TARGET,
    V_WORD,
    VECTOR_PACKAGE_SIZE,
    VECTOR_PACKAGES,
    VECTOR_TABLE,
    word,
)
from rcb4hv.protocol import ICS_COUNT

__all__ = ["Memo", "Vectors"]

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
        return word(self.ram, VECTOR_TABLE)

    def operand_address(self, w: int, size: int) -> int | None:
        """RAM address of a package operand word (direct or ICS-relative), None if invalid."""
        if w & V_ICS_OPERAND:
            base = word(self.ram, ALLOC + 2 * (((w >> 8) & 0x7F) % ICS_COUNT))
            if base == 0xFFFF:
                return None
            a = base + (w & 0xFF)
        else:
            a = w
        return a if a + size <= RAM_SIZE else None

    def evaluate(self) -> tuple[int, int, bool] | None:
        """``(package, ROM target, is a CALL)`` of the first matching package, or None.

        An invalid operand ends the evaluation with no match (nothing memoised).
        """
        table = self.table()
        if self.accelerate and self.unchanged(table):
            return None
        self.memo = None
        r = self.ram
        for i in range(VECTOR_PACKAGES):
            a = table + VECTOR_PACKAGE_SIZE * i
            if a + VECTOR_PACKAGE_SIZE > RAM_SIZE:
                return None
            c = r[a]
            size = 2 if c & V_WORD else 1
            da = self.operand_address(word(r, a + V_DST), size)
            if da is None:
                return None
            dv = int.from_bytes(r[da : da + size], "little")
            src = word(r, a + V_SRC)
            if c & V_LITERAL:
                sv = src & (0xFFFF if size == 2 else 0xFF)
            else:
                sa = self.operand_address(src, size)
                if sa is None:
                    return None
                sv = int.from_bytes(r[sa : sa + size], "little")
            _, z, carry = alu(AluOp.SUB, dv, sv, size)
            if condition_table(c & V_COND)[int(z) | int(bool(carry)) << 1]:
                t = a + V_TARGET
                target = (r[t] | r[t + 1] << 8 | r[t + 2] << 16) % ROM_SIZE
                return i, target, not c & V_JUMP
            if c & V_LAST:
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
        for i in range(VECTOR_PACKAGES):
            a = table + VECTOR_PACKAGE_SIZE * i
            if a + VECTOR_PACKAGE_SIZE > RAM_SIZE:
                break
            c = r[a]
            size = 2 if c & V_WORD else 1
            spans.append((a, a + VECTOR_PACKAGE_SIZE))
            for w, literal in ((word(r, a + V_DST), False), (word(r, a + V_SRC), c & V_LITERAL)):
                if literal:
                    continue
                if w & V_ICS_OPERAND or w + size > RAM_SIZE:
                    return None
                spans.append((w, w + size))
            if c & V_LAST:
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
        if table == 0xFFFF:
            return True
        if table < STATIC_VECTOR_RAM:
            return False
        span = VECTOR_PACKAGE_SIZE * VECTOR_PACKAGES
        snap = self.ram[table : table + span]
        memo = self._static_memo
        if memo is not None and memo[0] == table and memo[1] == snap:
            return memo[2]
        result = self._static_scan(table)
        self._static_memo = (table, snap, result)
        return result

    def _static_scan(self, table: int) -> bool:
        r = self.ram
        for i in range(VECTOR_PACKAGES):
            a = table + VECTOR_PACKAGE_SIZE * i
            if a + VECTOR_PACKAGE_SIZE > RAM_SIZE:
                return True
            c = r[a]
            for off, is_src in ((V_DST, False), (V_SRC, True)):
                if is_src and c & V_LITERAL:
                    continue
                w = word(r, a + off)
                if w & V_ICS_OPERAND or w < STATIC_VECTOR_RAM or w + 2 > RAM_SIZE:
                    return False
            if c & V_LAST:
                return True
        return True
