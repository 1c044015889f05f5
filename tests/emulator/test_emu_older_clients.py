"""The motion play of the older host libraries, byte for byte, against older-layout images.

The frames below are written out from the public sources of the two libraries (facts, not
code): python-khr3hv ``kondo/khr3hv.py`` (``KHR3HV.play_motion``: its ``__cmd_stopmotion``,
``__motion_bytes[n]``, ``__cmd_restorestatus`` and ``__cmd_querystatus`` strings) and
libkondo4 ``rcb4.c``/``rcb4.h`` as carried by robotlearn/khr3hv (``kondo_init``,
``kondo_play_motion``: RCB4_ADDR_MAIN 03FDh, RCB4_ADDR_MOT_BASE 3000, RCB4_MOT_SIZE 2048).
Both clients are replayed on an emulated board in virtual time, polling every 50 ms as they do.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import pytest

from rcb4hv.emulator import Board, VirtualClock
from rcb4hv.project.simulate import Simulator
from rcb4hv.rom.default import default_image
from rcb4hv.rom.layout import HTH4_22, LAYOUTS, MotionLayout

H = bytes.fromhex
OLDER = LAYOUTS["2.1"]
ACK_MOVE = H("04 00 06 0A")
ACK_CALL = H("04 0C 06 16")

# ---------------------------------------------------------------- python-khr3hv (KHR3HV)
KHR3HV_STOP = H("13 00 02 00 00 00 21 87 FD 03 00 00 00 00 00 00 00 00 BD")
"""MOVE COM->RAM 0000h, 12 bytes: system register 8721h, PC 0003FDh, depth 0, flags 0."""
KHR3HV_RESTORE = H("09 00 02 00 00 00 23 87 B5")
"""System register 8723h (ROM_F set). Its FRAME bits (10) mean 20 ms periods (spec 10.2) until
the main loop writes the board's own register back: a motion made for 15 ms periods plays
20/15 times as long under this client."""
KHR3HV_STRETCH = 20 / 15
KHR3HV_QUERY = H("0A 00 20 00 00 00 00 00 02 2C")
"""Read the system register; the client polls while byte 2 of the reply is 23h ('#')."""
KHR3HV_MOTION = {
    0: H("07 0C B8 0B 00 00 D6"),
    1: H("07 0C B8 13 00 00 DE"),
    2: H("07 0C B8 1B 00 00 E6"),
    10: H("07 0C B8 5B 00 00 26"),
    30: H("07 0C B8 FB 00 00 C6"),
    31: H("07 0C B8 03 01 00 CF"),
    63: H("07 0C B8 03 02 00 D0"),
    100: H("07 0C B8 2B 03 00 F9"),
}
"""Entries of ``__motion_bytes`` (101 CALLs, index n = motion n + 1)."""

# ---------------------------------------------------------------- libkondo4
LK_ACK = H("04 FE 06 08")
LK_GET_OPTIONS = H("0A 00 20 00 00 00 00 00 02 2C")
LK_OPT_SIO, LK_OPT_EEPROM, LK_OPT_RESP, LK_OPT_VEC = 0x01, 0x02, 0x04, 0x08
LK_ADDR_MAIN, LK_ADDR_MOT_BASE, LK_MOT_SIZE = 0x03FD, 3000, 2048

# The same three frames for the default board's options (9B C0), written out:
LK_DEFAULT_BOARD = (
    H("13 00 02 00 00 00 99 C0 FD 03 00 00 00 00 00 00 00 00 6E"),
    H("07 0C B8 0B 00 00 D6"),
    H("09 00 02 00 00 00 93 C0 5E"),
)


def _sum(body: bytes) -> bytes:
    return body + bytes([sum(body) & 0xFF])


def lk_stop(opt: bytes) -> bytes:
    """Step 1 of kondo_play_motion: options without EEPROM/RESP, with SIO; PC 03FDh; 7 zeros."""
    o0 = (opt[0] & ~LK_OPT_EEPROM & ~LK_OPT_RESP) | LK_OPT_SIO
    return _sum(
        bytes((19, 0x00, 0x02, 0, 0, 0, o0, opt[1])) + LK_ADDR_MAIN.to_bytes(3, "little") + bytes(7)
    )


def lk_call(num: int) -> bytes:
    """Step 2: CALL RCB4_MOT_SIZE * (num - 1) + RCB4_ADDR_MOT_BASE, COND 00."""
    a = LK_MOT_SIZE * (num - 1) + LK_ADDR_MOT_BASE
    return _sum(bytes((7, 0x0C)) + a.to_bytes(3, "little") + b"\x00")


def lk_resume(opt: bytes) -> bytes:
    """Step 3: the step-1 options with EEPROM set and VEC cleared."""
    o0 = (((opt[0] & ~LK_OPT_EEPROM & ~LK_OPT_RESP) | LK_OPT_SIO) | LK_OPT_EEPROM) & ~LK_OPT_VEC
    return _sum(bytes((9, 0x00, 0x02, 0, 0, 0, o0, opt[1])))


# ---------------------------------------------------------------- replay on a virtual board


@dataclass
class Played:
    polls: int
    seconds: float
    motion_seen: bool
    word: int
    pc: int
    depth: int


class Link:
    """A board on a virtual clock, spoken to frame by frame like a serial port."""

    def __init__(self, image: bytes) -> None:
        self.clock = VirtualClock()
        self.board = Board(clock=self.clock, rom_image=image)
        self.board.run_for(3.0)  # boot: servos homed, main loop running

    def x(self, frame: bytes, reply_size: int) -> bytes:
        self.clock.advance(len(frame) * 11 / 115200)  # the request's wire time
        reply = self.board.feed(frame)
        assert len(reply) == reply_size, (frame.hex(" "), reply.hex(" "))
        return reply

    def poll(
        self,
        request: bytes,
        playing: Callable[[bytes], bool],
        lay: MotionLayout,
        slot: int,
        limit: float = 60.0,
    ) -> Played:
        """Poll every 50 ms while ``playing(reply)``; track whether the motion slot ran."""
        t0, polls, seen = self.clock.now(), 0, False
        while True:
            reply = self.x(request, 5)
            polls += 1
            seen = seen or lay.motion_at(self.board.pc) == slot
            if not playing(reply):
                break
            assert self.clock.now() - t0 < limit, f"still playing after {limit} s"
            self.board.run_for(0.05)
            seen = seen or lay.motion_at(self.board.pc) == slot
        b = self.board
        return Played(polls, self.clock.now() - t0, seen, b.system_register, b.pc, b.ram[5])

    def khr3hv_play(self, n: int, lay: MotionLayout = OLDER) -> Played:
        """KHR3HV.play_motion(n): stop, CALL, restore, poll while the low byte is 23h."""
        assert self.x(KHR3HV_STOP, 4) == ACK_MOVE
        assert self.x(khr3hv_motion(n), 4) == ACK_CALL
        assert self.x(KHR3HV_RESTORE, 4) == ACK_MOVE
        return self.poll(KHR3HV_QUERY, lambda r: r[2] == 0x23, lay, n + 1)

    def lk_init(self) -> bytes:
        assert self.x(LK_ACK, 4) == LK_ACK
        r = self.x(LK_GET_OPTIONS, 5)
        assert r[1] == 0x00
        return r[2:4]

    def lk_play(self, num: int, lay: MotionLayout = OLDER) -> Played:
        """kondo_play_motion(num, 50 s): stop, CALL, resume, poll until VEC is set."""
        opt = self.x(LK_GET_OPTIONS, 5)[2:4]
        assert self.x(lk_stop(opt), 4)[2] == 0x06
        assert self.x(lk_call(num), 4)[2] == 0x06
        assert self.x(lk_resume(opt), 4)[2] == 0x06
        return self.poll(LK_GET_OPTIONS, lambda r: not r[2] & LK_OPT_VEC, lay, num, 50.0)


def khr3hv_motion(n: int) -> bytes:
    """``__motion_bytes[n]``: the table above where written out, else its rule."""
    return KHR3HV_MOTION.get(n) or _sum(
        bytes((7, 0x0C)) + (0x0BB8 + 0x800 * n).to_bytes(3, "little") + b"\x00"
    )


def test_tables_follow_the_documented_rules() -> None:
    for n, frame in KHR3HV_MOTION.items():
        assert frame == _sum(
            bytes((7, 0x0C)) + OLDER.address(n + 1).to_bytes(3, "little") + b"\x00"
        )
    assert (
        _sum(H("13 00 02 00 00 00 21 87") + OLDER.main_loop.to_bytes(3, "little") + bytes(7))
        == KHR3HV_STOP
    )
    assert (lk_stop(H("9B C0")), lk_call(1), lk_resume(H("9B C0"))) == LK_DEFAULT_BOARD
    assert all(lk_call(n) == khr3hv_motion(n - 1) for n in range(1, 102))


@pytest.fixture
def older_link() -> Iterator[Link]:
    link = Link(default_image(OLDER))
    yield link
    link.board.close()


def _returned(p: Played, lay: MotionLayout = OLDER) -> None:
    """The board is back in its main loop with an empty stack and the program running."""
    assert p.motion_seen
    assert lay.main_loop <= p.pc < lay.main_loop_end and p.depth == 0
    assert p.word & 0x0002 and not p.word & 0x0400  # ROM_F set, no ROMERR


def test_khr3hv_plays_both_default_motions_to_their_return(older_link: Link) -> None:
    sim = Simulator(default_image(OLDER))
    sim.boot()
    for n in (0, 1):
        expected = sim.play(OLDER.address(n + 1)).duration
        p = older_link.khr3hv_play(n)
        _returned(p)
        assert p.word & 0xFF == 0x9B  # the main loop wrote the board's own register back
        assert expected * KHR3HV_STRETCH - 0.06 <= p.seconds <= expected * KHR3HV_STRETCH + 0.1
        assert p.polls >= 2  # it did read 23h while the motion played


def test_libkondo4_init_and_play_send_the_written_out_frames(older_link: Link) -> None:
    opt = older_link.lk_init()
    assert opt == H("9B C0")
    assert (lk_stop(opt), lk_call(1), lk_resume(opt)) == LK_DEFAULT_BOARD
    for num in (1, 2):
        p = older_link.lk_play(num)
        _returned(p)
        assert p.word & LK_OPT_VEC and p.polls >= 2


def test_khr3hv_against_a_2_2_board_stops_with_romerr() -> None:
    """Why the issue was filed: the CALL lands on 0BB8h, inside motion 1's second frame of a
    2.2 image, so the first fetch fails its checksum and the board stops (the return address
    03FDh, inside a 79-byte servo frame there, would fail the same way)."""
    link = Link(default_image(HTH4_22))
    try:
        assert link.x(KHR3HV_STOP, 4) == ACK_MOVE
        assert link.x(khr3hv_motion(0), 4) == ACK_CALL
        assert link.x(KHR3HV_RESTORE, 4) == ACK_MOVE
        link.board.run_for(0.05)
        reply = link.x(KHR3HV_QUERY, 5)
        assert reply[2:4] == H("21 87")  # ROM_F cleared (ROMERR was already in 8723h)
        assert link.board.pc == 0x0BB8 and HTH4_22.motion_at(0x0BB8) == 1
        assert link.board.ram[5] == 1  # stopped on the first fetch after the CALL
    finally:
        link.board.close()


@pytest.fixture(scope="module")
def kxr_older(kxr_project_path: object) -> tuple[bytes, dict[int, float]]:
    """The fixture project moved to 2.1, its image and each completing motion's duration."""
    from rcb4hv import hth4
    from rcb4hv.project.relocate import project_image, relocate_project

    project = relocate_project(hth4.load_project(kxr_project_path), OLDER)  # type: ignore[arg-type]
    image, lay = project_image(project)
    assert lay == OLDER
    sim = Simulator(image)
    sim.boot()
    done = {}
    for m in project.used_motions:
        r = sim.play(OLDER.address(m.slot), slot=m.slot, limit=30.0)
        if r.status == "completed":
            done[m.slot] = r.duration
    return image, done


def test_both_clients_play_every_motion_of_an_older_fixture_image(
    kxr_older: tuple[bytes, dict[int, float]],
) -> None:
    image, done = kxr_older
    assert len(done) == 64
    link = Link(image)
    try:
        assert link.lk_init() == (0x821B).to_bytes(2, "little")
        for slot, seconds in done.items():
            if slot <= 101:
                p = link.khr3hv_play(slot - 1)
                _returned(p)
                # 20 ms instead of 15 ms periods (821Bh) stretch what counts periods, not what
                # counts the 100 ms timers
                assert seconds - 0.06 <= p.seconds <= seconds * KHR3HV_STRETCH + 0.1, slot
            q = link.lk_play(slot)
            _returned(q)
            assert seconds - 0.06 <= q.seconds <= seconds + 0.1, slot
    finally:
        link.board.close()
