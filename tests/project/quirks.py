"""Write the quirks of real HeartToHeart4 projects into the shared fixture's XML text.

Each helper edits the project file as text (the way another person's HeartToHeart4 would have
written it) and the tests read the result with the ordinary project reader.
"""

from __future__ import annotations

import re
from pathlib import Path

from rcb4hv import hth4
from rcb4hv.rom import layout

EMPTY_SLOT = 18
"""A slot the fixture leaves empty (0x0B80 + 2048 * 17 = 09380h)."""
EMPTY_ADDRESS = layout.motion_address(EMPTY_SLOT)


def fixture_xml(path: Path) -> str:
    return path.read_bytes().decode("utf-8")


def load(xml: str) -> hth4.Project:
    return hth4.parse_project(xml.encode("utf-8"))


def set_setting(xml: str, tag: str, value: int) -> str:
    """Replace the text of the project-level element ``tag`` (first occurrence)."""
    new, n = re.subn(rf"<{tag}>[^<]*</{tag}>", f"<{tag}>{value}</{tag}>", xml, count=1)
    assert n == 1, tag
    return new


def set_priority_address(xml: str, key: int, address: int) -> str:
    """Give priority check ``key`` (which must have a value) the motion ``address``."""
    head, sep, tail = xml.partition("<PriorityMotionCollection>")
    pattern = rf'(<Key xsi:type="xsd:string">{key}</Key>\s*<Value.*?<Address>)[^<]*(</Address>)'
    tail, n = re.subn(pattern, rf"\g<1>{address}\g<2>", tail, count=1, flags=re.S)
    assert n == 1
    return head + sep + tail


def _motion_block(xml: str, slot: int) -> re.Match[str]:
    m = re.search(
        rf'<Key xsi:type="xsd:string">M{slot:03d}</Key>.*?</DictionaryEntry>', xml, flags=re.S
    )
    assert m is not None
    return m


def motion_frames(xml: str, slot: int) -> list[str]:
    block = _motion_block(xml, slot).group(0)
    return re.findall(r'<anyType xsi:type="xsd:string">([^<]*)</anyType>', block)


def set_motion_frames(xml: str, slot: int, frames: list[str]) -> str:
    m = _motion_block(xml, slot)
    block = m.group(0)
    inner = "".join(f'\r\n          <anyType xsi:type="xsd:string">{f}</anyType>' for f in frames)
    block, n = re.subn(
        r"<MotionData>.*?</MotionData>",
        lambda _: f"<MotionData>{inner}\r\n        </MotionData>",
        block,
        count=1,
        flags=re.S,
    )
    assert n == 1
    return xml[: m.start()] + block + xml[m.end() :]


def set_button(xml: str, slot: int, buttons: int) -> str:
    m = _motion_block(xml, slot)
    block = re.sub(
        r"<ButtonData>\d+</ButtonData>", f"<ButtonData>{buttons}</ButtonData>", m.group(0)
    )
    return xml[: m.start()] + block + xml[m.end() :]


def with_checksum(data: bytes) -> str:
    """``data`` (SIZE..last payload byte) with its checksum, as HeartToHeart4 hex text."""
    return (data + bytes((sum(data) & 0xFF,))).hex(" ").upper()


def edit_frame(frame: str, **offsets: int) -> str:
    """Frame hex text with bytes replaced (``b7=0`` sets byte 7) and the checksum fixed."""
    data = bytearray(bytes.fromhex(frame))
    for name, value in offsets.items():
        data[int(name[1:])] = value
    return with_checksum(bytes(data[:-1]))


def frames_at(address: int, commands: list[object]) -> list[str]:
    """HeartToHeart4 frame texts of ``commands`` (Command objects or frame texts); a command
    given as ``callable(addresses)`` is built once every frame's address is known (forward
    jumps). ``address`` is where the first frame lands in ROM."""
    from rcb4hv.protocol import encode_command

    sizes = []
    for c in commands:
        if isinstance(c, str):
            sizes.append(len(bytes.fromhex(c)))
        elif callable(c):
            sizes.append(7)  # JUMP / CALL: 07 0B/0C A0 A1 A2 COND SUM
        else:
            sizes.append(len(encode_command(c)))  # type: ignore[arg-type]
    starts = [address + sum(sizes[:i]) for i in range(len(sizes))]
    out = []
    for c in commands:
        if isinstance(c, str):
            out.append(c)
            continue
        cmd = c(starts) if callable(c) else c
        out.append(encode_command(cmd).hex(" ").upper())  # type: ignore[arg-type]
    return out
