"""Client: round trips over a real pty against the emulator, against the wire-limited rate.

What is measured: wall-clock time per operation of the whole host stack (Robot/Rcb4Client,
SerialTransport on a pty, pyserial) plus the emulator serving the other end
of the pty in a background thread of the same process (``PtyServer``, reply latency set to 0).
The wire figure is the time the request and reply bytes take on the real link at 1,250,000
baud with 11 bits a byte (8E1), with no board processing time: the best a real link allows.
ratio = ours / wire: below 1 means we would not be the bottleneck on a real cable.

Cases: ACK check; one RunSingleServo; a bulk read of every servo's measured position (the
cheapest MOVE reads under the robot's link cost model, see ``Robot.read_plan``); a
control-loop cycle = that read plus one RunConstFrameServo commanding every servo.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

from rcb4hv.client import Rcb4Client, Robot

BAUD = 1_250_000
BITS_PER_BYTE = 11


def wire_us(nbytes: int) -> float:
    return nbytes * BITS_PER_BYTE / BAUD * 1e6


def _per_op_us(fn: Callable[[], object], seconds: float = 1.0) -> float:
    fn()
    best = float("inf")
    for _ in range(3):
        n = 0
        t0 = time.perf_counter()
        while True:
            fn()
            n += 1
            elapsed = time.perf_counter() - t0
            if elapsed > seconds / 3:
                break
        best = min(best, elapsed / n * 1e6)
    return best


def run(quick: bool = False) -> list[dict[str, Any]]:
    from rcb4hv.emulator import Board, EmulatorConfig, PtyServer, RealClock

    board = Board(EmulatorConfig(min_reply_latency_s=0.0), clock=RealClock(speed=10.0))
    results: list[dict[str, Any]] = []
    try:
        with PtyServer(board) as srv:
            client = Rcb4Client.open(str(srv.path), timeout=1.0)
            try:
                robot = Robot(client)
                robot.wait_ready(timeout=5.0)
                ids = robot.servo_ids()
                reads = robot.read_plan(ids)
                read_wire = sum(wire_us(10 + n + 3) for _, n in reads)
                cmd_wire = wire_us(9 + 2 * len(ids) + 4)
                targets = dict.fromkeys(ids, 7500)

                def loop() -> None:
                    robot.positions(ids)
                    client.run_const_frame_servo(1, targets)

                cases: list[tuple[str, Callable[[], object], float]] = [
                    ("client/pty: ACK check round trip", client.acknowledge_check, wire_us(7)),
                    (
                        "client/pty: RunSingleServo + ACK",
                        lambda: client.run_single_servo(ids[0], 10, 7500),
                        wire_us(11),
                    ),
                    (
                        f"client/pty: read {len(ids)} servo positions ({len(reads)} frames)",
                        lambda: robot.positions(ids),
                        read_wire,
                    ),
                    (
                        f"client/pty: control loop, read+command {len(ids)} servos",
                        loop,
                        read_wire + cmd_wire,
                    ),
                ]
                for name, fn, wire in cases:
                    ours = _per_op_us(fn, 0.03 if quick else 1.0)
                    results.append(
                        {
                            "name": name,
                            "ours_us": ours,
                            "wire_us": wire,
                            "ratio": ours / wire,
                            "note": f"{1e6 / ours:.0f}/s vs wire-limited {1e6 / wire:.0f}/s",
                        }
                    )
            finally:
                client.close()
    finally:
        board.close()
    return results


if __name__ == "__main__":
    for r in run():
        print(
            f"{r['name']:<58} {r['ours_us']:9.1f} µs  wire {r['wire_us']:8.1f} µs  "
            f"ratio {r['ratio']:.2f}  ({r['note']})"
        )
