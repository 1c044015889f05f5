"""``project image``: slots holding garbage, the settings and the layout it shows."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.project.image import read_image
from rcb4hv.rom import default_image, layout
from rcb4hv.rom.layout import LAYOUTS

GARBAGE = bytes((0x5A + 7 * i) % 0xF0 for i in range(64))  # never FF (erased)


def _damaged(image: bytes) -> tuple[bytes, int, int]:
    """``image`` with slot 1 garbage from its first byte and slot 2 after its first frame."""
    rom = bytearray(image)
    one, two = layout.motion_address(1), layout.motion_address(2)
    rom[one : one + len(GARBAGE)] = GARBAGE
    after = two + rom[two]
    rom[after : after + len(GARBAGE)] = GARBAGE
    return bytes(rom), one, after


def test_a_slot_holding_garbage_is_listed_not_dropped(kxr_image: bytes, tmp_path: Path) -> None:
    """A slot that is not erased but does not decode was left out of ``project image`` without
    a word ("64 motions", rc 0); it is listed with where and why it stops decoding."""
    rom, one, after = _damaged(kxr_image)
    assert read_image(kxr_image).undecoded == ()
    clean = {m.slot: m for m in read_image(kxr_image).motions}
    c = read_image(rom)
    assert [(u.slot, u.at) for u in c.undecoded] == [(1, one), (2, after)]
    assert all("checksum" in u.reason or "size byte" in u.reason for u in c.undecoded)
    assert 1 not in {m.slot for m in c.motions}  # no frame: no motion, but listed above
    assert len(c.motion(2).frames) == 2  # the frame before the garbage (and a RETURN)
    assert {m.slot: m for m in c.motions if m.slot > 2} == {n: m for n, m in clean.items() if n > 2}

    path = tmp_path / "corrupt.bin"
    path.write_bytes(rom)
    r = CliRunner().invoke(cli, ["project", "image", str(path)])
    assert r.exit_code == 0, r.output
    assert "2 slots that do not decode" in r.output
    (row1,) = [line for line in r.output.splitlines() if line.lstrip().startswith("1  00B80")]
    assert f"does not decode from {one:05X}h" in row1
    (row2,) = [line for line in r.output.splitlines() if line.lstrip().startswith("2  01380")]
    assert f"does not decode from {after:05X}h" in row2
    r = CliRunner().invoke(cli, ["project", "image", str(path), "--json"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    assert [(u["slot"], u["at"]) for u in data["undecoded_slots"]] == [
        (1, f"{one:05X}"),
        (2, f"{after:05X}"),
    ]
    assert "does not decode" in data["undecoded_slots"][0]["note"]
    assert [m["slot"] for m in data["motions"]] == [n for n in sorted(clean) if n != 1]


def test_image_shows_its_settings_and_layout(kxr_image: bytes, tmp_path: Path) -> None:
    """``project image`` printed no startup / priority settings (``project info`` does) and its
    --json did not say which layout it read the image in."""
    path = tmp_path / "kxr.bin"
    path.write_bytes(kxr_image)
    r = CliRunner().invoke(cli, ["project", "image", str(path)])
    assert r.exit_code == 0, r.output
    lines = r.output.splitlines()
    assert "HeartToHeart4 2.2 layout" in lines[0]
    assert lines[1:3] == [
        "startup motion: 13B80h (slot 39)",
        "priority check 0: Battery LessThan 224 -> 14380h (slot 40)",  # AD0 <= 223 as stored
    ]
    for version in ("2.2", "2.1", "1.3"):
        path.write_bytes(default_image(LAYOUTS[version]))
        r = CliRunner().invoke(cli, ["project", "image", str(path), "--json"])
        assert r.exit_code == 0, r.output
        assert json.loads(r.output)["layout"] == version
        r = CliRunner().invoke(cli, ["project", "image", str(path)])
        assert f"HeartToHeart4 {version} layout" in r.output
        assert "startup motion: none" in r.output
