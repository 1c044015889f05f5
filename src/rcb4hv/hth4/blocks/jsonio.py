"""Motion programs as JSON files (the schema: ``docs/motion-programs.md``).

::

    {"format": "rcb4hv-motion-program", "version": 1, "slot": 5, "name": "walk",
     "date": "2026-01-01T00:00:00.0000000+09:00", "button": 0, "compare_type": "Equals",
     "key_code": "None",
     "blocks": [{"kind": "servo_stretch", "values": {"8": 80}},
                {"label": "L1", "kind": "pose", "frames": 10, "positions": {"0": 7500}},
                {"kind": "button_branch", "buttons": ["UP"], "if": "equal", "to": "L1"},
                {"kind": "end"}]}

:func:`program_json` / :func:`program_from_json` convert; :func:`dump_program` gives the file
text (one line per block, so diffs stay small) and :func:`load_program` reads a
file. Structure errors are :class:`~rcb4hv.errors.EditError` naming the field; the fields of
each block are checked when the program is compiled
(:func:`~rcb4hv.hth4.blocks.program.compile_program`).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Final

from rcb4hv.errors import EditError
from rcb4hv.files import read_text
from rcb4hv.hth4.blocks.fields import Fields, Json
from rcb4hv.hth4.blocks.kinds import Block
from rcb4hv.hth4.blocks.program import Program

__all__ = ["FORMAT", "dump_program", "load_program", "program_from_json", "program_json"]

FORMAT: Final = "rcb4hv-motion-program"
VERSION: Final = 1
_KEYS: Final = (
    "format", "version", "slot", "name", "date", "button", "compare_type", "key_code", "blocks",
)  # fmt: skip


def program_json(program: Program) -> dict[str, Json]:
    """The JSON object of ``program``."""
    return {
        "format": FORMAT,
        "version": VERSION,
        "slot": program.slot,
        "name": program.name,
        "date": program.date,
        "button": program.button,
        "compare_type": program.compare_type,
        "key_code": program.key_code,
        "blocks": [b.to_json() for b in program.blocks],
    }


def _opt_str(f: Fields, name: str) -> str | None:
    return None if f.obj.get(name) is None else f.text(name)


def program_from_json(obj: Json, where: str = "") -> Program:
    """The program of a JSON object (EditError naming the field for a bad structure: its
    path after ``where``, e.g. the file's name: ``turn.json.blocks[1].frames``)."""
    if not isinstance(obj, dict):
        raise EditError(f"{where or 'program'}: a motion program is a JSON object")
    f = Fields(obj, where)
    f.check_known(_KEYS)
    if obj.get("format", FORMAT) != FORMAT:
        raise EditError(f"{f.path('format')}: expected {FORMAT!r}")
    if f.integer("version", 1, VERSION, VERSION) != VERSION:
        raise EditError(f"{f.path('version')}: this rcb4hv reads version {VERSION}")
    blocks = f.get("blocks")
    if not isinstance(blocks, list):
        raise EditError(f"{f.path('blocks')}: expected a list of blocks")
    slot = obj.get("slot")
    return Program(
        blocks=tuple(Block.from_json(b, f.path(f"blocks[{n}]")) for n, b in enumerate(blocks)),
        name=_opt_str(f, "name"),
        date=_opt_str(f, "date"),
        button=f.integer("button", 0, 0xFFFF, 0),
        compare_type=_opt_str(f, "compare_type") or "Equals",
        key_code=_opt_str(f, "key_code") or "None",
        slot=f.integer("slot", 1, 999) if slot is not None else None,
    )


def dump_program(program: Program) -> str:
    """The file text of ``program``: JSON, one line per header field and per block (so a
    changed block is one changed line in a diff), a final newline."""
    obj = program_json(program)
    blocks = obj.pop("blocks")
    assert isinstance(blocks, list)
    head = [f"  {json.dumps(k)}: {json.dumps(v, ensure_ascii=False)}," for k, v in obj.items()]
    rows = ",\n".join(f"    {json.dumps(b, ensure_ascii=False)}" for b in blocks)
    body = f'  "blocks": [\n{rows}\n  ]' if blocks else '  "blocks": []'
    return "{\n" + "\n".join(head) + "\n" + body + "\n}\n"


def load_program(path: str | os.PathLike[str]) -> Program:
    """Read a program file (EditError for text that is not JSON or not a program;
    :class:`~rcb4hv.errors.FileAccessError` for a file that cannot be read or is not UTF-8)."""
    try:
        obj = json.loads(read_text(path))
    except json.JSONDecodeError as exc:
        raise EditError(f"{path}: not JSON: {exc}") from None
    return program_from_json(obj, str(Path(path).name))
