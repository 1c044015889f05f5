"""Hand-written programs assemble to known bytes (spec section 14 vectors and more)."""

from __future__ import annotations

import pytest

from rcb4hv import protocol as p
from rcb4hv.asm import assemble, disassemble, format_command

# (source line, expected frame); the frames are the spec's section 14 test vectors.
GOLDEN = [
    ("ACKCHECK", "03 FE 01"),
    ("ackcheck.long", "04 FE 06 08"),
    ("VERSION", "03 FD 00"),
    ("RETURN", "03 0D 10"),
    ("MOVE COM, RAM[SYSTEM], 2", "0A 00 20 00 00 00 00 00 02 2C"),
    ("MOVE RAM[SYSTEM], #02 80", "09 00 02 00 00 00 02 80 8D"),
    ("MOVE RAM[0], #0x8002", "09 00 02 00 00 00 02 80 8D"),
    ("MOVE COM, ICS[5].MEASURED, 2", "0A 00 21 00 00 00 04 05 02 36"),
    ("MOVE COM, ICS[5]+4, 2", "0A 00 21 00 00 00 04 05 02 36"),
    ("MOVE COM, ROM[$000B80], 4", "0B 00 23 00 00 00 80 0B 00 04 BD"),
    ("MOVE ROM[0x0B80], #03 0D 10", "0A 00 32 80 0B 00 03 0D 10 E7"),
    ("CALL $000B80", "07 0C 80 0B 00 00 9E"),
    ("JUMP $00044B IF Z", "07 0B 4B 04 00 05 66"),
    ("ADD RAM[VAR[0]], #0x0005", "09 06 02 62 04 00 05 00 7C"),
    ("ADD RAM[VAR0], #5:2", "09 06 02 62 04 00 05 00 7C"),
    ("ADD RAM[0x0462], #05 00", "09 06 02 62 04 00 05 00 7C"),
    ("SUB.NW RAM[BUTTONS], #00 01", "09 07 82 50 03 00 00 01 E6"),
    ("AND RAM[PIO_DATA], #0F", "08 01 02 3A 00 00 0F 54"),
    ("NOT RAM[VAR[0]], 2", "0A 04 00 62 04 00 00 00 02 76"),
    ("SHR RAM[VAR[0]], 1, 2", "0A 05 00 62 04 00 00 01 02 78"),
    ("SHL RAM[VAR[0]], 1, 2", "0A 05 00 62 04 00 00 FF 02 76"),
    ("SHIFT RAM[VAR[0]], 0xFF, 2", "0A 05 00 62 04 00 00 FF 02 76"),
    ("SERVO 2, 30, 7500", "07 0F 02 1E 4C 1D 9F"),
    ("SERVO 2, 1, FREE", "07 0F 02 01 00 80 99"),
    ("SERVOS 10, 0=7500, 9=8000", "0D 10 01 02 00 00 00 0A 4C 1D 40 1F F2"),
    ("SERVOS 10, 9=8000, 0=7500", "0D 10 01 02 00 00 00 0A 4C 1D 40 1F F2"),
    ("SERIES 3=7600@5, 32=7700@6", "0E 11 08 00 00 00 01 05 B0 1D 06 14 1E 32"),
    ("SPEED 0=100, 9=60", "0B 12 01 02 00 00 00 02 64 3C C2"),
    ("MOVE RAM[SYSTEM], #10 83", "09 00 02 00 00 00 10 83 9E"),
    ("CALL $FFFFFF", "07 0C FF FF FF 00 10"),
]


@pytest.mark.parametrize(("line", "frame"), GOLDEN)
def test_golden_line(line: str, frame: str) -> None:
    program = assemble(line)
    assert program.data == bytes.fromhex(frame)
    assert program.frames == [bytes.fromhex(frame)]


@pytest.mark.parametrize(("line", "frame"), GOLDEN)
def test_golden_disassembles_to_equivalent_text(line: str, frame: str) -> None:
    data = bytes.fromhex(frame)
    text = format_command(p.decode_command(data))
    assert assemble(text).data == data


def test_canonical_text_of_spec_vectors() -> None:
    data = bytes.fromhex(
        "07 0B 4B 04 00 05 66 09 07 82 50 03 00 00 01 E6 0A 00 21 00 00 00 04 05 02 36"
    )
    assert disassemble(data, 0x44B, comments=False).splitlines() == [
        "    .org $00044B",
        "L_00044B:",
        "    JUMP L_00044B IF Z",
        "    SUB.NW RAM[BUTTONS], #00 01",
        "    MOVE COM, ICS[5].MEASURED, 2",
    ]
    assert disassemble(data, 0x44B, comments=False, labels=False, symbols=False).splitlines() == [
        "    .org $00044B",
        "    JUMP $00044B IF Z",
        "    SUB.NW RAM[0x0350], #00 01",
        "    MOVE COM, ICS[5]+4, 2",
    ]


PROGRAM = """\
; wait for the UP button, then play motion 1 and stop
        .org $000B80          ; motion 1's slot
start:  MOVE RAM[COUNTER[0]], #03
loop:
        SUB.NW RAM[BUTTONS], #00 01   ; UP pressed?
        JUMP pressed IF Z
        SUB RAM[COUNTER0], #01
        JUMP loop IF NZ
        RETURN

pressed:
        CALL $000B80
        SERVO.KEEP 35, 10, HOLD
        MOVE ICS[2].OUTPUT, RAM[SERVO[3].OUTPUT], 2
        RETURN
        .byte FF              ; end-of-motion marker
"""


def test_program_with_labels_symbols_and_comments() -> None:
    prog = assemble(PROGRAM)
    assert prog.origin == 0x0B80
    assert prog.labels == {"start": 0x0B80, "loop": 0x0B88, "pressed": 0x0BAA}
    expected = b"".join(
        (
            p.encode_command(p.Move(p.Ram(0x0457), p.Data(b"\x03"))),
            bytes.fromhex("09 07 82 50 03 00 00 01 E6"),
            bytes.fromhex("07 0B AA 0B 00 05 CC"),  # JUMP pressed IF Z
            p.encode_command(p.Sub(p.Ram(0x0457), p.Data(b"\x01"))),
            p.encode_command(p.Jump(0x0B88, p.Condition.if_not_zero())),
            b"\x03\x0d\x10",
            bytes.fromhex("07 0C 80 0B 00 00 9E"),
            p.encode_command(p.RunSingleServo(35, 10, 0x7FFF, set_update_flag=False)),
            p.encode_command(p.Move(p.Ics(6, 2), p.Ram(0x0090 + 3 * 20 + 6), 2)),
            b"\x03\x0d\x10\xff",
        )
    )
    assert prog.data == expected
    assert [item.line for item in prog.items] == [3, 5, 6, 7, 8, 9, 12, 13, 14, 15, 16]
    assert prog.items[-1].command is None and prog.items[-1].data == b"\xff"
    assert prog.items[2].command == p.Jump(0x0BAA, p.Condition.if_zero())


def test_org_gap_is_erased_and_image_pads() -> None:
    prog = assemble(".org 0x10\nRETURN\n.org 0x15\nRETURN")
    assert prog.origin == 0x10
    assert prog.data == b"\x03\x0d\x10\xff\xff\x03\x0d\x10"
    image = prog.image()
    assert len(image) == p.ROM_SIZE
    assert image[0x10:0x18] == prog.data and image[:0x10] == b"\xff" * 0x10


def test_fill_and_data_directives() -> None:
    prog = assemble(".fill 3, 00\n.data 0x0D $10 ab", origin=5)
    assert prog.origin == 5 and prog.data == b"\x00\x00\x00\x0d\x10\xab"


def test_conditions() -> None:
    def cond(text: str) -> int:
        return assemble(f"JUMP 0 IF {text}").data[5]

    assert [cond(c) for c in ("Z", "NZ", "C", "NC", "Z&C", "nz & nc", "ALWAYS")] == [
        0x05,
        0x04,
        0x0A,
        0x08,
        0x0F,
        0x0C,
        0x00,
    ]
    assert cond("COND=0x03") == 0x03  # flag values without compare bits round trip too
    assert format_command(p.decode_command(assemble("JUMP 0 IF COND=1").data)).endswith(
        "IF COND=0x01"
    )


def test_labels_before_and_on_org_lines() -> None:
    prog = assemble("first:\n  .org $0B80\nRETURN\nsecond: .org 0x0B90\nJUMP first\nJUMP second")
    assert prog.labels == {"first": 0x0B80, "second": 0x0B90}
    assert prog.origin == 0x0B80
    assert prog.items[1].command == p.Jump(0x0B80)
    assert prog.items[2].command == p.Jump(0x0B90)


def test_case_insensitive_keywords_case_sensitive_labels() -> None:
    prog = assemble(
        "Top: sub.nw ram[buttons], #00 01\njump Top if nz\nmove com, ics[5].measured, 2"
    )
    assert (
        prog.data
        == assemble(
            "Top: SUB.NW RAM[BUTTONS], #00 01\nJUMP Top IF NZ\nMOVE COM, ICS[5].MEASURED, 2"
        ).data
    )
    with pytest.raises(ValueError, match="undefined label 'top'"):
        assemble("Top: RETURN\nJUMP top")
