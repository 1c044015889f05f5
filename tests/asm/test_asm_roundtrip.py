"""disassemble -> assemble is byte-exact: fixture motions, random frames and bytes, images."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv import protocol as p
from rcb4hv.asm import assemble, disassemble, disassemble_frames, disassemble_image
from rcb4hv.hth4 import load_project
from rcb4hv.rom import default_image, layout
from tests.strategies import command_frames

OPTIONS = [
    {},
    {"labels": False},
    {"comments": False},
    {"symbols": False, "labels": False, "comments": False},
]


@pytest.mark.parametrize("options", OPTIONS, ids=["default", "no-labels", "bare", "raw"])
def test_every_fixture_motion_round_trips_at_its_address(
    kxr_project_path: Path, options: dict[str, bool]
) -> None:
    project = load_project(kxr_project_path)
    motions = [m for m in project.motions if not m.is_empty]
    assert len(motions) > 50
    for m in motions:
        text = disassemble_frames(m.frames, m.address, **options)
        program = assemble(text)
        assert program.origin == m.address, m.slot
        assert program.data == m.rom_bytes(), m.slot
        # every frame came back as a command, the FF markers as data
        assert b"".join(program.frames) == b"".join(f[: f[0]] for f in m.frames), m.slot
        assert text.count(".byte FF") == sum(1 for f in m.frames if len(f) == f[0] + 1)


def test_fixture_motion_uses_labels_and_marker(kxr_project_path: Path) -> None:
    m = load_project(kxr_project_path).motion(1)
    text = disassemble_frames(m.frames, m.address)
    assert "    JUMP L_000CCD IF Z" in text
    assert "L_000CCD:" in text
    assert "SUB.NW RAM[BUTTONS], #00 01" in text
    assert "end-of-motion marker" in text.splitlines()[-1]


_chunks = st.lists(
    st.one_of(command_frames, st.binary(min_size=1, max_size=20)), min_size=0, max_size=12
)


@settings(max_examples=120)
@given(chunks=_chunks, origin=st.integers(0, p.ROM_SIZE - 4096))
def test_any_bytes_round_trip(chunks: list[bytes], origin: int) -> None:
    data = b"".join(chunks)
    text = disassemble(data, origin)
    program = assemble(text)
    assert program.origin == origin
    assert program.data == data
    # a fixed point: the text of the assembled bytes is the same text
    assert disassemble(program.data, origin) == text


@settings(max_examples=60)
@given(frames=st.lists(command_frames, min_size=1, max_size=8))
def test_frames_come_back_as_the_same_commands(frames: list[bytes]) -> None:
    program = assemble(disassemble_frames(frames, 0x0B80, comments=False, symbols=False))
    assert program.frames == frames
    assert program.commands == [p.decode_command(f) for f in frames]


@settings(max_examples=60)
@given(frames=st.lists(command_frames, min_size=1, max_size=8), origin=st.integers(0, 0x3F000))
def test_assemble_disassemble_is_stable(frames: list[bytes], origin: int) -> None:
    text1 = disassemble_frames(frames, origin)
    first = assemble(text1)
    text2 = disassemble(first.data, origin)
    second = assemble(text2)
    assert second.data == first.data == b"".join(frames)
    assert text2 == text1


def test_unresolved_target_ffffff_round_trips() -> None:
    frame = p.encode_command(p.Call(0xFFFFFF))
    text = disassemble(frame + b"\x03\x0d\x10", 0x0B80)
    assert "CALL $FFFFFF" in text
    assert assemble(text).data == frame + b"\x03\x0d\x10"


def test_default_image_round_trips() -> None:
    image = default_image()
    text = disassemble_image(image)
    assert assemble(text).image() == image
    assert "main_loop:" in text and "JUMP main_loop" in text
    assert "; ==== 0005DC-0005DD system register value" in text
    assert "; ==== 000B80-00137F motion 1" in text
    assert "empty (erased)" in text


def test_image_with_fixture_motions_round_trips(kxr_project_path: Path) -> None:
    image = bytearray(default_image())
    used = []
    for m in load_project(kxr_project_path).motions:
        if not m.is_empty and m.address == layout.motion_address(m.slot):
            data = m.rom_bytes()
            image[m.address : m.address + len(data)] = data
            used.append(m.slot)
    text = disassemble_image(bytes(image))
    assert assemble(text).image() == bytes(image)
    for slot in used:
        assert f"motion {slot}\n" in text
        assert f"motion_{slot}:" in text


@settings(max_examples=8)
@given(
    patches=st.lists(
        st.tuples(st.integers(0, p.ROM_SIZE - 64), st.binary(min_size=1, max_size=64)),
        max_size=6,
    )
)
def test_patched_images_round_trip(patches: list[tuple[int, bytes]]) -> None:
    image = bytearray(default_image())
    for at, data in patches:
        image[at : at + len(data)] = data
    assert assemble(disassemble_image(bytes(image))).image() == bytes(image)


def test_disassemble_image_wants_256k() -> None:
    with pytest.raises(ValueError, match="262144"):
        disassemble_image(b"\xff" * 100)


@pytest.mark.parametrize("fill", [0x00, 0xFF])
def test_labels_inside_long_runs(fill: int) -> None:
    jumps = p.encode_command(p.Jump(0x0B80 + 14 + 20)) + p.encode_command(p.Call(0x0B80 + 14 + 40))
    data = jumps + bytes([fill]) * 64
    text = disassemble(data, 0x0B80)
    assert "L_000BA2:" in text and "L_000BB6:" in text
    assert assemble(text).data == data
    image = bytearray(default_image())
    start = layout.motion_address(120)
    image[start : start + len(data)] = data
    image_text = disassemble_image(bytes(image))
    assert assemble(image_text).image() == bytes(image)


def test_a_frame_with_a_bad_checksum_is_named_and_round_trips() -> None:
    """A damaged command frame is kept as bytes (it must assemble back the same) with a note
    that it is a frame with a bad checksum, not data (it became plain ``.byte`` before)."""
    good = bytes.fromhex("070B4B04000566")
    bad = good[:-1] + b"\x67"
    text = disassemble(bad + bytes.fromhex("030D10"))
    assert "000000: 7-byte frame with a bad checksum 67 (the sum is 66)" in text
    assert "RETURN" in text
    assert assemble(text).data == bad + bytes.fromhex("030D10")
    assert "bad checksum" not in disassemble(good)
    # bytes that are no frame whatever their sum get no such note
    assert "bad checksum" not in disassemble(bytes.fromhex("07FF4B04000567"))
