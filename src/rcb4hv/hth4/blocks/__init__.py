"""Motion programs: every entry of a motion as a typed block, programs as JSON files and as
HeartToHeart4 flowcharts.

* :mod:`.kinds`: the block kinds, decoded from and encoded to command frames through
  :mod:`rcb4hv.protocol`;
* :mod:`.operands`: operands by name (``VAR3``, ``BUTTONS``, ``ICS5+14``);
* :mod:`.program`: a motion as a :class:`Program` (branches by label) and back;
* :mod:`.jsonio`: programs as JSON files;
* :mod:`.flowxml`: programs as HeartToHeart4 flowchart XML.
"""

from rcb4hv.hth4.blocks.jsonio import dump_program, load_program, program_from_json, program_json
from rcb4hv.hth4.blocks.kinds import KINDS, Block
from rcb4hv.hth4.blocks.program import (
    Program,
    block_spans,
    compile_program,
    motion_program,
    put_program,
)

__all__ = [
    "KINDS",
    "Block",
    "Program",
    "block_spans",
    "compile_program",
    "dump_program",
    "load_program",
    "motion_program",
    "program_from_json",
    "program_json",
    "put_program",
]
