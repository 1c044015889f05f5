"""Host sequences (spec 11.4 and relatives) as golden frames, and their effect on an emulated
board."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.protocol import SYS, Command, encode_command
from rcb4hv.protocol import sequences as seq
from rcb4hv.protocol.memory import ProgramState
from rcb4hv.rom import default_image
from rcb4hv.rom.layout import HTH4_22, LAYOUTS


def H(s: str) -> bytes:
    return bytes.fromhex(s)


def frames(commands: list[Command]) -> list[bytes]:
    return [encode_command(c) for c in commands]


def test_play_motion_is_the_spec_11_4_sequence() -> None:
    # spec 11.4 steps 2 and 3 verbatim; the system register word 801Bh as the client test reads
    assert frames(seq.play_motion(0x801B, HTH4_22.address(1), HTH4_22.main_loop)) == [
        H("09 00 02 00 00 00 10 80 9B"),
        H("11 00 02 02 00 00 4B 04 00 00 00 00 00 00 00 00 64"),
        H("07 0C 80 0B 00 00 9E"),
        H("09 00 02 00 00 00 1B 80 A6"),
    ]


def test_play_motion_older_layout_and_options() -> None:
    old = LAYOUTS["2.1"]
    cmds = seq.play_motion(
        0x0413, old.address(2), old.main_loop, vector=False, clear_rom_error=True
    )
    assert [type(c).__name__ for c in cmds] == ["Move", "Move", "Call", "Move"]
    assert encode_command(cmds[1])[6:9] == H("FD 03 00")  # PC <- 003FDh
    assert cmds[2].address == 0x0BB8 + 0x800  # type: ignore[attr-defined]
    # ROMERR and the play flags cleared, then ICS_F and ROM_F without VEC_F
    assert encode_command(cmds[0])[6:8] == H("10 00")
    assert encode_command(cmds[3])[6:8] == H("13 00")


def test_stop_resume_restart_frames() -> None:
    assert frames(seq.stop_program(0x801B, 0x044B, reset=False)) == [
        H("09 00 02 00 00 00 19 80 A4")
    ]
    stop = frames(seq.stop_program(0x801B, 0x044B))
    assert stop[0] == H("09 00 02 00 00 00 19 80 A4")
    assert stop[1] == H("11 00 02 02 00 00 4B 04 00 00 00 00 00 00 00 00 64")
    assert stop[2] == H("09 00 02 00 00 00 1B 80 A6")
    assert frames(seq.resume_program(0x8019)) == [H("09 00 02 00 00 00 1B 80 A6")]
    # restart after an upload: PC 000000h, depth and flags 0, ROMERR cleared, ROM_F set
    restart = frames(seq.restart_program(0x8419))
    assert restart[0] == H("11 00 02 02 00 00 00 00 00 00 00 00 00 00 00 00 15")
    assert restart[1][6:8] == H("1B 80")
    assert encode_command(seq.system_query()) == H("0A 00 20 00 00 00 00 00 02 2C")


@given(st.integers(0, 0xFFFF), st.booleans(), st.booleans())
def test_play_flags_property(word: int, vector: bool, clear: bool) -> None:
    cmds = seq.play_motion(word, 0x0B80, 0x044B, vector=vector, clear_rom_error=clear)
    suspend = int.from_bytes(encode_command(cmds[0])[6:8], "little")
    resume = int.from_bytes(encode_command(cmds[3])[6:8], "little")
    assert not suspend & seq.PLAY_FLAGS
    assert resume & seq.PLAY_FLAGS == seq.PLAY_FLAGS & ~(0 if vector else SYS.VECTOR_JUMP)
    keep = ~(seq.PLAY_FLAGS | (SYS.ROM_ERROR if clear else 0)) & 0xFFFF
    assert suspend == resume & ~seq.PLAY_FLAGS == word & keep


def test_play_motion_on_an_emulated_board() -> None:
    clock = VirtualClock()
    board = Board(EmulatorConfig(), clock=clock, rom_image=default_image())
    board.tick()
    word = int.from_bytes(board.ram[0:2], "little")
    for cmd in seq.play_motion(word, HTH4_22.address(1), HTH4_22.main_loop):
        assert board.feed(encode_command(cmd))[2] == 0x06  # ACK
    state = ProgramState.unpack(board.ram)
    assert state.call_depth == 1 and state.running
    assert state.system & SYS.ICS_OUTPUT
