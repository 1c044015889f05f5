"""Golden byte vectors of spec section 14, in both directions."""

from __future__ import annotations

import pytest

from rcb4hv import protocol as p

H = bytes.fromhex

# (frame, the command it must decode to)
VECTORS: list[tuple[str, p.Command]] = [
    ("03 FE 01", p.AcknowledgeCheck()),
    ("04 FE 06 08", p.AcknowledgeCheck(long_form=True)),
    ("03 FD 00", p.GetVersionInfo()),
    ("03 0D 10", p.Return()),
    ("0A 00 20 00 00 00 00 00 02 2C", p.Move(p.Com(), p.Ram(0x0000), 2)),
    ("09 00 02 00 00 00 02 80 8D", p.Move(p.Ram(0x0000), p.Data(b"\x02\x80"))),
    ("0A 00 21 00 00 00 04 05 02 36", p.Move(p.Com(), p.Ics(4, 5), 2)),
    ("0B 00 23 00 00 00 80 0B 00 04 BD", p.Move(p.Com(), p.Rom(0x0B80), 4)),
    ("0A 00 32 80 0B 00 03 0D 10 E7", p.Move(p.Rom(0x0B80), p.Data(b"\x03\x0d\x10"))),
    ("07 0C 80 0B 00 00 9E", p.Call(0x0B80)),
    ("07 0B 4B 04 00 05 66", p.Jump(0x044B, p.Condition.if_zero())),
    ("09 06 02 62 04 00 05 00 7C", p.Add(p.Ram(0x0462), p.Data(b"\x05\x00"))),
    ("09 07 82 50 03 00 00 01 E6", p.Sub(p.Ram(0x0350), p.Data(b"\x00\x01"), no_write=True)),
    ("08 01 02 3A 00 00 0F 54", p.And(p.Ram(0x003A), p.Data(b"\x0f"))),
    ("0A 04 00 62 04 00 00 00 02 76", p.Not(p.Ram(0x0462), 2)),
    ("0A 05 00 62 04 00 00 01 02 78", p.Shift.right(p.Ram(0x0462), 1, 2)),
    ("0A 05 00 62 04 00 00 FF 02 76", p.Shift.left(p.Ram(0x0462), 1, 2)),
    ("07 0F 02 1E 4C 1D 9F", p.RunSingleServo(2, 30, 7500)),
    ("07 0F 02 01 00 80 99", p.RunSingleServo(2, 1, p.POSITION_FREE)),
    ("0D 10 01 02 00 00 00 0A 4C 1D 40 1F F2", p.RunConstFrameServo(10, {0: 7500, 9: 8000})),
    (
        "0E 11 08 00 00 00 01 05 B0 1D 06 14 1E 32",
        p.RunSeriesServo([(3, 5, 7600), (32, 6, 7700)]),
    ),
    ("0B 12 01 02 00 00 00 02 64 3C C2", p.SetSpeed({0: 100, 9: 60})),
    ("09 00 02 00 00 00 10 83 9E", p.Move(p.Ram(0), p.Data(b"\x10\x83"))),
    (
        "11 00 02 02 00 00 4B 04 00 00 00 00 00 00 00 00 64",
        p.Move(p.Ram(0x0002), p.Data(bytes.fromhex("4B 04 00 00 00 00 00 00 00 00"))),
    ),
]


@pytest.mark.parametrize(("frame", "command"), VECTORS, ids=[v[0] for v in VECTORS])
def test_encode_matches_golden_frame(frame: str, command: p.Command) -> None:
    assert p.encode_command(command) == H(frame)


@pytest.mark.parametrize(("frame", "command"), VECTORS, ids=[v[0] for v in VECTORS])
def test_decode_matches_golden_command(frame: str, command: p.Command) -> None:
    assert p.decode_command(H(frame)) == command


REPLIES: list[tuple[str, p.Command, p.Reply]] = [
    ("04 FE 06 08", p.AcknowledgeCheck(), p.Ack(0xFE)),
    ("04 FE 15 17", p.AcknowledgeCheck(), p.Nak(0xFE)),
    ("05 00 02 80 87", p.Move(p.Com(), p.Ram(0), 2), p.DataReply(0, b"\x02\x80")),
    ("04 00 06 0A", p.Move(p.Ram(0), p.Data(b"\x02\x80")), p.Ack(0)),
    ("04 10 06 1A", p.RunConstFrameServo(10, {0: 7500, 9: 8000}), p.Ack(0x10)),
    (
        "23 FD 43 42 2D 34 20 56 31 2E 30 20 20 20 20 20 20 30 39 30 37 31 35 "
        "20 20 20 20 20 20 20 20 20 20 C7 08",
        p.GetVersionInfo(),
        p.VersionReply(b"CB-4 V1.0      090715          \xc7"),
    ),
]


@pytest.mark.parametrize(("frame", "command", "reply"), REPLIES, ids=[r[0][:20] for r in REPLIES])
def test_reply_vectors(frame: str, command: p.Command, reply: p.Reply) -> None:
    assert p.decode_reply(H(frame), command) == reply
    assert p.encode_reply(reply) == H(frame)


def test_version_reply_text() -> None:
    reply = p.VersionReply(b"CB-4 V1.0      090715          \xc7")
    assert reply.text == "CB-4 V1.0      090715"


def test_checksum_of_every_vector() -> None:
    for frame, _ in VECTORS:
        f = H(frame)
        assert p.checksum(f[:-1]) == f[-1]
        assert f[0] == len(f)


def test_system_register_8002() -> None:
    reg = p.SystemRegister.from_word(0x8002)
    assert reg.rom_run and reg.led and not reg.ics_output
    assert reg.to_bytes() == b"\x02\x80"
