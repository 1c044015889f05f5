"""Fuzzing the protocol core: nothing but the documented exception types ever escapes.

The budget follows the hypothesis profile: small in `make test`, large in `make fuzz`
(HYPOTHESIS_PROFILE=fuzz, RCB4HV_FUZZ_EXAMPLES=N).
"""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rcb4hv import protocol as p
from rcb4hv.errors import ChecksumError, FrameError, ProtocolError
from tests.reliability.mutations import hostile_input, mutated_frames


@given(hostile_input)
def test_fuzz_decode_command(data: bytes) -> None:
    try:
        cmd = p.decode_command(data)
    except ProtocolError:
        return
    assert p.encode_command(cmd) == data


@given(hostile_input, st.sampled_from(["byte", "frame"]), st.integers(1, 17))
def test_fuzz_frame_decoder_in_chunks(data: bytes, resync: str, chunk: int) -> None:
    decoder = p.FrameDecoder(resync=resync)  # type: ignore[arg-type]
    consumed = 0
    for i in range(0, len(data), chunk):
        decoder.receive_data(data[i : i + chunk])
        while True:
            try:
                frame = decoder.next_frame()
            except (FrameError, ChecksumError):
                continue
            if frame is p.NEED_DATA:
                break
            assert isinstance(frame, bytes)
            p.check_frame(frame)
            consumed += len(frame)
        assert len(decoder.pending) < p.MAX_FRAME_SIZE + chunk
    assert consumed <= len(data)


@given(mutated_frames)
def test_fuzz_reply_decoder(data: bytes) -> None:
    """Replies to every kind of expectation: only ProtocolError may escape."""
    for cmd in (p.AcknowledgeCheck(), p.Move(p.Com(), p.Ram(0), 2), p.GetVersionInfo()):
        try:
            reply = p.decode_reply(data, cmd)
        except ProtocolError:
            continue
        assert p.encode_reply(reply) == data
