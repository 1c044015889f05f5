"""Golden bytes: the exact frames the client methods send (spec section 14 vectors)."""

from __future__ import annotations

import math

import pytest

from rcb4hv.client import Rcb4Client, Robot, ServoInfo
from rcb4hv.protocol import Condition, Data, Ram, Rom, ServoBlock
from rcb4hv.rom.layout import HTH4_22
from tests.client.scripted import ScriptedTransport

H = bytes.fromhex


@pytest.mark.parametrize(
    ("call", "frame", "reply"),
    [
        (lambda c: c.acknowledge_check(), "03 FE 01", "04 FE 06 08"),
        (lambda c: c.acknowledge_check(long_form=True), "04 FE 06 08", "04 FE 06 08"),
        (lambda c: c.return_(), "03 0D 10", "04 0D 06 17"),
        (lambda c: c.read_ram(0, 2), "0A 00 20 00 00 00 00 00 02 2C", "05 00 02 80 87"),
        (lambda c: c.write_ram(0, H("0280")), "09 00 02 00 00 00 02 80 8D", "04 00 06 0A"),
        (
            lambda c: c.read_rom(0x0B80, 4),
            "0B 00 23 00 00 00 80 0B 00 04 BD",
            "07 00 03 0D 10 00 27",
        ),
        (
            lambda c: c.move(Rom(0x0B80), Data(H("030D10"))),
            "0A 00 32 80 0B 00 03 0D 10 E7",
            "04 00 06 0A",
        ),
        (lambda c: c.call(0x0B80), "07 0C 80 0B 00 00 9E", "04 0C 06 16"),
        (lambda c: c.jump(0x044B, Condition.if_zero()), "07 0B 4B 04 00 05 66", "04 0B 06 15"),
        (
            lambda c: c.add(Ram(0x0462), Data(H("0500"))),
            "09 06 02 62 04 00 05 00 7C",
            "05 06 05 00 10",
        ),
        (
            lambda c: c.sub(Ram(0x0350), Data(H("0001")), no_write=True),
            "09 07 82 50 03 00 00 01 E6",
            "05 07 00 FF 0B",
        ),
        (lambda c: c.and_(Ram(0x003A), Data(H("0F"))), "08 01 02 3A 00 00 0F 54", "04 01 05 0A"),
        (lambda c: c.not_(Ram(0x0462), 2), "0A 04 00 62 04 00 00 00 02 76", "05 04 FF FF 07"),
        (lambda c: c.shift(Ram(0x0462), 2, 1), "0A 05 00 62 04 00 00 01 02 78", "05 05 00 00 0A"),
        (
            lambda c: c.shift(Ram(0x0462), 2, 0xFF),
            "0A 05 00 62 04 00 00 FF 02 76",
            "05 05 00 00 0A",
        ),
        (lambda c: c.run_single_servo(2, 30, 7500), "07 0F 02 1E 4C 1D 9F", "04 0F 06 19"),
        (lambda c: c.run_single_servo(2, 1, 0x8000), "07 0F 02 01 00 80 99", "04 0F 06 19"),
        (
            lambda c: c.run_const_frame_servo(10, {0: 7500, 9: 8000}),
            "0D 10 01 02 00 00 00 0A 4C 1D 40 1F F2",
            "04 10 06 1A",
        ),
        (
            lambda c: c.run_series_servo([(3, 5, 7600), (32, 6, 7700)]),
            "0E 11 08 00 00 00 01 05 B0 1D 06 14 1E 32",
            "04 11 06 1B",
        ),
        (lambda c: c.set_speed({0: 100, 9: 60}), "0B 12 01 02 00 00 00 02 64 3C C2", "04 12 06 1C"),
    ],
)
def test_client_sends_spec_vector(call: object, frame: str, reply: str) -> None:
    t = ScriptedTransport(H(reply))
    client = Rcb4Client(t, timeout=0.2)
    call(client)  # type: ignore[operator]
    assert t.writes == [H(frame)]


def test_results_are_typed() -> None:
    t = ScriptedTransport(
        H("05 06 05 00 10"),
        H("04 01 05 0A"),
        H(
            "23 FD 43 42 2D 34 20 56 31 2E 30 20 20 20 20 20 20 30 39 30 37 31 35 20 20 20 20 20 "
            "20 20 20 20 20 C7 08"
        ),
    )
    c = Rcb4Client(t, timeout=0.2)
    assert c.add(Ram(0x0462), Data(H("0500"))) == 5
    assert c.and_(Ram(0x003A), Data(H("0F"))) == b"\x05"
    v = c.get_version_info()
    assert v.text == "CB-4 V1.0      090715"
    assert v.version[-1] == 0xC7


def test_play_motion_sends_the_hth4_sequence() -> None:
    """Spec 11.4: suspend, reset PC to 044B, CALL 0B80, resume with ICS_F|ROM_F|VEC_F."""
    ack0 = H("04 00 06 0A")
    t = ScriptedTransport(H("05 00 1B 80 A0"), ack0, ack0, H("04 0C 06 16"), ack0)
    Robot(Rcb4Client(t, timeout=0.2), layout=HTH4_22).play_motion(1)
    assert t.writes == [
        H("0A 00 20 00 00 00 00 00 02 2C"),  # read the system register (801B)
        H("09 00 02 00 00 00 10 80 9B"),  # ICS_F, ROM_F, VEC_F cleared
        H("11 00 02 02 00 00 4B 04 00 00 00 00 00 00 00 00 64"),
        H("07 0C 80 0B 00 00 9E"),
        H("09 00 02 00 00 00 1B 80 A6"),
    ]


def test_hold_free_and_timed_move_frames() -> None:
    ack = H("04 10 06 1A")
    t = ScriptedTransport(ack, ack, ack)
    robot = Robot(Rcb4Client(t, timeout=0.2))
    robot._servos = {k: ServoInfo(k, 0x90 + 20 * k, ServoBlock()) for k in (0, 2, 4)}
    robot._period = 0.015
    robot.hold()
    robot.free([0, 2, 4])
    robot.move({0: 8000, 2: 7000}, duration=0.15)  # 10 output periods of 15 ms
    assert t.writes == [
        H("0f 10 15 00 00 00 00 01 ff 7f ff 7f ff 7f af"),
        H("0f 10 15 00 00 00 00 01 00 80 00 80 00 80 b5"),
        H("0d 10 05 00 00 00 00 0a 40 1f 58 1b fe"),
    ]


def test_robot_validates_before_sending() -> None:
    t = ScriptedTransport()
    robot = Robot(Rcb4Client(t, timeout=0.2))
    robot._servos = {0: ServoInfo(0, 0x90, ServoBlock())}
    robot._period = 0.010
    with pytest.raises(ValueError, match=r"outside 3500\.\.11500"):
        robot.move({0: 12000})
    with pytest.raises(ValueError, match="255 periods"):
        robot.move({0: 7500}, duration=3.0)
    with pytest.raises(ValueError, match="no servo at ICS"):
        robot.free([5])
    with pytest.raises(ValueError):
        robot.move_angles({0: 200.0})
    with pytest.raises(ValueError):
        robot.set_pa(5, 1)
    with pytest.raises(ValueError):
        robot.client.read_ram(0x48F, 2)
    assert t.writes == []


@pytest.mark.parametrize("bad", [None, 0, -1.0, math.inf, math.nan, "1", True])
def test_a_timeout_is_seconds_above_zero_and_finite(bad: object) -> None:
    """A ValueError before anything is sent: None raised a TypeError, inf hung for ever."""
    with pytest.raises(ValueError, match="a timeout is a number of seconds"):
        Rcb4Client(ScriptedTransport(), timeout=bad)  # type: ignore[arg-type]
    if bad is not None:  # a call's None is "the client's timeout"
        client = Rcb4Client(ScriptedTransport())
        with pytest.raises(ValueError, match="a timeout is a number of seconds"):
            client.acknowledge_check(timeout=bad)  # type: ignore[arg-type]
        assert client.transport.writes == []  # type: ignore[attr-defined]
