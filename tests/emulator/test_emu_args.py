"""Bad emulator parameters are refused when given; a ROM file that cannot be written is
reported (typed, naming the file) without ending the session; the board's host and test hooks
(``measure``, ``feed``, ``set_ad_input``, ``set_servo_position``) refuse a bad argument with a
typed error before they change anything."""

from __future__ import annotations

import contextlib
import errno
import math
from pathlib import Path

import pytest

from rcb4hv.client import Rcb4Client
from rcb4hv.emulator import Board, EmulatorConfig, RealClock, VirtualClock, emulator_url, romstore
from rcb4hv.emulator.config import ad_inputs_from
from rcb4hv.errors import ArgumentError, ArgumentTypeError, RomFileError, TransportError
from tests.emulator.conftest import IDLE, h

ROM_PAGE = 0x3F000
ACK_CHECK = h("03 FE 01")


@pytest.mark.parametrize(
    "query", ["speed=inf", "speed=-inf", "speed=1e999", "latency=inf", "latency=nan"]
)
def test_a_non_finite_url_parameter_is_refused_at_open(query: str) -> None:
    """``speed=inf`` opened, then the first call raised OverflowError inside the board."""
    name = query.split("=")[0]
    with pytest.raises(TransportError, match=f"{name} must be a finite number"):
        Rcb4Client.open(f"rcb4emu://?{query}")


def test_clocks_refuse_non_finite_times() -> None:
    for bad in (math.inf, math.nan, 0.0, -1.0):
        with pytest.raises(ArgumentError, match="speed must be a finite number > 0"):
            RealClock(bad)
    clock = VirtualClock()
    for bad in (math.inf, math.nan, -1.0):
        with pytest.raises(ArgumentError, match="finite number of seconds >= 0"):
            clock.advance(bad)
        with pytest.raises(ArgumentError):
            VirtualClock(bad)
    with pytest.raises(ArgumentError):
        clock.set(math.inf)
    assert clock.now() == 0.0


def _refuse_writes(monkeypatch: pytest.MonkeyPatch, path: Path) -> None:
    def refuse(target: object, data: bytes) -> None:
        raise PermissionError(errno.EACCES, f"cannot write {path}: Permission denied")

    monkeypatch.setattr(romstore, "write_atomic", refuse)


def test_a_rom_file_that_cannot_be_written_is_reported_once_and_at_close(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The call that meets the failed save raises RomFileError naming the file; the board
    serves on (every later call used to fail with "cannot flush input"), and close() reports
    the image still unsaved."""
    path = tmp_path / "board.rom"
    board = Board(EmulatorConfig(rom_flush_delay_s=0), clock=VirtualClock(), rom_path=path)
    client = Rcb4Client.open(emulator_url(board))
    _refuse_writes(monkeypatch, path)
    with pytest.raises(RomFileError, match=f"cannot save its ROM image: cannot write {path}"):
        for _ in range(3):  # the save is tried at the next tick after the write
            client.write_rom(ROM_PAGE, b"\x11" * 64)
            client.acknowledge_check()
    for _ in range(3):
        client.acknowledge_check()  # the board serves on
    assert client.read_rom(ROM_PAGE, 4) == b"\x11" * 4
    client.close()
    with pytest.raises(RomFileError, match=str(path)) as info:
        board.close()
    assert info.value.path == str(path)
    monkeypatch.undo()
    board.flush_rom()  # writable again: saved after all
    assert path.read_bytes()[ROM_PAGE : ROM_PAGE + 4] == b"\x11" * 4


def test_closing_a_port_whose_rom_file_cannot_be_written_says_so(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "board.rom"
    client = Rcb4Client.open(f"rcb4emu://?rom={path}")
    _refuse_writes(monkeypatch, path)
    with contextlib.suppress(RomFileError):  # slow machine: the delayed save came due
        client.write_rom(ROM_PAGE, b"\x22" * 64)
    with pytest.raises(RomFileError, match=str(path)):
        client.close()
    with pytest.raises(TransportError, match="the client is closed"):
        client.acknowledge_check()


# ------------------------------------------------------------------ the test hooks' arguments


@pytest.mark.parametrize(
    ("positions", "ad", "error", "message"),
    [
        ({99: 7500}, {}, ArgumentError, r"ICS number 99 outside 0\.\.35"),
        ({-1: 7500}, {}, ArgumentError, r"ICS number -1 outside 0\.\.35"),
        ({2: 0x10000}, {}, ArgumentError, r"ICS 2: position 65536 is not 16 bits \(0\.\.65535\)"),
        ({2: -1}, {}, ArgumentError, r"ICS 2: position -1 is not 16 bits"),
        ({2: 7500.0}, {}, ArgumentTypeError, r"ICS 2: position must be an int, not 7500\.0"),
        ({"2": 7500}, {}, ArgumentTypeError, r"ICS number must be an int, not '2'"),
        ({}, {11: 300}, ArgumentError, r"AD11: inputs are set on AD0-AD10"),
        ({}, {1: 1024}, ArgumentError, r"AD1: the input 1024 is outside 0\.\.1023 counts"),
        ({}, {1: -5}, ArgumentError, r"AD1: the input -5 is outside 0\.\.1023"),
        ({}, {1: 300.5}, ArgumentTypeError, r"AD1: the input must be an int"),
    ],
)
def test_measure_refuses_a_servo_channel_or_value_out_of_range_before_setting_any(
    positions: dict[object, object], ad: dict[object, object], error: type, message: str
) -> None:
    """``measure({99: 7500}, {})`` was ignored, ``{2: 70000}`` and AD inputs past 1023 were
    clamped in silence: a typed error (a ValueError; a TypeError for a wrong type) naming the
    key and its range, and no reading of the call is set, the good ones beside it neither."""
    b = Board(IDLE, clock=VirtualClock())

    def readings() -> tuple[dict[int, int], list[int], int]:
        return dict(b._servos.physical), [b.ad_input(ch) for ch in range(11)], b.ad_measured(3)

    before = readings()
    with pytest.raises(error, match=message) as info:
        b.measure({2: 9000, **positions}, {3: 500, **ad})  # type: ignore[dict-item]
    assert isinstance(info.value, ValueError)
    if error is ArgumentTypeError:
        assert isinstance(info.value, TypeError)
    assert readings() == before
    b.measure({2: 9000, 1: 7500}, {3: 500})  # in range; ICS 1 has no virtual servo: ignored
    assert b._servos.physical[2] == 9000 and 1 not in b._servos.physical
    assert b.ad_input(3) == 500 and b.ad_measured(3) == 500


def test_the_other_test_hooks_share_the_rule_and_its_typed_errors() -> None:
    b = Board(IDLE, clock=VirtualClock())
    with pytest.raises(ArgumentError, match="AD11: inputs are set on AD0-AD10"):
        b.set_ad_input(11, 300)
    with pytest.raises(ArgumentError, match=r"ICS 1 has no virtual servo \(those with one: \[0, 2"):
        b.set_servo_position(1, 7500)
    with pytest.raises(ArgumentError, match="ICS 2: position 70000 is not 16 bits"):
        b.set_servo_position(2, 70000)
    with pytest.raises(ArgumentError, match=r"AD0: inputs are set on AD1-AD10 \(AD0 is the supply"):
        ad_inputs_from([(0, 300)])  # emulate --ad 0=300
    with pytest.raises(ArgumentError, match=r"AD2: the input 2000 is outside 0\.\.1023"):
        ad_inputs_from([(2, 2000)])


@pytest.mark.parametrize("data", [5, 0, "03 FE 01", [3, 0xFE, 1], None])
def test_feed_refuses_what_is_not_bytes_before_the_board_moves(data: object) -> None:
    """``feed(5)`` fed five zero bytes (``bytes(5)``), ``feed(0)`` nothing, in silence: an
    ArgumentTypeError (a TypeError), raised before the board ticks or takes a byte."""
    clock = VirtualClock()
    b = Board(IDLE, clock=clock)
    clock.advance(0.1)  # a tick would bring the board up to 0.1 s
    with pytest.raises(ArgumentTypeError, match="data must be bytes, bytearray or memoryview"):
        b.feed(data)  # type: ignore[arg-type]
    assert b.now == 0.0 and b.frames_handled == 0 and not b._decoder.pending
    for ok in (ACK_CHECK, bytearray(ACK_CHECK), memoryview(ACK_CHECK)):
        assert b.feed(ok) == bytes.fromhex("04 FE 06 08")
