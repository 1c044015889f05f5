"""RCB-4 assembler and disassembler: a readable text form of ROM programs.

One command per line, ``;`` starts a comment, ``name:`` defines a label. Mnemonics and RAM
symbols are case-insensitive; labels are case-sensitive. Numbers: ``123``, ``0x7B``, ``$7B``.

==========================================  ===============================================
text                                        command
==========================================  ===============================================
``MOVE DST, SRC[, SIZE]``                   Move (DST may be ``COM``: read to the host)
``AND|OR|XOR[.NW] DST, SRC[, SIZE]``        And, Or, Xor (``.NW``: flags only, no write-back)
``ADD|SUB|MUL|DIV|MOD[.NW] DST, SRC[, N]``  Add ... Mod (N = 1 or 2)
``NOT[.NW] DST, SIZE``                      Not
``SHR[.NW] DST, BITS, SIZE``                Shift right 0-127 (``SHL``: left 1-128;
                                            ``SHIFT DST, COUNT, SIZE``: the raw count byte)
``JUMP|CALL TARGET [IF COND]``              Jump, Call; COND ``Z``, ``NZ``, ``C``, ``NC``,
                                            ``Z&C`` ..., or ``COND=0x01`` (raw byte)
``RETURN``                                  Return
``ICSCOMM ICS, COUNT, RAM[TX], RAM[RX]``    CommunicateDevice
``SERVO[.KEEP] ICS, SPEED, POS``            RunSingleServo (``.KEEP``: leave update flags)
``SERVOS[.KEEP] SPEED, ICS=POS, ...``       RunConstFrameServo
``SERIES[.KEEP] ICS=POS@SPEED, ...``        RunSeriesServo
``SPEED ICS=V, ...`` / ``STRETCH ICS=V``    SetSpeed / SetStretch
``VERSION`` / ``ACKCHECK[.LONG]``           GetVersionInfo / AcknowledgeCheck
==========================================  ===============================================

Operands: ``RAM[expr]``, ``ICS[n]`` with an optional servo-block field and offset
(``ICS[5].MEASURED``, ``ICS[5]+20``), ``ROM[expr]`` (labels allowed), ``COM``, and literals:
``#02 80`` (two-digit hex bytes in frame order), ``#0x8002`` (little-endian, width from the
digits), ``#7500:2`` (value:width). SIZE is required for RAM/ICS/ROM sources and implied by
a literal. Positions are numbers or ``FREE`` (8000h) / ``HOLD`` (7FFFh).

RAM symbols (spec 10.1 and HeartToHeart4's user area): ``SYSTEM PC CALL_DEPTH UPDATE_FLAGS
PIO_DIR PIO_DATA VECTOR_TABLE KRI3 BUTTONS KRI3_SUM`` and the tables ``AD_REF[0-10]
AD[0-10] TIMER[0-3] ALLOC[0-35] SERVO[0-34] PA[1-4] VPKG[0-31] COUNTER[0-10] VAR[0-19]
TEMP[0-1]`` (``VAR3`` = ``VAR[3]``); ``SERVO[n].FIELD`` names a servo-block byte; any
expression may add or subtract numbers (``RAM[VAR[0]+1]``).

Directives: ``.org ADDR`` (ROM address of what follows; forward gaps are erased FF),
``.byte 03 0D 10 FF`` / ``.data`` (raw bytes, two-digit hex or ``0x..``) and
``.fill COUNT, BYTE``.
"""

from __future__ import annotations

from rcb4hv.asm.assembler import AsmItem, AssembledProgram, assemble
from rcb4hv.asm.disassembler import (
    disassemble,
    disassemble_frames,
    format_command,
    operand_text,
)
from rcb4hv.asm.image import disassemble_image

__all__ = [
    "AsmItem",
    "AssembledProgram",
    "assemble",
    "disassemble",
    "disassemble_frames",
    "disassemble_image",
    "format_command",
    "operand_text",
]
