"""``rcb4emu://`` opens on a board whose start-up program has run (the README's first wire
example sends a servo read right after opening), ``?boot=live`` at power-on; ``rcb4hv emulate``
has the same choice."""

from __future__ import annotations

import subprocess
import sys
import time

import pytest

from rcb4hv.client import Rcb4Client, Robot
from rcb4hv.errors import NakError, TransportError
from rcb4hv.protocol import Com, Ics
from rcb4hv.rom.layout import HTH4_22


def test_open_waits_for_the_start_up_program() -> None:
    t0 = time.monotonic()
    with Rcb4Client.open("rcb4emu://") as rcb:
        assert time.monotonic() - t0 < 1.0  # virtual time: no real 1.6 s wait
        assert int.from_bytes(rcb.move(Com(), Ics(4, 2), 2) or b"", "little") == 7500
        robot = Robot(rcb)
        status = robot.motion_status()
        assert HTH4_22.main_loop <= status.pc < HTH4_22.motion_base
        assert status.call_depth == 0
        assert len(robot.discover_servos()) == 17
        assert robot.system_register().rom_run


def test_boot_live_opens_at_power_on() -> None:
    # the start-up program allocates the servos 8 ms of board time after power-on: at a
    # thousandth of real time the first command comes before that even on a loaded machine
    slow = "rcb4emu://?boot=live&speed=0.001"
    with Rcb4Client.open(slow) as rcb, pytest.raises(NakError):  # nothing allocated yet
        rcb.move(Com(), Ics(4, 2), 2)
    with Rcb4Client.open("rcb4emu://?boot=live") as rcb:
        robot = Robot(rcb)
        robot.wait_ready(timeout=10.0)
        assert len(robot.discover_servos()) == 17


def test_bad_boot_option() -> None:
    with pytest.raises(TransportError, match="boot must be"):
        Rcb4Client.open("rcb4emu://?boot=later")


@pytest.mark.parametrize("boot", ["ready", "live"])
def test_emulate_boot_option(boot: str) -> None:
    # A live board's start-up program allocates the servos 8 ms of board time after power-on;
    # at a thousandth of real time that is 8 s, so the first command comes before it even on a
    # loaded machine (at full speed it had to come within 8 ms of the server starting).
    speed = "1" if boot == "ready" else "0.001"
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "rcb4hv",
            "emulate",
            "--tcp",
            "127.0.0.1:0",
            "--boot",
            boot,
            "--speed",
            speed,
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline().split()
        assert line[0] == "TCP"
        with Rcb4Client.open(f"socket://{line[1]}") as rcb:
            if boot == "ready":
                assert rcb.move(Com(), Ics(4, 2), 2) == (7500).to_bytes(2, "little")
            else:
                with pytest.raises(NakError):
                    rcb.move(Com(), Ics(4, 2), 2)
    finally:
        proc.terminate()
        assert proc.wait(timeout=10) == 0
        if proc.stdout:
            proc.stdout.close()
