"""Emulator benchmarks: service time per frame vs wire time; virtual-time motion speed."""

from __future__ import annotations

import subprocess
import sys
import time
from typing import Any

import serial

from rcb4hv.emulator import Board, EmulatorConfig, VirtualClock
from rcb4hv.protocol import ALWAYS, Call, Jump, RunConstFrameServo, encode_command
from rcb4hv.rom import ImageDescription, ImageMotion, ImageServo, build_image, layout

BAUD = 1_250_000
FRAMES = {
    "ack check": bytes.fromhex("03 FE 01"),
    "read 126 bytes (rcb4 angle_vector)": bytes.fromhex("0A 00 20 00 00 00 92 00 7E 3A"),
    "single servo move": bytes.fromhex("07 0F 02 1E 4C 1D 9F"),
    "servo move, 17 servos": encode_command(
        RunConstFrameServo(
            10, {k: 7600 for k in (0, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19)}
        )
    ),
}


def wire_us(request: bytes, reply: bytes) -> float:
    return (len(request) + len(reply)) * 11 / BAUD * 1e6


def in_process(n: int = 3000) -> list[dict[str, Any]]:
    out = []
    clock = VirtualClock()
    board = Board(clock=clock)
    board.run_for(3.0)  # booted, main loop running
    for name, frame in FRAMES.items():
        reply = board.feed(frame)
        t0 = time.perf_counter()
        for _ in range(n):
            clock.advance(0.0005)
            board.feed(frame)
        ours = (time.perf_counter() - t0) / n * 1e6
        w = wire_us(frame, reply)
        out.append(
            {
                "name": f"emulator in-process: {name}",
                "ours_us": ours,
                "wire_us": w,
                "ratio": ours / w,
                "target": 0.5,
                "lower_is_better": True,
            }
        )
    return out


_ECHO_SERVER = """
import os, pty, select, sys, tty
reply = bytes.fromhex(sys.argv[1])
master, slave = pty.openpty()
tty.setraw(slave)
print("PTY", os.ttyname(slave), flush=True)
while True:
    if select.select([master], [], [], 1.0)[0]:
        os.read(master, 4096)
        os.write(master, reply)
"""


def _serve(args: list[str]) -> tuple[subprocess.Popen[str], str]:
    proc = subprocess.Popen([sys.executable, "-c", *args], stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    return proc, proc.stdout.readline().split()[1]


def _round_trip_us(path: str, frame: bytes, n: int = 400) -> tuple[float, bytes]:
    """Best-of-5 mean time of ``n`` times ``frame`` -> reply through pyserial at 1,250,000
    baud 8E1."""
    port = serial.Serial(path, BAUD, parity="E", timeout=2)
    try:
        port.write(frame)
        reply = port.read(1)
        reply += port.read(reply[0] - 1)
        best = float("inf")
        for _ in range(5):
            t0 = time.perf_counter()
            for _ in range(n):
                port.write(frame)
                port.read(len(reply))
            best = min(best, (time.perf_counter() - t0) / n * 1e6)
        return best, reply
    finally:
        port.close()


def pty_round_trip(n: int = 400) -> list[dict[str, Any]]:
    """Round trips through ``rcb4hv emulate --pty`` run as its own process (as users run it),
    driven by pyserial at 1,250,000 baud 8E1, minimum reply latency 0; and, side by side, the
    same exchange with a trivial Python server that answers the same bytes over a pty (the
    floor of two process wake-ups and the tty layer, which varies with the machine). The
    emulator's service time is the difference."""
    out = []
    emu, path = _serve(
        ["from rcb4hv.cli.main import main; main()", "emulate", "--pty", "--latency", "0"]
    )
    try:
        measured = {name: _round_trip_us(path, frame, n) for name, frame in FRAMES.items()}
    finally:
        with emu:  # closes its stdout pipe, then waits
            emu.terminate()
    for name, frame in FRAMES.items():
        ours, reply = measured[name]
        echo, floor_path = _serve([_ECHO_SERVER, reply.hex()])
        try:
            floor, _ = _round_trip_us(floor_path, frame, n)
        finally:
            with echo:  # closes its stdout pipe, then waits
                echo.kill()
        w = wire_us(frame, reply)
        out.append(
            {
                "name": f"emulator pty round trip (own process): {name}",
                "ours_us": ours,
                "wire_us": w,
                "ratio": ours / w,
                "target": 0.5,
                "lower_is_better": True,
                "note": f"pty floor (Python echo of the same bytes) {floor:.1f} us",
            }
        )
        service = max(0.0, ours - floor)
        out.append(
            {
                "name": f"emulator pty service time above the pty floor: {name}",
                "ours_us": service,
                "wire_us": w,
                "ratio": service / w,
                "target": 0.5,
                "lower_is_better": True,
            }
        )
    return out


def motion_speed() -> list[dict[str, Any]]:
    ics = list(range(22))
    poses = [
        RunConstFrameServo(20, {k: 7500 + (300 if (i + k) % 2 else -300) for k in ics})
        for i in range(100)
    ]
    # 53-byte poses: 38 fit a 2048-byte slot; chain three slots with JUMPs
    motions = (
        ImageMotion(1, [*poses[:38], Jump(layout.motion_address(2), ALWAYS)]),
        ImageMotion(2, [*poses[38:76], Jump(layout.motion_address(3), ALWAYS)]),
        ImageMotion(3, poses[76:]),
    )
    desc = ImageDescription(
        servos=tuple(ImageServo(k) for k in ics),
        startup_motion=None,
        motions=motions,
    )
    clock = VirtualClock()
    board = Board(
        EmulatorConfig(virtual_servos=tuple(ics)), clock=clock, rom_image=build_image(desc)
    )
    board.run_for(3.0)
    a1 = layout.motion_address(1)
    t0 = time.perf_counter()
    v0 = clock.now()
    board.feed(bytes.fromhex("11 00 02 02 00 00 4B 04 00 00 00 00 00 00 00 00 64"))
    board.feed(encode_command(Call(a1, ALWAYS)))
    periods0 = board.periods
    while board.pc >= a1 or board.ram[5]:
        board.run_for(1.0)
    assert board.periods - periods0 >= 100 * 21
    wall = time.perf_counter() - t0
    virtual = clock.now() - v0
    return [
        {
            "name": "emulator virtual time: 100 poses x 22 servos (wall s / board s)",
            "ours_us": wall * 1e6,
            "wire_us": virtual * 1e6,
            "ratio": wall / virtual,
            "target": 0.001,
            "lower_is_better": True,
            "note": "ours_us = wall time, wire_us = the motion's board (virtual) time",
        }
    ]


def run(quick: bool = False) -> list[dict[str, Any]]:
    feeds, trips = (10, 10) if quick else (3000, 400)
    return in_process(feeds) + pty_round_trip(trips) + motion_speed()


if __name__ == "__main__":
    for r in run():
        print(f"{r['name']:<62} {r['ours_us']:>10.2f} {r['wire_us']:>10.2f} {r['ratio']:>8.4f}")
