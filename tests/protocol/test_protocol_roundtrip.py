"""Property-based round trips of every encoder/decoder in the protocol core."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rcb4hv import protocol as p
from rcb4hv.errors import ProtocolError
from tests.strategies import command_frames, commands


@given(commands)
def test_decode_of_encode_is_identity(cmd: p.Command) -> None:
    frame = p.encode_command(cmd)
    assert frame[0] == len(frame) <= p.MAX_FRAME_SIZE
    assert p.checksum(frame[:-1]) == frame[-1]
    assert p.decode_command(frame) == cmd


@given(command_frames)
def test_encode_of_decode_is_identity(frame: bytes) -> None:
    assert p.encode_command(p.decode_command(frame)) == frame


@given(st.integers(0, 0xFF), st.binary(max_size=125))
def test_any_checksummed_frame_decodes_exactly_or_raises_protocol_error(
    cmd: int, payload: bytes
) -> None:
    frame = p.build_frame(cmd, payload)
    try:
        decoded = p.decode_command(frame)
    except ProtocolError:
        return
    assert p.encode_command(decoded) == frame


@given(st.sampled_from(sorted({0x00, 0x01, 0x06, 0x07, 0x0F, 0x10, 0x11, 0x12})), st.binary())
def test_command_shaped_frames_never_raise_anything_else(cmd: int, payload: bytes) -> None:
    frame = p.build_frame(cmd, payload)[:-1] + b"\x00"
    try:
        decoded = p.decode_command(frame)
    except ProtocolError:
        return
    assert p.encode_command(decoded) == frame


@given(st.integers(0, 0xFFFF))
def test_system_register_round_trip(word: int) -> None:
    reg = p.SystemRegister.from_word(word)
    assert reg.to_word() == word
    assert p.SystemRegister.from_bytes(reg.to_bytes()) == reg
    assert reg.frame_period_ms in p.FRAME_PERIODS_MS


@given(st.binary(min_size=20, max_size=20))
def test_servo_block_round_trip(raw: bytes) -> None:
    block = p.ServoBlock.from_bytes(raw)
    assert block.to_bytes() == raw


@given(st.sets(st.integers(0, 35)), st.booleans())
def test_bitmap_round_trip(ics: set[int], keep: bool) -> None:
    bitmap = p.bitmap_from_ics(ics, keep)
    assert len(bitmap) == 5
    assert p.ics_from_bitmap(bitmap) == sorted(ics)
    assert bool(bitmap[4] & 0x80) == keep


@given(st.integers(0, 0x0F))
def test_condition_round_trip(byte: int) -> None:
    assert p.Condition.from_byte(byte).to_byte() == byte


@given(st.sampled_from([p.Ack, p.Nak]), st.integers(0, 0xFF))
def test_ack_nak_reply_round_trip(kind: type[p.Ack] | type[p.Nak], cmd: int) -> None:
    class _Cmd:
        reply_data_size = None

    _Cmd.cmd = cmd  # type: ignore[attr-defined]
    reply = kind(cmd)
    assert p.decode_reply(p.encode_reply(reply), _Cmd()) == reply  # type: ignore[arg-type]


@given(st.integers(2, 128), st.data())
def test_data_reply_round_trip(size: int, data: st.DataObject) -> None:
    cmd = p.Move(p.Com(), p.Ram(0), size)
    payload = data.draw(st.binary(min_size=size, max_size=size))
    frame = p.encode_reply(p.DataReply(0, payload))
    assert len(frame) == p.reply_length(cmd)
    assert p.decode_reply(frame, cmd) == p.DataReply(0, payload)
    assert p.decode_reply(p.encode_reply(p.Nak(0)), cmd) == p.Nak(0)
