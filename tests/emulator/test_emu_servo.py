"""Servo interpolation (spec 9), free/hold, base and mixing, virtual servos, fast-forward."""

from __future__ import annotations

from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.emulator.memmap import UPDATE_FLAGS
from rcb4hv.protocol import RunConstFrameServo, RunSeriesServo, RunSingleServo
from tests.emulator.conftest import IDLE, x

BLK = 0x0090


def servo_board(ics: int = 0, *, start: int = 7500, sysreg: int = 0x01, **cfg: object) -> Board:
    config = EmulatorConfig(power_on_system_register=sysreg, **cfg)  # type: ignore[arg-type]
    b = Board(config, clock=VirtualClock(), rom_image=b"\xff" * 0x40000)
    alloc(b, ics, BLK + 20 * ics, start)
    return b


def alloc(b: Board, ics: int, blk: int, start: int = 7500, base: int = 0) -> None:
    b.ram[0x44 + 2 * ics : 0x46 + 2 * ics] = blk.to_bytes(2, "little")
    b.ram[blk : blk + 20] = bytes(20)
    b.ram[blk + 2 : blk + 4] = (base & 0xFFFF).to_bytes(2, "little")
    b.ram[blk + 6 : blk + 8] = start.to_bytes(2, "little")
    b.ram[blk + 14 : blk + 16] = b"\xff\xff"
    b.ram[blk + 17 : blk + 19] = b"\xff\xff"


def w(b: Board, a: int) -> int:
    return int.from_bytes(b.ram[a : a + 2], "little")


def expected_trace(start: int, end: int, speed: int) -> list[int]:
    """Spec 9: output after period k = end -/+ |width| * remaining // speed."""
    width = end - start
    out = []
    for k in range(1, speed + 1):
        rem = speed - k
        a = abs(width) * rem // speed
        out.append(end - a if width >= 0 else end + a)
    out.append(end)
    return out


@settings(max_examples=40)
@given(
    start=st.integers(3500, 11500),
    end=st.integers(3500, 11500),
    speed=st.integers(1, 255),
    frame=st.integers(0, 3),
)
def test_interpolation_trace_matches_the_formula(
    start: int, end: int, speed: int, frame: int
) -> None:
    b = servo_board(0, start=start, sysreg=0x01 | frame << 4)
    trace: list[tuple[float, int]] = []
    b.add_output_listener(lambda t, outs: trace.append((t, outs[0])))
    assert x(b, RunSingleServo(0, speed, end)) == bytes.fromhex("04 0F 06 19")
    period = (10, 15, 20, 25)[frame] / 1000
    b.run_for(period * (speed + 1) + 1e-6)
    assert [v for _, v in trace[: speed + 1]] == expected_trace(start, end, speed)
    assert abs(trace[0][0] - period) < 1e-6
    assert b.ram[BLK + 8] == 0 and w(b, BLK + 6) == end and b.ram[7] == 0


@settings(max_examples=40)
@given(
    start=st.integers(3500, 11500),
    end=st.integers(3500, 11500),
    speed=st.integers(1, 255),
    steps=st.integers(0, 300),
    gap=st.integers(1, 50),
)
def test_fast_forward_equals_stepping(
    start: int, end: int, speed: int, steps: int, gap: int
) -> None:
    """The closed-form skip leaves RAM exactly as stepping every period does."""
    boards = [servo_board(4, start=start, sysreg=0x03), servo_board(4, start=start, sysreg=0x03)]
    boards[1].add_output_listener(lambda t, outs: None)  # a listener forces stepping
    for b in boards:
        b.ram[0x90 + 20 * 4 + 2 : 0x90 + 20 * 4 + 4] = (50).to_bytes(2, "little")
        x(b, RunSingleServo(4, speed, end))
        b.rom[0:7] = bytes.fromhex("07 0B 00 00 00 00 12")  # JUMP 0 (loop) once flags clear
        b.run_for(steps * 0.01 + gap * 0.001)
    assert boards[0].ram == boards[1].ram
    assert boards[0].periods == boards[1].periods


def test_move_restarts_from_current_output() -> None:
    b = servo_board(0, start=7000)
    x(b, RunSingleServo(0, 10, 8000))
    b.run_for(0.05)  # 5 periods: 7000 + 1000 * 5 / 10
    assert w(b, BLK + 6) == 7500
    x(b, RunSingleServo(0, 5, 7000))
    assert w(b, BLK + 12) == (-500) & 0xFFFF
    b.run_for(0.06)
    assert w(b, BLK + 6) == 7000


def test_speed_zero_behaves_as_one() -> None:
    b = servo_board(0, start=7000)
    x(b, RunSingleServo(0, 0, 8000))
    assert b.ram[BLK + 8] == 1
    b.run_for(0.0105)
    assert w(b, BLK + 6) == 8000
    imm = servo_board(0, start=7000, speed_zero="immediate")
    x(imm, RunSingleServo(0, 0, 8000))
    assert w(imm, BLK + 6) == 8000 and imm.ram[7] == 0


def test_single_servo_flag_clears_the_others() -> None:
    b = servo_board(0)
    alloc(b, 3, 0x0100)
    b.ram[7:12] = b"\xff\xff\x00\x00\x00"
    x(b, RunSingleServo(3, 10, 8000))
    assert b.ram[7:12] == bytes((0x08, 0, 0, 0, 0))
    x(b, RunSingleServo(0, 10, 8000, set_update_flag=False))
    assert b.ram[7:12] == bytes((0x08, 0, 0, 0, 0))


def test_const_frame_flags_leave_unselected_and_skip_unallocated() -> None:
    b = servo_board(0)
    b.ram[8] = 0x80  # ICS 15 flag from before
    reply = x(b, RunConstFrameServo(5, {0: 8000, 9: 8000}))
    assert reply == bytes.fromhex("04 10 06 1A")
    assert b.ram[7] == 0x01 and b.ram[8] == 0x80  # ICS 9 unallocated: flag 0, no error
    b2 = servo_board(0, unselected_update_flags="clear")
    b2.ram[8] = 0x80
    x(b2, RunConstFrameServo(5, {0: 8000}))
    assert b2.ram[7:9] == b"\x01\x00"


def test_series_servo_settings() -> None:
    b = servo_board(0)
    assert x(b, RunSeriesServo([(0, 3, 8000)])) == bytes.fromhex("04 11 06 1B")
    assert b.ram[BLK + 8] == 3
    nak = servo_board(0, series_servo="nak")
    assert x(nak, RunSeriesServo([(0, 3, 8000)])) == bytes.fromhex("04 11 15 2A")
    reset = servo_board(0, series_servo="reset")
    assert x(reset, RunSeriesServo([(0, 3, 8000)])) == b""
    assert reset.alloc(0) == 0xFFFF  # power-on RAM


def test_free_hold_and_reported_position() -> None:
    b = servo_board(2, start=7500)
    base_blk = BLK + 40
    b.ram[base_blk + 2 : base_blk + 4] = (100).to_bytes(2, "little")
    b.run_for(0.011)
    assert w(b, base_blk + 4) == 7500  # reports actual (7600) - base
    st = b.servo_state(2)
    assert st is not None and st.torque and st.sent == 7600
    x(b, RunSingleServo(2, 1, 0x8000))
    b.run_for(0.011)
    st = b.servo_state(2)
    assert st is not None and not st.torque
    b.set_servo_position(2, 9100)  # pushed by hand while free
    b.run_for(0.011)
    assert w(b, base_blk + 4) == 9000
    x(b, RunSingleServo(2, 1, 0x7FFF))  # hold where it is
    b.run_for(0.011)
    st = b.servo_state(2)
    assert st is not None and st.torque and w(b, base_blk + 4) == 9000
    # a move from hold starts from the actual position
    x(b, RunSingleServo(2, 4, 8000))
    assert w(b, base_blk + 6) == 9000
    # free/hold sent value with and without the base (spec 13 #14)
    x(b, RunSingleServo(2, 1, 0x8000))
    assert b.servo_outputs()[2] == 0x8000 + 100
    omit = servo_board(2, free_hold_base="omit")
    x(omit, RunSingleServo(2, 1, 0x8000))
    assert omit.servo_outputs()[2] == 0x8000


def test_7fff_as_free_setting() -> None:
    b = servo_board(0, position_7fff="free")
    x(b, RunSingleServo(0, 1, 0x7FFF))
    b.run_for(0.011)
    st = b.servo_state(0)
    assert st is not None and not st.torque


def test_mixing_adds_to_the_sent_value() -> None:
    b = servo_board(0, start=7500)
    # mix 1: RAM word 0462 x 3; mix 2: ICS 0 byte at offset 1 (ID = 5) x -2
    b.ram[BLK + 1] = 5
    b.ram[BLK + 14 : BLK + 16] = (0x4000 | 0x0462).to_bytes(2, "little")
    b.ram[BLK + 16] = 3
    b.ram[BLK + 17 : BLK + 19] = (0x8000 | 0x0001).to_bytes(2, "little")
    b.ram[BLK + 19] = 0x80 | 2
    b.ram[0x462:0x464] = (-10 & 0xFFFF).to_bytes(2, "little")
    assert b.servo_outputs()[0] == 7500 - 30 - 10
    b.run_for(0.011)
    assert w(b, BLK + 4) == 7460


def test_measured_only_for_virtual_servos_with_ics_output() -> None:
    b = servo_board(1)  # ICS 1 has no virtual servo in the default set
    alloc(b, 0, BLK)
    b.run_for(0.05)
    assert w(b, BLK + 20 + 4) == 0 and w(b, BLK + 4) == 7500
    off = servo_board(0, sysreg=0x00)  # ICS_F clear: no servo communication
    off.run_for(0.05)
    assert w(off, BLK + 4) == 0


def test_rcb4_style_probe_sees_exactly_the_virtual_servos() -> None:
    b = Board(IDLE, clock=VirtualClock())
    b.ram[0] |= 0x01
    table = b"".join((0x90 + 20 * n).to_bytes(2, "little") for n in range(35))
    for n in range(35):
        b.ram[0x90 + 20 * n + 4 : 0x90 + 20 * n + 9] = bytes.fromhex("00 00 00 80 00")
    b.ram[0x44 : 0x44 + 70] = table
    b.run_for(0.1)
    alive = [n for n in range(35) if w(b, 0x90 + 20 * n + 4) > 0]
    assert alive == list(b.virtual_servos)


def test_stretch_kept_per_servo(idle: Board) -> None:
    assert x(idle, "0C 12 15 00 00 00 00 01 3C 3C 3C E8") == bytes.fromhex("04 12 06 1C")
    assert idle.stretch == {0: 60, 2: 60, 4: 60}


def test_servo_mode_reads_the_output_without_the_trim() -> None:
    """A trimmed servo sends 8000h + trim when free: the mode reads the block's output, so a
    negative trim (sent value below 8000h) or a positive one (above) is still "free"."""
    for trim in (-100, 100):
        b = servo_board(0, start=7500)
        b.ram[BLK + 2 : BLK + 4] = (trim & 0xFFFF).to_bytes(2, "little")
        assert b.servo_mode(0) == "angle"
        assert b.sent_angles() == {0: 7500 + trim}
        assert b.sent_angles(trim=False) == {0: 7500}
        x(b, RunSingleServo(0, 1, 0x8000))
        b.run_for(0.011)
        assert b.servo_outputs()[0] == 0x8000 + trim  # the sent value is not 8000h
        assert b.servo_mode(0) == "free" and b.sent_angles() == {0: None}
        x(b, RunSingleServo(0, 1, 0x7FFF))
        b.run_for(0.011)
        assert b.servo_mode(0) == "hold" and b.sent_angles() == {0: None}
    assert servo_board(1).servo_mode(0) is None  # no block


def test_servo_mode_honours_position_7fff() -> None:
    b = servo_board(0, position_7fff="free")
    x(b, RunSingleServo(0, 1, 0x7FFF))
    b.run_for(0.011)
    assert b.servo_mode(0) == "free"


def test_update_flag_wait_counts_the_periods_left() -> None:
    b = servo_board(0, start=7500)
    assert b.update_flag_wait() == 0  # no flag set
    x(b, RunSingleServo(0, 5, 8000))
    assert b.update_flag_wait() == 6  # 5 steps, the flag clears the period after the last
    b.run_for(0.011)
    assert b.update_flag_wait() == 5
    x(b, RunSingleServo(0, 1, 0x7FFF, set_update_flag=False))  # a hold stops the move
    b.ram[UPDATE_FLAGS] |= 1
    assert b.update_flag_wait() is None  # a flag no move will ever clear


def test_the_virtual_servos_are_the_images_robot(kxr_project_path: Path) -> None:
    """With no ``virtual_servos`` the board has the servos its image's allocation table
    configures (the KXR-L2's ICS 8 and 9 too, which the default humanoid lacks), as
    ``project simulate`` has; an erased image, which configures none, the default humanoid's;
    an image uploaded for another robot, from then on."""
    from rcb4hv.emulator.config import DEFAULT_SERVOS
    from rcb4hv.hth4 import load_project
    from rcb4hv.project.relocate import project_image
    from rcb4hv.rom.calibration import image_servos

    image, _ = project_image(load_project(kxr_project_path))
    kxr = image_servos(image)
    assert {8, 9} <= set(kxr) and not {8, 9} & set(DEFAULT_SERVOS)
    board = Board(EmulatorConfig(), clock=VirtualClock(), rom_image=image)
    board.run_for(3.0)  # the start-up program allocates the blocks and homes the robot
    assert board.virtual_servos == kxr
    assert all(w(board, board.alloc(k) + 4) > 0 for k in kxr)  # every servo reports
    assert Board(clock=VirtualClock(), rom_image=b"\xff" * 0x40000).virtual_servos == (
        DEFAULT_SERVOS
    )
    assert Board(EmulatorConfig(virtual_servos=(2, 3)), rom_image=image).virtual_servos == (2, 3)
    board.load_rom(0, bytes(Board(clock=VirtualClock()).rom))  # the default image, uploaded
    assert board.virtual_servos == DEFAULT_SERVOS
    board.load_rom(0, image)
    assert board.virtual_servos == kxr
