"""The AD reference rule (spec 10.4): each measured register (0022h) reads the channel's input
minus its reference (000Ch), signed, recomputed whenever the board samples its inputs, so a
reference written by the host or the ROM program takes effect at once."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.client import Rcb4Client, Robot
from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock, emulator_url
from rcb4hv.emulator.config import ad_inputs_from
from rcb4hv.errors import TransportError
from rcb4hv.protocol import ADDR, Com, Data, Move, Ram, encode_command
from rcb4hv.protocol.memory import s16
from rcb4hv.session.state import BoardState, poll_state
from tests.emulator.conftest import IDLE, x
from tests.emulator.test_emu_program import halt_at, load, start

REPO = Path(__file__).resolve().parents[2]
REF_273 = (273).to_bytes(2, "little")


def reference_move(channel: int, value: int) -> Move:
    return Move(Ram(ADDR.AD_REFERENCE + 2 * channel), Data(value.to_bytes(2, "little")))


def test_over_a_real_pty_inputs_300_and_250_with_references_273_read_27_and_minus_23() -> None:
    proc = subprocess.Popen(
        [sys.executable, "-m", "rcb4hv", "emulate", "--pty", "--ad", "1=300", "--ad", "AD2=250"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=REPO,
        env={**os.environ, "PYTHONPATH": str(REPO / "src")},
    )
    try:
        assert proc.stdout is not None
        kind, path = proc.stdout.readline().split()
        assert kind == "PTY"
        with Rcb4Client.open(path) as rcb:
            robot = Robot(rcb)
            assert robot.ad_values()[1:3] == [300, 250]  # references 0 at power-on
            rcb.write_ram(ADDR.AD_REFERENCE + 2, REF_273 + REF_273)
            assert robot.ad_values()[1:3] == [27, -23]
            ad = robot.ad_readings()
            assert ad.inputs[1:3] == (300, 250) and ad.references[1:3] == (273, 273)
            # the register itself holds the two's complement of -23
            assert rcb.read_ram(ADDR.AD_VALUES + 4, 2) == (0x10000 - 23).to_bytes(2, "little")
    finally:
        proc.terminate()
        _, err = proc.communicate(timeout=10)
    assert proc.returncode == 0, err


@given(
    channel=st.integers(0, 10),
    counts=st.integers(0, 1023),
    reference=st.integers(0, 0xFFFF),
    reference_first=st.booleans(),
)
def test_measured_is_input_minus_reference_whichever_is_written_last(
    channel: int, counts: int, reference: int, reference_first: bool
) -> None:
    b = Board(IDLE, clock=VirtualClock())
    if reference_first:
        x(b, reference_move(channel, reference))
        b.set_ad_input(channel, counts)
    else:
        b.set_ad_input(channel, counts)
        x(b, reference_move(channel, reference))
    expected = s16((counts - reference) & 0xFFFF)
    assert b.ad_measured(channel) == expected
    assert b.ad_input(channel) == counts and b.ad_reference(channel) == reference
    reply = x(b, Move(Com(), Ram(ADDR.AD_VALUES + 2 * channel), size=2))
    assert reply[2:4] == (expected & 0xFFFF).to_bytes(2, "little")
    # the other channels keep input - their own reference (0 here)
    other = (channel + 1) % 11
    assert b.ad_measured(other) == b.ad_input(other)


def test_a_reference_the_rom_program_writes_takes_effect_before_its_next_instruction() -> None:
    b = Board(IDLE, clock=VirtualClock())
    b.set_ad_input(1, 300)
    var = ADDR.USER_VARIABLES
    read = Move(Ram(var), Ram(ADDR.AD_VALUES + 2), size=2)
    at = load(b, 0, [reference_move(1, 273), read])  # a compiled literal MOVE: resamples too
    end = at[-1] + len(encode_command(read))
    load(b, end, [halt_at(end)])
    start(b, 0)
    b.run_for(0.05)
    assert int.from_bytes(b.ram[var : var + 2], "little") == 27


def test_a_host_write_to_the_measured_register_lasts_until_the_next_sample() -> None:
    b = Board(IDLE, clock=VirtualClock())
    b.set_ad_input(3, 500)
    x(b, Move(Ram(ADDR.AD_VALUES + 6), Data(b"\x01\x00")))
    assert b.ad_measured(3) == 1
    b.run_for(0.02)  # an output period: the board samples its inputs again
    assert b.ad_measured(3) == 500


def test_the_start_up_program_copies_the_image_references() -> None:
    from rcb4hv.cli.project_common import load_image

    image, _, _ = load_image(Path("../shared/fixtures/hth4/kxr-l2-hac/HAC_KXR_HTH4_project.h4p"))
    b = Board(EmulatorConfig(ad_inputs=ad_inputs_from([(1, 280), (2, 273)])), rom_image=image)
    b.run_for(3.0)
    assert (b.ad_reference(1), b.ad_reference(2)) == (273, 273)
    assert (b.ad_measured(1), b.ad_measured(2)) == (7, 0)


def test_rcb4emu_url_sets_inputs_and_the_dashboard_shows_input_and_measured() -> None:
    with Rcb4Client.open("rcb4emu://?ad1=300&ad10=1023") as rcb:
        robot = Robot(rcb)
        rcb.write_ram(ADDR.AD_REFERENCE + 2, REF_273)
        assert robot.ad_values()[1] == 27 and robot.ad_values()[10] == 1023
    b = Board(clock=VirtualClock())
    b.run_for(3.0)
    b.set_ad_input(2, 250)
    x(b, reference_move(2, 273))
    with Rcb4Client.open(emulator_url(b)) as rcb:
        robot = Robot(rcb)
        robot.discover_servos()
        state = poll_state(robot, BoardState(url="x"), 0.0)
    from rcb4hv.ui.board_page import state_rows

    rows = {r["field"]: r["value"] for r in state_rows(state)}
    assert rows["AD2"] == "input 250, measured -23 (reference 273)"
    assert state.describe()["ad"]["measured"][2] == -23  # type: ignore[index]


@pytest.mark.parametrize("query", ["ad11=5", "ad1=1024", "ad0=3", "adx=1"])
def test_rcb4emu_url_refuses_bad_ad_inputs(query: str) -> None:
    with pytest.raises(TransportError, match="bad rcb4emu"):
        Rcb4Client.open(f"rcb4emu://?{query}")


@pytest.mark.parametrize("arg", ["11=5", "1=1024", "1:300", "x=1"])
def test_cli_refuses_bad_ad_inputs(arg: str) -> None:
    from click.testing import CliRunner

    from rcb4hv.cli.emulate_cmd import emulate

    res = CliRunner().invoke(emulate, ["--pty", "--ad", arg])
    assert res.exit_code == 2 and "--ad" in res.output


def test_a_reset_leaves_the_inputs_and_zeroes_the_references() -> None:
    b = Board(IDLE, clock=VirtualClock())
    b.set_ad_input(4, 600)
    x(b, reference_move(4, 100))
    assert b.ad_measured(4) == 500
    b.power_on()  # what a reset does (spec 10.1): the references are 0 again
    assert b.ad_input(4) == 600 and b.ad_reference(4) == 0 and b.ad_measured(4) == 600
