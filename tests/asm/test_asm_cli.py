"""``rcb4hv asm`` and ``rcb4hv disasm``."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.asm import assemble
from rcb4hv.cli.main import cli
from rcb4hv.hth4 import load_project
from rcb4hv.rom import default_image

SOURCE = """\
        .org $000B80
loop:   SUB.NW RAM[BUTTONS], #00 01
        JUMP loop IF NZ
        RETURN
"""


def test_asm_prints_hex_frames(tmp_path: Path) -> None:
    src = tmp_path / "m.s"
    src.write_text(SOURCE)
    result = CliRunner().invoke(cli, ["asm", str(src)])
    assert result.exit_code == 0, result.stderr
    assert result.stdout.splitlines() == [
        "000B80  09 07 82 50 03 00 00 01 E6",
        "000B89  07 0B 80 0B 00 04 A1",
        "000B90  03 0D 10",
    ]


def test_asm_writes_binary_and_hex(tmp_path: Path) -> None:
    src = tmp_path / "m.s"
    src.write_text("RETURN\nCALL $FFFFFF\n")
    out = tmp_path / "m.bin"
    result = CliRunner().invoke(cli, ["asm", str(src), "-o", str(out), "--origin", "0x0B80"])
    assert result.exit_code == 0, result.stderr
    assert out.read_bytes() == bytes.fromhex("03 0D 10 07 0C FF FF FF 00 10")
    assert "10 bytes at $000B80" in result.stderr
    hex_out = tmp_path / "m.hex"
    result = CliRunner().invoke(cli, ["asm", str(src), "-o", str(hex_out), "--hex"])
    assert result.exit_code == 0
    assert hex_out.read_text() == "000000  03 0D 10\n000003  07 0C FF FF FF 00 10\n"


def test_asm_reads_stdin() -> None:
    result = CliRunner().invoke(cli, ["asm", "-"], input="VERSION\n")
    assert result.exit_code == 0
    assert result.stdout == "000000  03 FD 00\n"


def test_asm_error_is_one_line_with_position(tmp_path: Path) -> None:
    src = tmp_path / "bad.s"
    src.write_text("RETURN\n  JUMP nowhere\n")
    result = CliRunner().invoke(cli, ["asm", str(src)])
    assert result.exit_code == 1
    assert result.stderr == f"error: {src}:2:8: undefined label 'nowhere'\n"
    assert result.stdout == ""


def test_asm_missing_file(tmp_path: Path) -> None:
    result = CliRunner().invoke(cli, ["asm", str(tmp_path / "nope.s")])
    assert result.exit_code == 1
    assert result.stderr.startswith("error: ") and "nope.s" in result.stderr


def test_disasm_hex_words() -> None:
    result = CliRunner().invoke(
        cli, ["disasm", "--no-comments", "--origin", "$00044B", "07 0B 4B 04 00 05 66"]
    )
    assert result.exit_code == 0, result.stderr
    assert result.stdout == "    .org $00044B\nL_00044B:\n    JUMP L_00044B IF Z\n"
    result = CliRunner().invoke(
        cli, ["disasm", "--no-comments", "--no-labels", "--no-symbols", "09078250030000", "01E6"]
    )
    assert result.stdout == "    .org $000000\n    SUB.NW RAM[0x0350], #00 01\n"


def test_disasm_hex_file_and_bin(tmp_path: Path) -> None:
    hex_file = tmp_path / "f.hex"
    hex_file.write_text("# a motion\n07 0C 80 0B 00 00 9E  # CALL\n03 0D 10\n")
    result = CliRunner().invoke(cli, ["disasm", "--hex-file", str(hex_file)])
    assert result.exit_code == 0, result.stderr
    assert "CALL $000B80" in result.stdout and "RETURN" in result.stdout
    bin_file = tmp_path / "f.bin"
    bin_file.write_bytes(bytes.fromhex("07 0C 80 0B 00 00 9E 03 0D 10 FF"))
    out = tmp_path / "f.s"
    result = CliRunner().invoke(
        cli, ["disasm", "--bin", str(bin_file), "--origin", "0x0B80", "-o", str(out)]
    )
    assert result.exit_code == 0
    text = out.read_text()
    assert "L_000B80:" in text and "CALL L_000B80" in text
    assert assemble(text).data == bin_file.read_bytes()


def test_disasm_project_motion(kxr_project_path: Path) -> None:
    result = CliRunner().invoke(
        cli, ["disasm", "--project", str(kxr_project_path), "--motion", "1"]
    )
    assert result.exit_code == 0, result.stderr
    m = load_project(kxr_project_path).motion(1)
    assert result.stdout.startswith("; motion 1")
    program = assemble(result.stdout)
    assert program.origin == m.address and program.data == m.rom_bytes()


def test_disasm_project_errors(kxr_project_path: Path) -> None:
    runner = CliRunner()
    result = runner.invoke(cli, ["disasm", "--project", str(kxr_project_path), "--motion", "120"])
    assert result.exit_code == 1 and "motion slot 120 is empty" in result.stderr
    result = runner.invoke(cli, ["disasm", "--project", str(kxr_project_path)])
    assert result.exit_code == 1 and "--project and --motion go together" in result.stderr


def test_disasm_image(tmp_path: Path) -> None:
    image = tmp_path / "rom.bin"
    image.write_bytes(default_image())
    result = CliRunner().invoke(cli, ["disasm", "--image", str(image)])
    assert result.exit_code == 0, result.stderr
    assert "main_loop:" in result.stdout
    assert assemble(result.stdout).image() == image.read_bytes()
    image.write_bytes(b"\xff" * 10)
    result = CliRunner().invoke(cli, ["disasm", "--image", str(image)])
    assert result.exit_code == 1 and "262144" in result.stderr


def test_disasm_input_errors() -> None:
    runner = CliRunner()
    result = runner.invoke(cli, ["disasm"])
    assert result.exit_code == 1 and "give exactly one input" in result.stderr
    result = runner.invoke(cli, ["disasm", "0G"])
    assert result.exit_code == 1 and result.stderr.startswith("error: ")
    result = runner.invoke(cli, ["disasm", "--origin", "zz", "03 0D 10"])
    assert result.exit_code != 0 and "not an address" in result.stderr
    result = runner.invoke(cli, ["disasm", "--origin", "0x40000", "03 0D 10"])
    assert result.exit_code == 1 and "origin" in result.stderr


def test_an_image_disassembled_assembles_back_to_the_same_image(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """`disasm --image` then `asm --image`: the 256 KB image, byte for byte (asm wrote the
    program's bytes only, 248708 of them, which `disasm --image` and `upload` refuse)."""
    rom, text, back = tmp_path / "rom.bin", tmp_path / "rom.s", tmp_path / "rom2.bin"
    runner = CliRunner()
    assert (
        runner.invoke(cli, ["project", "build", str(kxr_project_path), "-o", str(rom)]).exit_code
        == 0
    )
    assert runner.invoke(cli, ["disasm", "--image", str(rom), "-o", str(text)]).exit_code == 0
    r = runner.invoke(cli, ["asm", str(text), "--image", "-o", str(back)])
    assert r.exit_code == 0, r.output
    assert back.read_bytes() == rom.read_bytes()


@pytest.mark.parametrize(
    ("source", "folder", "ok"),
    [
        (bytes(range(128, 256)), "", False),  # a ROM image given as the source
        (b"RETURN\n", "no/such/dir", False),  # the output in a missing folder
        (b"\xef\xbb\xbfRETURN\n", "", True),  # a byte-order mark is no statement
    ],
)
def test_asm_says_what_is_wrong_in_one_line(
    source: bytes, folder: str, ok: bool, tmp_path: Path
) -> None:
    """A binary source and an output in a missing folder printed tracebacks; a byte-order
    mark was an error."""
    src = tmp_path / "walk.s"
    src.write_bytes(source)
    r = CliRunner().invoke(cli, ["asm", str(src), "-o", str(tmp_path / folder / "x.bin")])
    if ok:
        assert r.exit_code == 0, r.output
    else:
        assert r.exit_code == 1 and r.output.startswith("error: "), r.output
        assert r.output.count("\n") == 1, r.output


def test_asm_hex_round_trips_through_disasm_hex_file(tmp_path: Path) -> None:
    """Was: disasm read asm's address column as data (.byte 00 0B 80, every address wrong)."""
    src = tmp_path / "m.s"
    src.write_text(SOURCE)
    runner = CliRunner()
    hex_out, bin_out = tmp_path / "m.hex", tmp_path / "m.bin"
    assert runner.invoke(cli, ["asm", str(src), "--hex", "-o", str(hex_out)]).exit_code == 0
    assert runner.invoke(cli, ["asm", str(src), "-o", str(bin_out)]).exit_code == 0
    from_hex = runner.invoke(cli, ["disasm", "--hex-file", str(hex_out)])
    from_bin = runner.invoke(cli, ["disasm", "--bin", str(bin_out), "--origin", "0x0B80"])
    assert from_hex.exit_code == 0, from_hex.stderr
    assert from_hex.stdout == from_bin.stdout
    assert ".org $000B80" in from_hex.stdout and ".byte" not in from_hex.stdout
    again = tmp_path / "again.s"
    again.write_text(from_hex.stdout)
    back = runner.invoke(cli, ["asm", str(again), "-o", str(tmp_path / "b2.bin")])
    assert back.exit_code == 0 and (tmp_path / "b2.bin").read_bytes() == bin_out.read_bytes()


@pytest.mark.parametrize(
    ("text", "extra", "words"),
    [
        ("000B80  03 0D 10\n000B90  03 0D 10\n", [], "address $000B90 does not follow"),
        ("000B80  03 0D 10\n03 0D 10\n", [], "line 2 has no address column"),
        ("000B80  03 0D 10\n", ["--origin", "0"], "--origin $000000 disagrees"),
    ],
)
def test_disasm_hex_file_refuses_inconsistent_addresses(
    tmp_path: Path, text: str, extra: list[str], words: str
) -> None:
    f = tmp_path / "m.hex"
    f.write_text(text)
    result = CliRunner().invoke(cli, ["disasm", "--hex-file", str(f), *extra])
    assert result.exit_code == 1 and words in result.stderr


def test_disasm_hex_file_without_addresses_still_reads_bytes(tmp_path: Path) -> None:
    f = tmp_path / "m.hex"
    f.write_text("03 0D 10  # RETURN\n070C FFFFFF0010\n")
    result = CliRunner().invoke(cli, ["disasm", "--hex-file", str(f), "--origin", "0x0B80"])
    assert result.exit_code == 0 and "RETURN" in result.stdout and "CALL" in result.stdout
