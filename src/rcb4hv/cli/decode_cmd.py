"""``rcb4hv decode HEX...``: decode captured RCB-4HV traffic into readable commands."""

from __future__ import annotations

import json
import re
import sys

import click

from rcb4hv.errors import ChecksumError, FrameError, ProtocolError
from rcb4hv.protocol import NEED_DATA, FrameDecoder, decode_command
from rcb4hv.protocol.describe import command_fields, describe_command
from rcb4hv.protocol.frame import checksum

_HEX_NOISE = re.compile(r"0x|[\s,:;\-]", re.IGNORECASE)


def parse_hex(words: tuple[str, ...]) -> bytes:
    """Bytes from hex given as ``07 0F 02``, ``070F02``, ``0x07,0x0f`` or a mix."""
    text = _HEX_NOISE.sub("", "".join(words))
    if len(text) % 2:
        raise click.BadParameter("an odd number of hex digits", param_hint="HEX")
    try:
        return bytes.fromhex(text)
    except ValueError as exc:
        raise click.BadParameter(f"not hex: {exc}", param_hint="HEX") from exc


def _reply_text(frame: bytes) -> str | None:
    """A 4-byte ACK/NAK that is not itself a command (``04 CMD 06|15 SUM``)."""
    if len(frame) == 4 and frame[2] in (0x06, 0x15):
        return f"{'ACK' if frame[2] == 0x06 else 'NAK'} of {frame[1]:02X}h"
    return None


def _skipped(offset: int, data: bytes) -> dict[str, object]:
    """An entry for bytes no frame starts at (noise between frames, a lost SIZE byte)."""
    n = len(data)
    return {
        "offset": offset,
        "hex": data.hex(" ").upper(),
        "error": f"{n} byte{'s' if n > 1 else ''} skipped: no frame starts there",
    }


def decode_stream(data: bytes) -> tuple[list[dict[str, object]], list[str]]:
    """Split ``data`` into frames (:class:`FrameDecoder`, resynchronising a frame at a time)
    and decode each, going on after a bad one.

    Returns the entries in order (a frame that does not decode, or bytes no frame starts at,
    is an entry with an ``error``) and the errors, each prefixed with its byte offset. A
    frame with a bad checksum is skipped whole (its SIZE byte is trusted); a byte that cannot
    start a frame is skipped alone, a run of them reported once.
    """
    decoder = FrameDecoder(max_size=255, resync="frame")
    decoder.receive_data(data)
    out: list[dict[str, object]] = []
    errors: list[str] = []
    skipped = bytearray()

    def flush(at: int) -> None:
        if skipped:
            entry = _skipped(at - len(skipped), bytes(skipped))
            out.append(entry)
            errors.append(f"byte {entry['offset']}: {entry['error']} ({entry['hex']})")
            skipped.clear()

    offset = 0
    while True:
        try:
            frame = decoder.next_frame()
        except ChecksumError as exc:  # the decoder dropped the frame its SIZE byte spans
            flush(offset)
            bad = exc.frame
            why = f"bad checksum {bad[-1]:02X}, the sum of the other bytes is "
            why += f"{checksum(bad[:-1]):02X}"
            out.append({"offset": offset, "hex": bad.hex(" ").upper(), "error": why})
            errors.append(f"byte {offset}: {bad.hex(' ').upper()}: {why}")
            offset += len(bad)
            continue
        except FrameError:  # a SIZE byte that cannot start a frame: dropped alone
            skipped.append(data[offset])
            offset += 1
            continue
        flush(offset)
        if frame is NEED_DATA:
            rest = decoder.reset()
            if rest:
                why = f"truncated frame (size byte says {rest[0]}, {len(rest)} given)"
                errors.append(f"byte {offset}: {why} {rest.hex(' ').upper()}")
                out.append({"offset": offset, "hex": rest.hex(" ").upper(), "error": why})
            return out, errors
        assert isinstance(frame, bytes)
        entry: dict[str, object] = {"offset": offset, "hex": frame.hex(" ").upper()}
        try:
            cmd = decode_command(frame)
        except ProtocolError as exc:
            reply = _reply_text(frame)
            if reply is None:
                entry["error"] = str(exc)
                errors.append(f"byte {offset}: {frame.hex(' ').upper()}: {exc}")
            else:
                entry.update({"reply": reply, "text": reply})
        else:
            entry.update(command_fields(cmd))
            entry["text"] = describe_command(cmd)
        out.append(entry)
        offset += len(frame)


@click.command("decode")
@click.argument("hex_words", metavar="HEX...", nargs=-1, required=True)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object per frame.")
def decode(hex_words: tuple[str, ...], as_json: bool) -> None:
    """Decode RCB-4HV frames given in hex (captured traffic: several frames in a row are fine).

    A frame that does not decode (a bad checksum, an unknown command) is reported and
    decoding goes on after it; the exit status is then 1.

    Example: rcb4hv decode 07 0F 02 1E 4C 1D 9F
    """
    entries, errors = decode_stream(parse_hex(hex_words))
    for entry in entries:
        if as_json:
            click.echo(json.dumps(entry, ensure_ascii=False))
        elif "error" in entry:
            click.echo(f"{entry['hex']}\n  (not decoded: {entry['error']})")
        else:
            click.echo(f"{entry['hex']}\n  {entry['text']}")
    for error in errors:
        click.echo(f"error: {error}", err=True)
    if errors:
        sys.exit(1)


def register(cli: click.Group) -> None:
    """Add ``decode`` to ``cli``."""
    cli.add_command(decode)
