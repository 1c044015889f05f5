"""The one ALU and the one branch-condition evaluator of the emulated board.

COM commands, ROM instructions (plain or compiled by :mod:`~rcb4hv.emulator.accel`) and
vector packages all compute through :func:`alu` / :data:`ALU` and test flags through
:func:`condition_table`; nothing else in the emulator knows how an operation sets Z and C.

Flags: Z is set when the (masked) result is 0. C is the carry out of ADD/MUL, "no borrow"
(``a >= b``) for SUB, 0 for DIV/MOD, the last bit shifted out for SHIFT, and *unchanged*
(``None``) for AND/OR/XOR/NOT and a zero-bit shift (the config's ``logic_carry="clear"``
clears it instead: :func:`set_flags`).
"""

from __future__ import annotations

import enum
from collections.abc import Callable
from typing import Final

from rcb4hv.protocol import Op
from rcb4hv.protocol.memory import SYS
from rcb4hv.protocol.registry import COMMANDS

__all__ = [
    "ALU",
    "C_BIT",
    "OP_OF",
    "Z_BIT",
    "AluOp",
    "alu",
    "condition_table",
    "set_flags",
]

# the Z and C flags as bits of the system register's high byte (RAM 0001h)
Z_BIT: Final = SYS.ZERO >> 8
C_BIT: Final = SYS.CARRY >> 8


class AluOp(enum.IntEnum):
    """The ALU operations, numbered by the command byte that runs them (spec section 4)."""

    AND = Op.AND
    OR = Op.OR
    XOR = Op.XOR
    NOT = Op.NOT
    SHIFT = Op.SHIFT
    ADD = Op.ADD
    SUB = Op.SUB
    MUL = Op.MUL
    DIV = Op.DIV
    MOD = Op.MOD


_ALU_BYTES: Final = frozenset(int(op) for op in AluOp)

#: the operation of each data command class, derived from the command table by command byte
OP_OF: Final[dict[type, AluOp]] = {
    s.cls: AluOp(s.opcode) for s in COMMANDS if s.opcode in _ALU_BYTES
}

# (a, b, mask) -> (result, carry or None = unchanged); a and b are unsigned, result masked
OpFn = Callable[[int, int, int], tuple[int, bool | None]]


def _add(a: int, b: int, mask: int) -> tuple[int, bool | None]:
    full = a + b
    return full & mask, full > mask


def _sub(a: int, b: int, mask: int) -> tuple[int, bool | None]:
    return (a - b) & mask, a >= b


def _mul(a: int, b: int, mask: int) -> tuple[int, bool | None]:
    full = a * b
    return full & mask, full > mask


def _div(a: int, b: int, mask: int) -> tuple[int, bool | None]:
    return (a // b if b else 0), False


def _mod(a: int, b: int, mask: int) -> tuple[int, bool | None]:
    return (a % b if b else 0), False


def _shift(a: int, k: int, mask: int) -> tuple[int, bool | None]:
    """``k`` > 0 shifts right by k, ``k`` < 0 left by -k (the carry is the last bit out)."""
    if k > 0:
        return a >> k, bool(a >> (k - 1) & 1)
    if k < 0:
        k = -k
        bits = mask.bit_length()
        return (a << k) & mask, bool(a >> (bits - k) & 1) if k <= bits else False
    return a, None


#: the ALU table: one function per operation
ALU: Final[dict[AluOp, OpFn]] = {
    AluOp.AND: lambda a, b, m: (a & b, None),
    AluOp.OR: lambda a, b, m: (a | b, None),
    AluOp.XOR: lambda a, b, m: (a ^ b, None),
    AluOp.ADD: _add,
    AluOp.SUB: _sub,
    AluOp.MUL: _mul,
    AluOp.DIV: _div,
    AluOp.MOD: _mod,
    AluOp.NOT: lambda a, b, m: (~a & m, None),
    AluOp.SHIFT: _shift,
}


def alu(op: AluOp, a: int, b: int, size: int) -> tuple[int, bool, bool | None]:
    """``(result, z, c)`` of ``a op b`` on ``size``-byte unsigned operands.

    ``c`` None leaves the carry unchanged. NOT ignores ``b``; for SHIFT ``b`` is the signed
    count (positive: right). DIV/MOD by 0 give 0 (the config's ``division_by_zero="error"``
    is the caller's check).
    """
    result, c = ALU[op](a, b, (1 << (8 * size)) - 1)
    return result, result == 0, c


def set_flags(hi: int, z: bool, c: bool | None, logic_clear: bool) -> int:
    """The system register's high byte ``hi`` with Z and C set from an ALU result."""
    hi = (hi | Z_BIT) if z else (hi & ~Z_BIT)
    if c is None:
        return hi & ~C_BIT if logic_clear else hi
    return (hi | C_BIT) if c else (hi & ~C_BIT)


def _holds(cond: int, z: bool, c: bool, any_mode: bool) -> bool:
    """The COND nibble (bit 0 Z wanted, bit 1 C wanted, bit 2 compare Z, bit 3 compare C)
    against flags ``z``, ``c``: every enabled comparison must match, or with ``any_mode``
    (config ``branch_condition="or"``) one of them (none enabled: always)."""
    checks = []
    if cond & 4:
        checks.append(z == bool(cond & 1))
    if cond & 8:
        checks.append(c == bool(cond & 2))
    if not checks:
        return True
    return any(checks) if any_mode else all(checks)


_TABLES: Final = {
    mode: tuple(
        tuple(_holds(cond, bool(zc & Z_BIT), bool(zc & C_BIT), mode) for zc in range(4))
        for cond in range(16)
    )
    for mode in (False, True)
}


def condition_table(cond: int, any_mode: bool = False) -> tuple[bool, bool, bool, bool]:
    """Whether a condition nibble holds, indexed by ``RAM[0001h] & 3`` (the Z and C bits).

    The one evaluator of JUMP/CALL conditions (``any_mode``: config ``branch_condition``)
    and of vector-package conditions (same nibble layout, always "and")."""
    t = _TABLES[any_mode][cond & 0x0F]
    return (t[0], t[1], t[2], t[3])
