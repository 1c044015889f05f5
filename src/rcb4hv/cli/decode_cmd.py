"""``rcb4hv decode HEX...``: decode captured RCB-4HV traffic into readable commands."""

from __future__ import annotations

import json
import re
import sys

import click

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol import NEED_DATA, FrameDecoder, decode_command
from rcb4hv.protocol.describe import command_fields, describe_command

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


def decode_stream(data: bytes) -> tuple[list[dict[str, object]], str | None]:
    """Split ``data`` into frames and decode each; the second item is the first error, if any."""
    decoder = FrameDecoder(max_size=255, resync="frame")
    decoder.receive_data(data)
    out: list[dict[str, object]] = []
    offset = 0
    while True:
        try:
            frame = decoder.next_frame()
        except ProtocolError as exc:
            return out, f"byte {offset}: {exc}"
        if frame is NEED_DATA:
            rest = decoder.reset()
            if rest:
                return out, (
                    f"byte {offset}: truncated frame {rest.hex(' ').upper()} "
                    f"(size byte says {rest[0]}, {len(rest)} given)"
                )
            return out, None
        assert isinstance(frame, bytes)
        entry: dict[str, object] = {"offset": offset, "hex": frame.hex(" ").upper()}
        try:
            cmd = decode_command(frame)
        except ProtocolError as exc:
            reply = _reply_text(frame)
            if reply is None:
                return out, f"byte {offset}: {frame.hex(' ').upper()}: {exc}"
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

    Example: rcb4hv decode 07 0F 02 1E 4C 1D 9F
    """
    entries, error = decode_stream(parse_hex(hex_words))
    for entry in entries:
        if as_json:
            click.echo(json.dumps(entry, ensure_ascii=False))
        else:
            click.echo(f"{entry['hex']}\n  {entry['text']}")
    if error:
        click.echo(f"error: {error}", err=True)
        sys.exit(1)


def register(cli: click.Group) -> None:
    """Add ``decode`` to ``cli``."""
    cli.add_command(decode)
