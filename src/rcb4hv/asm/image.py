"""Disassembly of a whole 256 KB ROM image in the HeartToHeart4 2.2 layout (spec 11.2)."""

from __future__ import annotations

from itertools import pairwise
from typing import Final

from rcb4hv.asm.disassembler import Listing, SweepItem, branch_targets, sweep
from rcb4hv.protocol import ROM_SIZE
from rcb4hv.rom import layout as L

__all__ = ["disassemble_image"]

# Notes shown where the boot program's fixed slots start.
_CODE_NOTES: Final[dict[int, str]] = {
    L.CONFIG_WRITE: "config write (ICS output off)",
    L.PIO_DIRECTION_WRITE: "PIO direction",
    L.PIO_DATA_WRITE: "PIO data",
    L.AD_REFERENCE_COPY: "AD reference copy",
    L.SERVO_BLOCK_COPIES: f"servo-block copies ({L.SERVO_BLOCK_COPY_COUNT})",
    L.ALLOC_COPY: "ICS allocation copy",
    L.KRI3_ALLOC_COPY: "KRI-3 allocation copy",
    L.KRI3_BLOCK_COPY: "KRI-3 block copy",
    L.VECTOR_PACKAGE_COPIES: f"vector-package copies ({L.VECTOR_PACKAGE_COUNT})",
    L.VECTOR_ADDRESS_COPY: "vector-table address copy",
    L.SYSTEM_REGISTER_COPY: "system-register write",
    L.ALL_FREE: "all servos free",
    L.TIMER_WAIT: "timer wait",
    L.ALL_HOLD: "all servos hold",
    L.ALL_HOME: "all servos home",
    L.STARTUP_CALL: "StartupCmd: call the startup motion",
    L.MAIN_LOOP: "main loop",
    L.PIO_SWITCHES: "PIO direction switches",
    L.PRIORITY_CHECKS: f"priority-motion checks ({L.PRIORITY_COUNT} x {L.PRIORITY_SIZE} bytes)",
    L.MAIN_LOOP_JUMP: "back to the main loop",
}

# Data tables: (start, end, title, bytes per line)
_DATA: Final[tuple[tuple[int, int, str, int], ...]] = (
    (L.SYSTEM_REGISTER_IMAGE, L.ALLOC_IMAGE, "system register value", 2),
    (L.ALLOC_IMAGE, L.SERVO_BLOCK_IMAGES, "ICS allocation table image (alloc[0..35])", 16),
    (L.SERVO_BLOCK_IMAGES, L.AD_REFERENCE_IMAGE, "servo block images (20 bytes each)", 20),
    (L.AD_REFERENCE_IMAGE, L.KRI3_ALLOC_IMAGE, "AD reference image", 22),
    (L.KRI3_ALLOC_IMAGE, L.KRI3_BLOCK_IMAGE, "KRI-3 allocation image", 2),
    (L.KRI3_BLOCK_IMAGE, L.VECTOR_ADDRESS_IMAGE, "KRI-3 block image", L.KRI3_BLOCK_SIZE),
    (L.VECTOR_ADDRESS_IMAGE, L.VECTOR_PACKAGE_IMAGES, "vector-table address image", 2),
    (L.VECTOR_PACKAGE_IMAGES, L.TITLE, "vector-package images (8 bytes each)", 8),
    (L.TITLE, L.PRIORITY_IMAGES, "project title", 16),
    (L.PRIORITY_IMAGES, L.MOTIONS, "priority-motion call images (25 bytes each)", 25),
)

_NAMED: Final[dict[int, str]] = {
    L.STARTUP_CALL: "startup",
    L.MAIN_LOOP: "main_loop",
    L.STARTUP_STUB: "startup_stub",
}


def _is_erased(data: bytes) -> bool:
    return data.count(0xFF) == len(data)


def disassemble_image(
    image: bytes | bytearray, *, comments: bool = True, symbols: bool = True
) -> str:
    """The whole ROM image as assembler text, its regions named (HeartToHeart4 2.2 layout).

    The boot program (00000h-005DBh) and every non-empty motion slot are shown as code, the
    data tables (005DCh-00B7Fh) as ``.byte`` lines; erased (all-FF) areas are skipped with a
    note. Assembling the text and padding it with FF to 256 KB gives ``image`` back.
    """
    image = bytes(image)
    if len(image) != ROM_SIZE:
        raise ValueError(f"a ROM image is {ROM_SIZE} bytes, not {len(image)}")

    code: list[tuple[int, int, str]] = [(0, L.SYSTEM_REGISTER_IMAGE, "boot program")]
    empty: list[int] = []
    for n in range(1, L.MOTION_COUNT + 1):
        start = L.motion_address(n)
        if _is_erased(image[start : start + L.MOTION_SIZE]):
            empty.append(n)
        else:
            code.append((start, start + L.MOTION_SIZE, f"motion {n}"))
    code.append((L.STARTUP_STUB, ROM_SIZE, "startup stub"))

    swept = {start: sweep(image[start:end], start) for start, end, _ in code}
    all_items = [it for items in swept.values() for it in items]
    starts = {it.address for it in all_items if it.command is not None}
    names: dict[int, str] = {}
    for start, _, title in code:
        if title.startswith("motion ") and start in starts:
            names[start] = f"motion_{title.split()[1]}"
    for address in sorted(branch_targets(all_items) & starts):
        names.setdefault(address, _NAMED.get(address, f"L_{address:06X}"))
    for address, name in _NAMED.items():
        if address in starts:
            names.setdefault(address, name)

    out = Listing(comments, symbols, names)
    out.comment("HeartToHeart4 2.2 ROM image (256 KB); erased areas are FF")

    def header(title: str, start: int, end: int) -> None:
        out.blank()
        out.comment(f"==== {start:06X}-{end - 1:06X} {title}")

    # boot program, with a note at each fixed slot
    header("boot program", 0, L.SYSTEM_REGISTER_IMAGE)
    _code_with_notes(out, swept[0])

    for start, end, title, per_line in _DATA:
        header(title, start, end)
        for at in range(start, end, per_line):
            chunk = image[at : min(at + per_line, end)]
            note = _data_note(title, start, at, per_line, chunk)
            out.raw(at, chunk, note, per_line=per_line, runs=False)

    empty_runs = _runs(empty)
    for start, end, title in code[1:]:
        if title.startswith("motion "):
            n = int(title.split()[1])
            for first, last in empty_runs:
                if last + 1 == n:
                    _note_empty(out, first, last)
        header(title, start, end)
        out.items(swept[start], skip_erased=True)
    for first, last in empty_runs:
        if last == L.MOTION_COUNT:
            _note_empty(out, first, last)
    return out.text()


def _code_with_notes(out: Listing, items: list[SweepItem]) -> None:
    notes = sorted(_CODE_NOTES.items())
    k = 0
    for lo, hi in _chunks(items, [a for a, _ in notes]):
        while k < len(notes) and notes[k][0] <= (items[lo].address if lo < hi else 1 << 30):
            out.comment(f"-- {notes[k][0]:06X} {notes[k][1]}")
            k += 1
        out.items(items[lo:hi], skip_erased=True)


def _chunks(items: list[SweepItem], cuts: list[int]) -> list[tuple[int, int]]:
    """Split ``items`` into index ranges that start at the first item at/after each cut."""
    bounds = sorted(
        {next((i for i, it in enumerate(items) if it.address >= c), len(items)) for c in cuts}
        | {0, len(items)}
    )
    return list(pairwise(bounds))


def _data_note(title: str, start: int, at: int, per_line: int, chunk: bytes) -> str:
    index = (at - start) // per_line
    if title.startswith("servo block"):
        return f"{at:06X}  ICS {index}"
    if title.startswith("vector-package"):
        return f"{at:06X}  package {index}"
    if title.startswith("priority"):
        return f"{at:06X}  priority {index + 1}"
    if title == "project title":
        return f"{at:06X}  {''.join(chr(b) if 0x20 <= b < 0x7F else '.' for b in chunk)!r}"
    return f"{at:06X}"


def _runs(numbers: list[int]) -> list[tuple[int, int]]:
    runs: list[tuple[int, int]] = []
    for n in numbers:
        if runs and runs[-1][1] == n - 1:
            runs[-1] = (runs[-1][0], n)
        else:
            runs.append((n, n))
    return runs


def _note_empty(out: Listing, first: int, last: int) -> None:
    out.blank()
    which = f"motion {first}" if first == last else f"motions {first}-{last}"
    out.comment(f"{which}: empty (erased)")
