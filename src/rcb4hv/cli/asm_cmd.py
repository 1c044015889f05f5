"""``rcb4hv asm`` and ``rcb4hv disasm``: RCB-4 programs as readable text and back."""

from __future__ import annotations

import re
import sys
from typing import NoReturn

import click

from rcb4hv.asm import assemble, disassemble, disassemble_frames, disassemble_image
from rcb4hv.cli._util import ADDRESS, NUMBER_FORMS
from rcb4hv.cli.decode_cmd import parse_hex
from rcb4hv.errors import AsmError, Rcb4Error
from rcb4hv.files import read_bytes, read_text, write_atomic


def _fail(message: str) -> NoReturn:
    click.echo(f"error: {message}", err=True)
    sys.exit(1)


_ORIGIN = click.option(
    "--origin",
    type=ADDRESS,
    metavar="ADDR",
    help=f"ROM address of the first byte ({NUMBER_FORMS}).",
)


@click.command("asm")
@click.argument("source", type=click.Path(dir_okay=False, allow_dash=True))
@click.option("-o", "--output", type=click.Path(dir_okay=False), help="Write the bytes here.")
@_ORIGIN
@click.option("--hex", "as_hex", is_flag=True, help="Write hex text (one frame a line).")
@click.option(
    "--image",
    "as_image",
    is_flag=True,
    help="With -o: a whole 256 KB ROM image, the program at its origin, the rest erased (FF): "
    "what `disasm --image` read.",
)
def asm(source: str, output: str | None, origin: int | None, as_hex: bool, as_image: bool) -> None:
    """Assemble SOURCE ('-' = stdin) into RCB-4 command frames.

    Without -o the frames are printed in hex, one per line, after their ROM address.
    """
    if as_image and (output is None or as_hex):
        _fail("--image writes a ROM image: give -o FILE (and no --hex)")
    try:
        with click.open_file(source, encoding="utf-8-sig") as f:  # a BOM is no statement
            text = f.read()
    except OSError as exc:
        _fail(f"{source}: {exc.strerror or exc}")
    except UnicodeDecodeError:
        _fail(
            f"{source}: not UTF-8 text; an assembler source is text (a ROM image is read "
            "with `rcb4hv disasm --image`)"
        )
    try:
        program = assemble(text, origin)
    except AsmError as exc:
        _fail(f"{source}:{exc.line}:{exc.column}: {exc.message}")
    except ValueError as exc:
        _fail(str(exc))
    if output is not None and not as_hex:
        data = program.image() if as_image else program.data
        _write(output, data)
        click.echo(f"{len(data)} bytes at ${program.origin:06X} -> {output}", err=True)
        return
    lines = [f"{item.address:06X}  {item.data.hex(' ').upper()}" for item in program.items]
    text_out = "\n".join(lines) + ("\n" if lines else "")
    if output is not None:
        _write(output, text_out)
    else:
        click.echo(text_out, nl=False)


def _write(output: str, data: bytes | str) -> None:
    """Write ``output`` atomically, or a one-line error naming it."""
    try:
        write_atomic(output, data)
    except OSError as exc:  # write_atomic's message names the file
        why = exc.strerror or str(exc)
        _fail(why if output in why else f"{output}: {why}")


_ADDRESSED = re.compile(r"^\s*\$?([0-9A-Fa-f]{6})(?:\s{2,}|\t)(\S.*)$")


def parse_hex_lines(lines: list[str]) -> tuple[bytes, int | None]:
    """The bytes of a hex file and the ROM address of its first byte (None: no addresses).

    Each line is hex bytes (``#`` starts a comment), or what ``asm --hex`` writes: the ROM
    address (6 hex digits) and two spaces before the frame's bytes. Addressed lines must
    follow each other without a gap; a file mixing both kinds is refused."""
    rows: list[tuple[int, int | None, bytes]] = []
    for n, raw in enumerate(lines, 1):
        line = raw.split("#", 1)[0]
        if not line.strip():
            continue
        m = _ADDRESSED.match(line)
        try:
            if m is not None:
                rows.append((n, int(m.group(1), 16), parse_hex((m.group(2),))))
            else:
                rows.append((n, None, parse_hex((line,))))
        except click.BadParameter as exc:
            raise click.BadParameter(f"line {n}: {exc.format_message()}") from None
    addressed = [r for r in rows if r[1] is not None]
    if not addressed:
        return b"".join(r[2] for r in rows), None
    if len(addressed) != len(rows):
        n = next(r[0] for r in rows if r[1] is None)
        raise click.BadParameter(
            f"line {n} has no address column while other lines have one (`asm --hex` writes "
            "an address before every frame)"
        )
    start = addressed[0][1]
    assert start is not None
    at = start
    for n, address, data in addressed:
        if address != at:
            raise click.BadParameter(
                f"line {n}: address ${address:06X} does not follow the previous bytes "
                f"(they end at ${at:06X})"
            )
        at += len(data)
    return b"".join(r[2] for r in addressed), start


@click.command("disasm")
@click.argument("hex_words", metavar="[HEX...]", nargs=-1)
@click.option("--hex-file", type=click.Path(exists=True, dir_okay=False), help="Hex text file.")
@click.option(
    "--bin",
    "bin_file",
    type=click.Path(exists=True, dir_okay=False),
    help="Binary file of ROM bytes (placed at --origin).",
)
@click.option(
    "--image",
    type=click.Path(exists=True, dir_okay=False),
    help="A whole 256 KB ROM image (HeartToHeart4 2.2 layout).",
)
@click.option(
    "--project",
    type=click.Path(exists=True, dir_okay=False),
    help="HeartToHeart4 project (.h4p); with --motion N.",
)
@click.option("--motion", type=int, help="Motion slot of --project (1 to its layout's count).")
@_ORIGIN
@click.option("--no-labels", is_flag=True, help="Write branch targets as addresses.")
@click.option("--no-comments", is_flag=True, help="Leave out addresses and notes.")
@click.option("--no-symbols", is_flag=True, help="Write RAM addresses as numbers.")
@click.option("-o", "--output", type=click.Path(dir_okay=False), help="Write the text here.")
def disasm(
    hex_words: tuple[str, ...],
    hex_file: str | None,
    bin_file: str | None,
    image: str | None,
    project: str | None,
    motion: int | None,
    origin: int | None,
    no_labels: bool,
    no_comments: bool,
    no_symbols: bool,
    output: str | None,
) -> None:
    """Disassemble RCB-4 frames into assembler text.

    Give exactly one input: hex on the command line, --hex-file, --bin, --image or
    --project with --motion. Example: rcb4hv disasm 07 0B 4B 04 00 05 66
    """
    given = [bool(hex_words), hex_file, bin_file, image, project]
    if sum(1 for g in given if g) != 1:
        _fail("give exactly one input: HEX..., --hex-file, --bin, --image or --project")
    if (motion is None) != (project is None):
        _fail("--project and --motion go together")
    kw = {"comments": not no_comments, "symbols": not no_symbols}
    try:
        if image is not None:
            if origin is not None:
                _fail("--origin does not apply to --image")
            data = read_bytes(image)
            _warn_older_layout(image, data)
            text = disassemble_image(data, **kw)
        elif project is not None:
            assert motion is not None
            text = _project_motion(project, motion, origin, labels=not no_labels, **kw)
        else:
            start: int | None = None
            if hex_file is not None:
                data, start = parse_hex_lines(read_text(hex_file).splitlines())
                if start is not None and origin is not None and origin != start:
                    _fail(
                        f"{hex_file} starts at ${start:06X} (its address column); "
                        f"--origin ${origin:06X} disagrees: leave --origin out"
                    )
            elif bin_file is not None:
                data = read_bytes(bin_file)
            else:
                data = parse_hex(hex_words)
            base = origin if origin is not None else start or 0
            text = disassemble(data, base, labels=not no_labels, **kw)
    except click.BadParameter as exc:
        _fail(exc.format_message())
    except (OSError, ValueError) as exc:
        _fail(str(exc))
    if output is not None:
        _write(output, text)
    else:
        click.echo(text, nl=False)


def _warn_older_layout(name: str, data: bytes) -> None:
    """``disasm --image`` names the regions of a HeartToHeart4 2.2 image: say so for an image
    in an older layout (its motions sit elsewhere; the frames are still right)."""
    from rcb4hv.project.relocate import image_layout

    try:
        layout = image_layout(data)
    except (ValueError, Rcb4Error):
        return  # no HeartToHeart4 layout found: disassemble_image says what is wrong
    if layout.version != "2.2":
        click.echo(
            f"warning: {name} is a HeartToHeart4 {layout.version} image; the regions below "
            "are named as in 2.2 (its motions start elsewhere: `rcb4hv project image` lists "
            "them)",
            err=True,
        )


def _project_motion(
    path: str, slot: int, origin: int | None, *, labels: bool, comments: bool, symbols: bool
) -> str:
    from rcb4hv.hth4 import load_project

    proj = load_project(path)
    try:
        m = proj.motion(slot)
    except KeyError:
        raise ValueError(f"{path}: no motion slot {slot}") from None
    if m.is_empty:
        raise ValueError(f"{path}: motion slot {slot} is empty")
    header = f"; motion {m.slot}" + (f": {m.name}" if m.name else "") + "\n" if comments else ""
    return header + disassemble_frames(
        m.frames,
        m.address if origin is None else origin,
        labels=labels,
        comments=comments,
        symbols=symbols,
    )


def register(cli: click.Group) -> None:
    """Add ``asm`` and ``disasm`` to ``cli``."""
    cli.add_command(asm)
    cli.add_command(disasm)
