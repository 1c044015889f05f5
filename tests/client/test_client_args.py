"""Bad arguments to the client and the robot API: a typed error naming the argument, at once.

The cases of the API bad-input sweep: NaN/inf/0/negative waits (a NaN timeout used to poll
forever), non-finite angles and durations (OverflowError), ``kind="bogus"``, wrong types
reaching internals, numpy integers, a calibration that is not a finite number, a degree
conversion for a servo the robot does not have, the closed-client message, a bad ``fault://``
URL on the asyncio face and a close racing a call from another thread.
"""

from __future__ import annotations

import asyncio
import math
import threading
from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from rcb4hv.aio import AsyncRcb4Client
from rcb4hv.client import Calibration, Rcb4Client
from rcb4hv.emulator import Board, emulator_url
from rcb4hv.errors import (
    ArgumentError,
    ArgumentTypeError,
    Rcb4TimeoutError,
    TransportError,
)
from rcb4hv.robot.builtin import load_builtin
from tests.client.conftest import Rig, make_board, make_rig

NAN, INF = math.nan, math.inf


@pytest.fixture(params=("inproc", "aio-inproc"))
def rig(request: pytest.FixtureRequest) -> Iterator[Rig]:
    """Both faces over the in-process link (the checks run before any byte is sent)."""
    yield from make_rig(request.param)


@pytest.mark.timeout(20)
@pytest.mark.parametrize("timeout", [NAN, -1.0, 0, INF, "1"])
def test_every_robot_wait_refuses_a_timeout_the_client_refuses(rig: Rig, timeout: Any) -> None:
    """One rule for every wait (the client's): a NaN timeout used to poll forever, and 0 or a
    negative one returned or ran unchecked."""
    r = rig.robot
    r.play_motion(1)
    r.stop_motion(reset=False)  # paused: wait_motion would wait for it
    waits = {
        "wait_motion": lambda: r.wait_motion(timeout=timeout),
        "wait_ready": lambda: r.wait_ready(timeout=timeout),
        "wait_interpolation": lambda: r.wait_interpolation(timeout=timeout),
        "play_motion": lambda: r.play_motion(2, wait=True, timeout=timeout),
        "move": lambda: r.move({2: 7500}, 0.1, wait=True, timeout=timeout),
    }
    for name, call in waits.items():
        with pytest.raises(ArgumentError, match="timeout") as info:
            call()
        assert isinstance(info.value, ValueError), name
    assert r.current_motion() == 1  # play_motion(2) never started: checked before it plays
    r.stop_motion()


def test_a_wait_refuses_a_negative_or_nan_poll(rig: Rig) -> None:
    for poll in (-1.0, NAN):
        with pytest.raises(ArgumentError, match="poll"):
            rig.robot.wait_ready(timeout=1.0, poll=poll)
        with pytest.raises(ArgumentError, match="poll"):
            rig.robot.wait_motion(timeout=1.0, poll=poll)


def test_a_paused_motion_times_out_as_paused(rig: Rig) -> None:
    r = rig.robot
    r.play_motion(1)
    r.stop_motion(reset=False)
    with pytest.raises(Rcb4TimeoutError, match=r"motion 1 still paused after 0\.05 s"):
        r.wait_motion(timeout=0.05)
    r.stop_motion()


@pytest.mark.parametrize("bad", [INF, -INF, NAN])
def test_non_finite_angles_and_durations_name_the_argument(rig: Rig, bad: float) -> None:
    r = rig.robot
    calls = {
        "ICS 2: angle": lambda: r.move_angles({2: bad}),
        "ICS 3: angle": lambda: r.to_position(3, bad),
        "duration": lambda: r.move({2: 7500}, duration=bad),
        "duration ": lambda: r.frames_for(bad),
    }
    for what, call in calls.items():
        with pytest.raises(ArgumentError, match=f"{what.strip()} must be a finite number"):
            call()
    model = load_builtin("kxr-l2")
    with pytest.raises(ArgumentError, match=r"angle .* is not a finite number"):
        model.motion_value(model.servos[0].index, bad)
    assert r.positions([2], kind="output")[2] == 7500  # nothing was sent


def test_kind_and_wrong_types_are_refused_by_name(rig: Rig) -> None:
    r = rig.robot
    with pytest.raises(ArgumentError, match="kind must be one of 'measured', 'output'"):
        r.positions(kind="bogus")  # type: ignore[arg-type]
    with pytest.raises(ArgumentError, match="kind"):
        r.angles(kind="bogus")  # type: ignore[arg-type]
    with pytest.raises(ArgumentTypeError, match=r"ics must be an iterable .*not 2"):
        r.positions(2)  # type: ignore[arg-type]
    with pytest.raises(ArgumentTypeError, match=r"ics must be"):
        r.free(2)  # type: ignore[arg-type]
    with pytest.raises(ArgumentTypeError, match=r"value must be an int, not 1.5"):
        r.set_variable(0, 1.5)  # type: ignore[arg-type]
    with pytest.raises(ArgumentTypeError, match=r"duration must be a number, not '1'"):
        r.move({2: 7500}, duration="1")  # type: ignore[arg-type]
    with pytest.raises(ArgumentTypeError, match=r"buttons must be an int, not 1.5"):
        r.set_buttons(1.5)  # type: ignore[arg-type]
    with pytest.raises(TypeError):  # ArgumentTypeError is a TypeError too
        r.set_system_register("x")  # type: ignore[arg-type]


def test_numpy_integers_are_ints_and_floats_are_shown_plainly(rig: Rig) -> None:
    r = rig.robot
    r.move({np.int64(2): np.int64(7600)}, np.float64(0.0))
    assert r.positions([2], kind="output")[2] == 7600
    r.set_variable(np.int64(0), np.int16(-5))
    assert r.variable(0) == -5
    r.set_stretch(np.int32(60), [2])
    with pytest.raises(ArgumentTypeError, match=r"ICS 2: position must be an int, not 7500.0$"):
        r.move({2: 7500.0})  # type: ignore[dict-item]
    with pytest.raises(ArgumentError, match=r"ICS 2: position 3000 outside 3500..11500"):
        r.move({2: np.int64(3000)})


@pytest.mark.parametrize(
    ("fields", "error", "message"),
    [
        ({"trim": NAN}, ArgumentError, "trim must be a finite number, not nan"),
        ({"trim": INF}, ArgumentError, "trim must be a finite number, not inf"),
        ({"trim": -INF}, ArgumentError, "trim must be a finite number, not -inf"),
        ({"trim": "40"}, ArgumentTypeError, "trim must be a number, not '40'"),
        ({"trim": None}, ArgumentTypeError, "trim must be a number, not None"),
        ({"direction": NAN}, ArgumentError, "direction must be a finite number, not nan"),
        ({"direction": 0}, ArgumentError, r"direction must be \+1 or -1, not 0"),
        ({"direction": "-1"}, ArgumentTypeError, "direction must be a number, not '-1'"),
        ({"direction": True}, ArgumentTypeError, "direction must be a number, not True"),
    ],
)
def test_a_calibration_refuses_a_field_that_is_not_a_finite_number(
    fields: dict[str, Any], error: type, message: str
) -> None:
    """``Calibration(trim=nan)`` was made, and every angle through it came out NaN (or an
    OverflowError for inf): a typed error naming the field, at construction."""
    with pytest.raises(error, match=message):
        Calibration(**fields)
    assert Calibration(trim=np.int64(40), direction=-1).to_position(10.0) == 7540 - 296
    assert Calibration(trim=12.5).to_position(0.0) == 7512  # a fractional trim is a number


def test_degree_conversions_refuse_an_ics_number_the_robot_does_not_have(rig: Rig) -> None:
    """``to_degrees(99, 7500)`` answered 0.0 (the default calibration) for a servo that is not
    there: an ArgumentError naming the number and the robot's servos, on both faces, and
    ``to_position`` the same; before the servo table is read, the servo slots 0..34."""
    fresh = rig.new_robot()  # its servo table not read yet
    for call in (lambda: fresh.to_degrees(99, 7500), lambda: fresh.to_position(99, 0.0)):
        with pytest.raises(ArgumentError, match=r"no servo at ICS 99 \(servos are ICS 0\.\.34\)"):
            call()
    with pytest.raises(ArgumentError, match="no servo at ICS 35"):
        fresh.to_degrees(35, 7500)  # the remote-control receiver's slot
    r = rig.robot
    assert 1 not in r.servo_ids()  # the servo table read: the robot's own servos count
    for ics in (99, 1):
        has = rf"no servo at ICS {ics} \(the robot has ICS \[0, 2, 3, 4, "
        with pytest.raises(ArgumentError, match=has):
            r.to_degrees(ics, 7500)
        with pytest.raises(ArgumentError, match=has):
            r.to_position(ics, 0.0)
    with pytest.raises(ArgumentTypeError, match="ICS number must be an int, not '2'"):
        r.to_degrees("2", 7500)  # type: ignore[arg-type]
    assert r.to_degrees(np.int64(2), 7500) == 0.0 and r.to_position(2, 0.0) == 7500


def test_open_names_a_wrong_url_or_baudrate() -> None:
    with pytest.raises(ArgumentTypeError, match="url must be a str"):
        Rcb4Client.open(5)  # type: ignore[arg-type]
    with pytest.raises(ArgumentTypeError, match="baudrate must be an int, not '115200'"):
        Rcb4Client.open("rcb4emu://", baudrate="115200")  # type: ignore[arg-type]
    with pytest.raises(ArgumentTypeError, match="url must be a str"):
        asyncio.run(AsyncRcb4Client.open(5))  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "url",
    [
        "fault://x@rcb4emu://",
        "fault://drop_reply=abc@rcb4emu://",
        "fault://seed=x@rcb4emu://",
        "fault://drop_reply=-0.5@rcb4emu://",
        "fault://drop_reply=0.1",
    ],
)
def test_a_bad_fault_url_is_a_transport_error_on_both_faces(url: str) -> None:
    with pytest.raises(TransportError, match=f"cannot open {url}"):
        Rcb4Client.open(url)
    with pytest.raises(TransportError, match=f"cannot open {url}"):
        asyncio.run(AsyncRcb4Client.open(url))


def test_a_closed_client_says_so(rig: Rig) -> None:
    client = rig.robot.client  # (the aio rig's bridge would stop its loop on close)
    client.close()
    with pytest.raises(TransportError, match="the client is closed") as info:
        client.acknowledge_check()
    assert "port that is not open" not in str(info.value)
    client.reconnect()
    client.acknowledge_check()


class _ClosingBoard:
    """Serves ``board``; while answering the first frame of a read it starts a close of the
    client from another thread and lets it run (a close racing a call)."""

    def __init__(self, board: Board) -> None:
        self.board = board
        self.client: Rcb4Client | None = None
        self.closer: threading.Thread | None = None

    def feed(self, data: bytes) -> bytes:
        reply = self.board.feed(data)
        if self.client is not None and self.closer is None and data[1:2] == b"\x00":
            self.closer = threading.Thread(target=self.client.close)
            self.closer.start()
            self.closer.join(timeout=0.2)  # an unlocked close finishes here; a locked one waits
        return reply

    def tick(self) -> None:
        self.board.tick()

    def take_output(self) -> bytes:
        return self.board.take_output()

    def close(self) -> None:
        pass


@pytest.mark.timeout(30)
def test_a_close_racing_a_call_ends_it_with_the_closed_client_error() -> None:
    """Rcb4Client.close() from another thread during a 3-frame read: the frame in flight is
    answered, the next one raises the closed-client TransportError (it was an AttributeError
    from the emulator's port, whose board the close had dropped under the read)."""
    board = make_board()
    served = _ClosingBoard(board)
    url = emulator_url(served)  # type: ignore[arg-type]
    client = Rcb4Client.open(url)
    served.client = client
    try:
        with pytest.raises(TransportError, match="the client is closed"):
            client.read_ram(0, 300)
    finally:
        assert served.closer is not None
        served.closer.join(timeout=5)
        board.close()


@pytest.mark.parametrize(
    ("kw", "error", "words"),
    [
        ({"calibration": 5}, ArgumentTypeError, "calibration must map"),
        ({"calibration": {2: 40}}, ArgumentTypeError, "ICS 2 needs a Calibration"),
        ({"calibration": {99: Calibration()}}, ArgumentError, "ICS 99 is not a servo"),
        ({"layout": "9.9"}, ArgumentError, "layout '9.9'"),
        ({"layout": 21}, ArgumentTypeError, "layout must be"),
        ({"link_cost": 5}, ArgumentTypeError, "link_cost must be a LinkCost"),
    ],
)
def test_robot_options_are_checked_before_the_link_opens(
    monkeypatch: pytest.MonkeyPatch, kw: dict[str, Any], error: type[Exception], words: str
) -> None:
    """They failed later (AttributeError on play_motion, TypeError after the link was open,
    which the asyncio face then leaked)."""
    from rcb4hv.aio import AsyncRobot
    from rcb4hv.client import Robot

    def never(*_a: object, **_k: object) -> None:
        raise AssertionError("the link was opened")

    monkeypatch.setattr(Rcb4Client, "open", never)
    monkeypatch.setattr(AsyncRcb4Client, "open", never)
    with pytest.raises(error, match=words):
        Robot.open("rcb4emu://", **kw)
    with pytest.raises(error, match=words):
        asyncio.run(AsyncRobot.open("rcb4emu://", **kw))


def test_a_robot_takes_a_layout_by_its_version() -> None:
    from rcb4hv.client import Robot
    from rcb4hv.rom.layout import LAYOUTS

    with Robot.open("rcb4emu://", layout="2.1") as robot:
        assert robot.layout is LAYOUTS["2.1"]


@pytest.mark.parametrize(
    ("call", "error"),
    [
        (lambda c: c.write_ram(0x0462, bytes(100)), ArgumentError),  # past the end of RAM
        (lambda c: c.read_ram(0, 0), ArgumentError),
        (lambda c: c.read_rom(0x3FFF0, 100), ArgumentError),
        (lambda c: c.write_rom(0x3FFF0, bytes(100)), ArgumentError),
        (lambda c: c.write_ram(0x0462, [1, 300]), ArgumentError),
        (lambda c: c.write_ram(0, "ab"), ArgumentTypeError),
        (lambda c: c.write_ram(0x0462, 5), ArgumentTypeError),  # bytes(5): five zero bytes
        (lambda c: c.read_ram(0x0462, 2.0), ArgumentTypeError),
    ],
)
def test_memory_helpers_raise_typed_errors_before_sending(
    call: Any, error: type[Exception]
) -> None:
    with Rcb4Client.open("rcb4emu://") as rcb:
        before = rcb.read_ram(0x0462, 8)
        with pytest.raises(error):
            call(rcb)
        assert rcb.read_ram(0x0462, 8) == before
        rcb.write_ram(0x0462, [1, 2])  # a sequence of ints 0..255 is still bytes
        assert rcb.read_ram(0x0462, 2) == b"\x01\x02"
