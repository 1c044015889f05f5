"""A motion as a program: its blocks in ROM order, branches by label, and back.

:func:`motion_program` reads motion ``slot`` of a project into a :class:`Program`;
:func:`compile_program` lays a program out at a slot's ROM address and gives its stored
entries; :func:`put_program` puts them (and the program's name, button and date) into a slot.

Branch targets (the ``to`` field) are relocatable:

* a block of the same program: its ``label`` (a string), or its 0-based index (an int);
  :func:`motion_program` labels every block a branch goes to ``L1``, ``L2``, ... in order;
* another motion: ``{"motion": N}`` (its start) or ``{"motion": N, "offset": K}`` (K bytes
  in);
* anything else: ``{"address": "FFFFFF"}`` (a hex ROM address, kept as is: HeartToHeart4's
  unresolved flowchart branches, the start-up stub, a point inside an entry).

A compare entry and its conditional JUMP become one block unless another branch goes to the
JUMP itself (then they stay two blocks, so that branch keeps its target).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, replace

from rcb4hv.errors import EditError
from rcb4hv.hth4.blocks.encode import encode_block
from rcb4hv.hth4.blocks.fields import Json
from rcb4hv.hth4.blocks.kinds import Block, Resolver, decode_group, exact_command, pairs, waits
from rcb4hv.hth4.model import Motion, Project
from rcb4hv.hth4.motioncode import slot_size
from rcb4hv.protocol import Call, Jump

__all__ = [
    "Program",
    "block_spans",
    "compile_blocks",
    "compile_program",
    "motion_program",
    "put_program",
]


@dataclass(frozen=True)
class Program:
    """One motion as blocks, with the slot's name, remote binding and date."""

    blocks: tuple[Block, ...]
    name: str | None = None
    date: str | None = None
    button: int = 0
    compare_type: str = "Equals"
    key_code: str = "None"
    slot: int | None = None
    """The slot it was read from (informative; import puts it where it is told)."""


def _targets(entries: tuple[bytes, ...]) -> Counter[int]:
    """How many JUMP / CALL entries go to each address."""
    out: Counter[int] = Counter()
    for e in entries:
        got = exact_command(e)
        if got is not None and isinstance(got[0], (Jump, Call)):
            out[got[0].address] += 1
    return out


def block_spans(motion: Motion) -> list[tuple[int, int]]:
    """(first entry, entry count) of each block of ``motion``."""
    entries = motion.frames
    starts = [motion.address]
    for e in entries:
        starts.append(starts[-1] + len(e))
    targets = _targets(entries)
    out: list[tuple[int, int]] = []
    i = 0
    while i < len(entries):
        if (
            i + 2 < len(entries)
            and targets[starts[i + 1]] == 1
            and starts[i + 2] not in targets
            and waits(entries[i : i + 3], starts[i + 1])
        ):
            out.append((i, 3))
            i += 3
            continue
        two = (
            i + 1 < len(entries)
            and starts[i + 1] not in targets
            and pairs(entries[i], entries[i + 1])
        )
        out.append((i, 2 if two else 1))
        i += 2 if two else 1
    return out


def motion_program(project: Project, slot: int) -> Program:
    """Motion ``slot`` of ``project`` as a program (EditError for a missing slot)."""
    try:
        motion = project.motion(slot)
    except KeyError:
        raise EditError(f"the project has no motion slot {slot}") from None
    starts = [motion.address]
    for e in motion.frames:
        starts.append(starts[-1] + len(e))
    groups = block_spans(motion)
    block_at = {starts[i]: n for n, (i, _) in enumerate(groups)}
    targets = _targets(motion.frames)
    labels = {a: f"L{k}" for k, a in enumerate(sorted(t for t in targets if t in block_at), 1)}
    by_address = {m.address: m for m in project.used_motions if m.slot != slot}

    def namer(address: int) -> Json:
        if address in labels:
            return labels[address]
        for start, other in by_address.items():
            if start <= address < start + len(other.rom_bytes()):
                off = address - start
                return {"motion": other.slot, **({"offset": off} if off else {})}
        return {"address": f"{address:06X}"}

    blocks = []
    for i, n in groups:
        b = decode_group(motion.frames[i : i + n], namer)
        blocks.append(replace(b, label=labels.get(starts[i])))
    return Program(
        blocks=tuple(blocks),
        name=motion.name,
        date=motion.date,
        button=motion.button_data,
        compare_type=motion.compare_type,
        key_code=motion.key_code,
        slot=slot,
    )


def _resolver(project: Project | None, addresses: dict[str, int], starts: list[int]) -> Resolver:
    def resolve(target: Json, where: str) -> int:
        if isinstance(target, str):
            if target not in addresses:
                raise EditError(f"{where}: no block is labelled {target!r}")
            return addresses[target]
        if isinstance(target, int) and not isinstance(target, bool):
            if not 0 <= target < len(starts) - 1:
                raise EditError(f"{where}: block index {target} outside 0..{len(starts) - 2}")
            return starts[target]
        if isinstance(target, dict) and "motion" in target:
            slot, off = target.get("motion"), target.get("offset", 0)
            if not isinstance(slot, int) or not isinstance(off, int) or off < 0:
                raise EditError(f"{where}: expected {{'motion': N, 'offset': K}}, not {target!r}")
            if project is None:
                raise EditError(f"{where}: a branch to another motion needs its project")
            try:
                return project.motion(slot).address + off
            except KeyError:
                raise EditError(f"{where}: the project has no motion slot {slot}") from None
        if isinstance(target, dict) and isinstance(target.get("address"), str):
            try:
                value = int(str(target["address"]), 16)
            except ValueError:
                value = -1
            if 0 <= value <= 0xFFFFFF:
                return value
        raise EditError(
            f"{where}: a target is a label, a block index, {{'motion': N}} or "
            f"{{'address': 'HEX'}}, not {target!r}"
        )

    return resolve


def compile_program(project: Project, slot: int, program: Program) -> tuple[bytes, ...]:
    """The stored entries of ``program`` laid out at slot ``slot`` of ``project`` (EditError
    naming the block and field for anything that does not encode, or if it does not fit)."""
    try:
        motion = project.motion(slot)
    except KeyError:
        raise EditError(f"the project has no motion slot {slot}") from None
    entries = compile_blocks(program.blocks, motion.address, project)
    size, room = sum(map(len, entries)), slot_size(motion)
    if size > room:
        raise EditError(f"motion {slot}: {size} bytes do not fit its {room}-byte slot")
    return entries


def compile_blocks(
    blocks: Sequence[Block], base: int, project: Project | None = None
) -> tuple[bytes, ...]:
    """The entries of ``blocks`` laid out from ROM address ``base``; branches by label or
    index resolve within them, to another motion (``{"motion": N}``) through ``project``."""
    labels: dict[str, int] = {}
    for n, b in enumerate(blocks):
        if b.label is not None:
            if b.label in labels:
                raise EditError(f"blocks[{n}].label: {b.label!r} is used twice")
            labels[b.label] = n

    def placeholder(target: Json, where: str) -> int:
        return 0

    starts = [base]
    for n, b in enumerate(blocks):
        made = encode_block(b, placeholder, f"blocks[{n}]", starts[-1])
        starts.append(starts[-1] + sum(map(len, made)))
    addresses = {label: starts[n] for label, n in labels.items()}
    resolve = _resolver(project, addresses, starts)
    entries: list[bytes] = []
    for n, b in enumerate(blocks):
        entries.extend(encode_block(b, resolve, f"blocks[{n}]", starts[n]))
    return tuple(entries)


def put_program(project: Project, slot: int, program: Program) -> Project:
    """``project`` with ``program`` compiled into slot ``slot`` (its name, date, button and key
    code too). Branches of other motions into the slot are left as they are."""
    entries = compile_program(project, slot, program)
    old = project.motion(slot)
    new = replace(
        old,
        frames=entries,
        name=program.name if program.name is not None else old.name,
        date=program.date if program.date is not None else old.date,
        button_data=program.button,
        compare_type=program.compare_type,
        key_code=program.key_code,
    )
    return replace(project, motions=tuple(new if m.slot == slot else m for m in project.motions))
