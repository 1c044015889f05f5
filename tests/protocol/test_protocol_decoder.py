"""The incremental frame decoder's contract, tested by brute force (whole, byte by byte, junk)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv import protocol as p
from rcb4hv.errors import ChecksumError, FrameError, ProtocolError
from tests.strategies import command_frames


def drain(decoder: p.FrameDecoder) -> tuple[list[bytes], int]:
    """All frames the decoder yields now, and how many protocol errors it raised on the way."""
    frames: list[bytes] = []
    errors = 0
    while True:
        try:
            out = decoder.next_frame()
        except ProtocolError:
            errors += 1
            continue
        if out is p.NEED_DATA:
            return frames, errors
        assert isinstance(out, bytes)
        frames.append(out)


@given(st.lists(command_frames, min_size=1, max_size=8))
def test_frames_fed_whole(frames: list[bytes]) -> None:
    d = p.FrameDecoder()
    d.receive_data(b"".join(frames))
    assert drain(d) == (frames, 0)
    assert d.pending == b""


@given(st.lists(command_frames, min_size=1, max_size=4))
def test_frames_fed_byte_by_byte(frames: list[bytes]) -> None:
    d = p.FrameDecoder()
    got: list[bytes] = []
    for byte in b"".join(frames):
        d.receive_data(bytes((byte,)))
        out, errors = drain(d)
        assert errors == 0
        got += out
    assert got == frames


@given(st.binary(max_size=400))
def test_random_bytes_whole_decode_or_raise_protocol_error(junk: bytes) -> None:
    d = p.FrameDecoder()
    d.receive_data(junk)
    frames, _ = drain(d)
    for f in frames:
        p.check_frame(f)
    assert len(d.pending) < p.MAX_FRAME_SIZE


@given(st.binary(max_size=200), st.sampled_from(["byte", "frame"]))
def test_random_bytes_byte_by_byte_bounded(junk: bytes, resync: str) -> None:
    d = p.FrameDecoder(resync=resync)  # type: ignore[arg-type]
    for byte in junk:
        d.receive_data(bytes((byte,)))
        for f in drain(d)[0]:
            p.check_frame(f)
        assert len(d.pending) < p.MAX_FRAME_SIZE


@given(st.binary(max_size=200))
def test_decode_command_on_random_bytes(junk: bytes) -> None:
    try:
        cmd = p.decode_command(junk)
    except ProtocolError:
        return
    assert p.encode_command(cmd) == junk


@given(st.binary(min_size=1, max_size=60), command_frames)
def test_byte_resync_finds_a_frame_after_junk(junk: bytes, frame: bytes) -> None:
    """With resync='byte' a valid frame after stray bytes is found (the client's case).

    A junk size byte may claim up to 128 bytes (and, the checksum being 8 bits, junk can even
    form a valid-looking frame), so recovery is guaranteed once that many bytes that cannot
    start a frame (here zeros) separate the junk from the frame.
    """
    d = p.FrameDecoder()
    d.receive_data(junk + bytes(p.MAX_FRAME_SIZE) + frame)
    frames, _ = drain(d)
    assert frames and frames[-1] == frame
    assert d.pending == b""


def test_size_byte_rules() -> None:
    d = p.FrameDecoder()
    d.receive_data(b"\x02\x81" + p.encode_command(p.Return()))
    with pytest.raises(FrameError):
        d.next_frame()
    with pytest.raises(FrameError):
        d.next_frame()
    assert d.next_frame() == b"\x03\x0d\x10"
    assert d.next_frame() is p.NEED_DATA


def test_checksum_resync_modes() -> None:
    bad = b"\x07\x0f\x02\x1e\x4c\x1d\x00"
    for mode, left in (("byte", bad[1:]), ("frame", b"")):
        d = p.FrameDecoder(resync=mode)  # type: ignore[arg-type]
        d.receive_data(bad)
        with pytest.raises(ChecksumError) as info:
            d.next_frame()
        assert info.value.frame == bad
        assert d.pending == left


def test_reset_returns_partial() -> None:
    d = p.FrameDecoder()
    d.receive_data(b"\x07\x0f\x02")
    assert d.next_frame() is p.NEED_DATA
    assert d.reset() == b"\x07\x0f\x02"
    assert d.pending == b""


def test_max_size_for_replies() -> None:
    reply = p.encode_reply(p.DataReply(0, bytes(126)))
    d = p.FrameDecoder()
    d.receive_data(reply)
    with pytest.raises(FrameError):
        d.next_frame()
    d = p.FrameDecoder(max_size=p.MAX_REPLY_SIZE)
    d.receive_data(reply)
    assert d.next_frame() == reply


def test_protocol_core_imports_no_io() -> None:
    code = (
        "import sys, rcb4hv.protocol, rcb4hv.errors\n"
        "bad = sorted(m for m in ('serial', 'socket', 'threading', 'select', 'asyncio')"
        " if m in sys.modules)\n"
        "print(','.join(bad))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=60
    ).stdout.strip()
    assert out == "", f"protocol core pulled in: {out}"


def test_protocol_sources_import_nothing_with_io_or_clocks() -> None:
    """``time`` is loaded by the interpreter itself, so check the sources' imports too."""
    import ast
    from pathlib import Path

    # struct and zlib compute only (precompiled frame layouts, the C byte sum of adler32)
    allowed = {"__future__", "collections", "dataclasses", "typing", "enum", "rcb4hv"}
    allowed |= {"struct", "zlib"}
    pkg = Path(p.__file__).parent
    for path in sorted(pkg.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = [node.module or ""]
            else:
                continue
            for name in names:
                assert name.split(".")[0] in allowed, f"{path.name} imports {name}"


@given(st.binary(max_size=40), command_frames, st.binary(max_size=40))
def test_frame_at_reads_the_frame_at_an_offset(head: bytes, frame: bytes, tail: bytes) -> None:
    data = head + frame + tail
    assert p.frame_at(data, len(head)) == frame
    assert p.frame_at(bytearray(data), len(head)) == frame


def test_frame_at_errors() -> None:
    ret = b"\x03\x0d\x10"
    with pytest.raises(FrameError):
        p.frame_at(ret + b"\xff", 3)  # erased ROM
    with pytest.raises(FrameError):
        p.frame_at(ret, 3)  # offset outside the data
    with pytest.raises(FrameError):
        p.frame_at(b"\x07\x0f\x02", 0)  # runs past the end
    with pytest.raises(ChecksumError):
        p.frame_at(b"\x03\x0d\x11", 0)
