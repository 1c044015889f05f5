"""One client, two faces: the blocking ``Robot``/``Rcb4Client`` are generated from the asyncio
``AsyncRobot``/``AsyncRcb4Client`` (tools/unasync.py). These tests prove the faces agree:
the same public methods with the same signatures, and, for every public robot method, the
same frames on the wire and the same result type for the same inputs."""

from __future__ import annotations

import asyncio
import inspect
import math
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from rcb4hv.aio import AsyncRcb4Client, AsyncRobot, AsyncTransport
from rcb4hv.client import Rcb4Client, Robot
from rcb4hv.protocol import AcknowledgeCheck, Button, SystemRegister
from rcb4hv.transport import Transport

ROOT = Path(__file__).resolve().parents[2]
URL = "rcb4emu://?speed=10"
"""A fresh emulated board per call: it opens at its main loop (servo table in RAM)."""


def _public(cls: type) -> dict[str, Any]:
    return {n: getattr(cls, n) for n in dir(cls) if not n.startswith("_")}


def _sync_text(text: str) -> str:
    for name in ("AsyncRcb4Client", "AsyncRobot", "AsyncTransport"):
        text = text.replace(name, name.removeprefix("Async"))
    return text


PAIRS = [(Robot, AsyncRobot), (Rcb4Client, AsyncRcb4Client), (Transport, AsyncTransport)]


@pytest.mark.parametrize(("blocking", "asyncio_face"), PAIRS, ids=lambda c: c.__name__)
def test_both_faces_have_the_same_methods(blocking: type, asyncio_face: type) -> None:
    sync, aio = _public(blocking), _public(asyncio_face)
    assert sorted(sync) == sorted(aio)
    for name, method in sync.items():
        twin = aio[name]
        if isinstance(method, property) or not callable(method):
            assert type(twin) is type(method), name
            continue
        assert str(inspect.signature(method)) == _sync_text(str(inspect.signature(twin))), name
        if inspect.iscoroutinefunction(twin):
            assert not inspect.iscoroutinefunction(method), name


def test_the_blocking_modules_are_what_the_generator_writes() -> None:
    done = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "unasync.py"), "--check"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert done.returncode == 0, done.stdout + done.stderr


# ---------------------------------------------------------------------- same frames

K = 2
"""An ICS number with a servo in the emulator's default image."""

CALLS: dict[str, Callable[[Any], Any]] = {
    "ad_readings": lambda r: r.ad_readings(),
    "ad_values": lambda r: r.ad_values(),
    "allocation_table": lambda r: r.allocation_table(),
    "angles": lambda r: r.angles([K, 3], kind="output"),
    "battery_voltage": lambda r: r.battery_voltage(),
    "board_layout": lambda r: r.board_layout(),
    "buttons": lambda r: r.buttons(),
    "check_position": lambda r: r.check_position(K, 7500),
    "close": lambda r: r.close(),
    "counter": lambda r: r.counter(3),
    "current_motion": lambda r: r.current_motion(),
    "discover_servos": lambda r: r.discover_servos(),
    "frames_for": lambda r: r.frames_for(0.3),
    "free": lambda r: r.free([K]),
    "hold": lambda r: r.hold(),
    "info": lambda r: r.info(),
    "interpolating": lambda r: r.interpolating(),
    "motion_status": lambda r: r.motion_status(),
    "move": lambda r: r.move({K: 8000, 3: 7000}, 0.2),
    "move_angles": lambda r: r.move_angles({K: 10.0}, 0.1),
    "neutral": lambda r: r.neutral([K, 3], 0.1),
    "open": lambda r: _open_and_close(type(r)),
    "output_period": lambda r: r.output_period(refresh=True),
    "pa_values": lambda r: r.pa_values(),
    "ping": lambda r: r.ping(),
    "pio": lambda r: r.pio(),
    "play_motion": lambda r: r.play_motion(1),
    "positions": lambda r: r.positions(),
    "press_button": lambda r: r.press_button(Button.UP, 0.0),
    "ram_dump": lambda r: r.ram_dump(),
    "read_plan": lambda r: r.read_plan([K, 3, 4]),
    "read_ram": lambda r: r.read_ram(0x0350, 200),
    "read_rom": lambda r: r.read_rom(0x0B80, 300),
    "reconnect": lambda r: r.reconnect(),
    "resume_motion": lambda r: r.resume_motion(),
    "send_sequence": lambda r: r.send_sequence([AcknowledgeCheck()]),
    "servo_ids": lambda r: r.servo_ids(),
    "servo_states": lambda r: r.servo_states([K, 5]),
    "set_buttons": lambda r: r.set_buttons(Button.DOWN),
    "set_counter": lambda r: r.set_counter(2, 9),
    "set_pa": lambda r: r.set_pa(2, 99),
    "set_pio_direction": lambda r: r.set_pio_direction(0x3),
    "set_speed": lambda r: r.set_speed(50, [K, 3]),
    "set_stretch": lambda r: r.set_stretch({K: 60}),
    "set_system_register": lambda r: r.set_system_register(SystemRegister.from_word(0x0C8F)),
    "set_timer": lambda r: r.set_timer(1, 40),
    "set_variable": lambda r: r.set_variable(4, -3),
    "stop_motion": lambda r: r.stop_motion(reset=False),
    "stop_timer": lambda r: r.stop_timer(1),
    "system_register": lambda r: r.system_register(),
    "system_word": lambda r: r.system_word(),
    "timer": lambda r: r.timer(0),
    "to_degrees": lambda r: r.to_degrees(K, 8000),
    "to_position": lambda r: r.to_position(K, 12.5),
    "variable": lambda r: r.variable(4),
    "variables": lambda r: r.variables(),
    "version": lambda r: r.version(),
    "wait_interpolation": lambda r: r.wait_interpolation([K], timeout=1.0),
    "wait_motion": lambda r: r.wait_motion(timeout=1.0),
    "wait_ready": lambda r: r.wait_ready(),
    "write_pio": lambda r: r.write_pio(0x1),
    "write_ram": lambda r: r.write_ram(0x0462, bytes(range(130))),
    "write_rom": lambda r: r.write_rom(0x3F0F0, bytes(range(40))),
}
"""One call of every public method of the robot API (the same inputs for both faces)."""


def _open_and_close(cls: type) -> Any:
    """Open a second robot (baud detection: ACK checks on its own link) and close it."""
    if cls is AsyncRobot:

        async def run() -> None:
            robot = await AsyncRobot.open(URL, baudrate=None)
            await robot.close()

        return run()
    Robot.open(URL, baudrate=None).close()
    return None


def test_every_public_robot_method_has_a_call() -> None:
    assert sorted(CALLS) == sorted(_public(Robot))


def _outcome(value: Any) -> tuple[str, Any]:
    """What a call gave, comparable across faces: the value where it is a fact of the board
    and the call (not a time or a live reading), else its type."""
    if isinstance(value, BaseException):
        return "raised", (type(value), str(value))
    if isinstance(value, float) and (math.isnan(value) or value < 1):  # ping, periods
        return "float", None
    return "returned", type(value)


def _record(transport: Any) -> list[bytes]:
    frames: list[bytes] = []
    write = transport.write

    def recording(data: bytes) -> None:
        frames.append(bytes(data))
        write(data)

    transport.write = recording
    return frames


def _blocking_run(call: Callable[[Any], Any]) -> tuple[list[bytes], tuple[str, Any]]:
    with Robot.open(URL) as robot:
        frames = _record(robot.client.transport)
        try:
            outcome = _outcome(call(robot))
        except Exception as exc:
            outcome = _outcome(exc)
        return frames, outcome


def _asyncio_run(call: Callable[[Any], Any]) -> tuple[list[bytes], tuple[str, Any]]:
    async def main() -> tuple[list[bytes], tuple[str, Any]]:
        async with await AsyncRobot.open(URL) as robot:
            frames = _record(robot.client.transport)
            try:
                value = call(robot)
                if inspect.isawaitable(value):
                    value = await value
                outcome = _outcome(value)
            except Exception as exc:
                outcome = _outcome(exc)
            return frames, outcome

    return asyncio.run(main())


@pytest.mark.parametrize("name", sorted(CALLS))
def test_both_faces_send_the_same_frames(name: str) -> None:
    call = CALLS[name]
    sync_frames, sync_outcome = _blocking_run(call)
    aio_frames, aio_outcome = _asyncio_run(call)
    assert aio_frames == sync_frames
    assert aio_outcome == sync_outcome
    if name in ("positions", "read_ram", "write_rom", "play_motion", "info"):
        assert sync_frames  # the calls that must talk to the board did


def test_positions_read_the_cheapest_plan_on_both_faces() -> None:
    """The drift the generator ended: AsyncRobot.positions() planned with plan_reads."""
    with Robot.open(URL) as robot:
        robot.servo_ids()
        plan = robot.read_plan()
        frames = _record(robot.client.transport)
        robot.positions()
    assert [(int.from_bytes(f[6:8], "little"), f[8]) for f in frames] == plan

    async def main() -> list[bytes]:
        async with await AsyncRobot.open(URL) as robot:
            await robot.servo_ids()
            frames = _record(robot.client.transport)
            await robot.positions()
            return frames

    assert asyncio.run(main()) == frames


def test_transport_wrappers_pass_the_baud_rate_on() -> None:
    """Baud detection goes through Transport.set_baudrate, so a wrapper must hand it to the
    link it wraps (the dashboard's MeteredTransport did not, and its detection failed)."""
    from rcb4hv.session.meter import MeteredTransport
    from rcb4hv.transport import FaultyTransport

    class Serialish(Transport):
        url = "serialish://"

        def __init__(self) -> None:
            self.rates: list[int] = []

        def write(self, data: bytes) -> None: ...

        def read(self, size: int, deadline: float) -> bytes:
            return b""

        def reset_input(self) -> None: ...

        def close(self) -> None: ...

        @property
        def is_open(self) -> bool:
            return True

        def set_baudrate(self, baudrate: int) -> None:
            self.rates.append(baudrate)

    inner = Serialish()
    for wrapper in (MeteredTransport(inner), FaultyTransport(inner)):
        wrapper.set_baudrate(625000)
    assert inner.rates == [625000, 625000]
