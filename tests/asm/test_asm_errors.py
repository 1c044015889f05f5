"""Assembler errors name the line and column and say what is wrong."""

from __future__ import annotations

import pytest

from rcb4hv.asm import assemble
from rcb4hv.errors import AsmError

CASES = [
    # (source, line, column, message fragment)
    ("RETURN\n    MOV RAM[SYSTEM], #01", 2, 5, "unknown mnemonic 'MOV'"),
    ("MOVE RAM[SYSTEM]", 1, 1, "expected MOVE DEST, SOURCE[, SIZE]"),
    ("JUMP loop\nRETURN", 1, 6, "undefined label 'loop'"),
    ("a: RETURN\n  a: RETURN", 2, 3, "duplicate label 'a' (first defined on line 1)"),
    ("ADD RAM[VAR[0]], #01 02 03", 1, 1, "ADD size 3 out of range 1..2"),
    ("SERVO 200, 1, 7500", 1, 1, "ICS number 200 out of range 0..127"),
    ("MOVE RAM[0x0490], #01", 1, 10, "RAM address 1168 out of range"),
    ("MOVE RAM[0x048F], #01 02", 1, 1, "runs past the end"),
    ("ADD RAM[VAR[0]], #5", 1, 18, "needs a width"),
    ("MOVE COM, RAM[SYSTEM]", 1, 1, "needs a size"),
    ("MOVE RAM[FOO], #01", 1, 10, "unknown RAM symbol 'FOO'"),
    ("MOVE RAM[VAR[20]], #01", 1, 10, "VAR index 20 out of range 0..19"),
    ("MOVE RAM[SYSTEM].OUTPUT, #01", 1, 6, "bad destination operand"),
    ("MOVE ICS[3].FOO, #01", 1, 13, "unknown servo-block field 'FOO'"),
    ("JUMP 0 IF QQ", 1, 11, "bad condition 'QQ'"),
    ("MOVE.NW RAM[SYSTEM], #01", 1, 1, "flag .NW is not allowed here"),
    ("SERVO.FAST 1, 1, 7500", 1, 1, "flag .FAST is not allowed here"),
    (".org 0x100\nRETURN\n.org 0x80", 3, 1, ".org $000080 is below the current address $000103"),
    (".byte 0D 1FF", 1, 10, "bad byte '1FF'"),
    (".bogus 1", 1, 1, "unknown directive '.bogus'"),
    ("SERVOS 10, 1=7500, 1=7600", 1, 20, "ICS 1 given twice"),
    ("SERIES 1=7500", 1, 10, "expected POSITION@SPEED"),
    ("SPEED 1=256", 1, 1, "value 256 out of range 0..255"),
    ("MOVE RAM[SYSTEM], #0x10000:2", 1, 19, "does not fit 2 byte(s)"),
    ("JUMP $1000000", 1, 6, "branch target 16777216 out of range"),
    ("RETURN 5", 1, 1, "expected RETURN without operands"),
    ("MOVE RAM[SYSTEM],, #01", 1, 18, "empty operand"),
    ("MOVE RAM[1 +], #01", 1, 13, "incomplete expression"),
    ("MOVE COM, ROM[x], 1", 1, 15, "undefined label 'x'"),
    (".fill 0, FF", 1, 7, "count 0 out of range"),
    ("  ?", 1, 3, "expected a mnemonic"),
]


@pytest.mark.parametrize(("source", "line", "column", "fragment"), CASES)
def test_error_position_and_message(source: str, line: int, column: int, fragment: str) -> None:
    with pytest.raises(AsmError) as info:
        assemble(source)
    err = info.value
    assert fragment in err.message
    assert (err.line, err.column) == (line, column)
    assert str(err).startswith(f"line {line}, column {column}: ")
    assert isinstance(err, ValueError)


def test_origin_conflict() -> None:
    with pytest.raises(AsmError, match=r"conflicts with the origin \$000B80"):
        assemble(".org 0x1000\nRETURN", origin=0x0B80)
    assert assemble(".org 0x0B80\nRETURN", origin=0x0B80).origin == 0x0B80


def test_code_past_end_of_rom() -> None:
    with pytest.raises(AsmError, match="past the end of ROM"):
        assemble(".org 0x3FFFE\nRETURN")


def test_bad_origin_argument() -> None:
    with pytest.raises(ValueError, match="origin"):
        assemble("RETURN", origin=0x40000)


@pytest.mark.parametrize(
    ("source", "fragment"),
    [
        ("MOVE RAM[1162], RAM[0], 20", "destination RAM[048Ah] + 20 bytes runs past the end"),
        ("MOVE RAM[0], ROM[0x3FFFF], 20", "source ROM[03FFFFh] + 20 bytes runs past the end"),
    ],
)
def test_an_operand_past_the_end_is_named_in_hex(source: str, fragment: str) -> None:
    """The message showed a Python repr: ``destination Ram(address=1162) + 20 bytes``."""
    with pytest.raises(AsmError) as info:
        assemble(source)
    assert fragment in info.value.message
    assert "address=" not in info.value.message
