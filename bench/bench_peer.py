"""Ours against the peer library (PyPI ``rcb4`` 0.1.6), same frames, same process, same run.

Three blocks, each measured in interleaved rounds (``bench.timing.interleaved``, medians):

* host: the whole library call with the operating system taken out (an in-memory link that
  answers at once, see ``bench.peer``). Ours builds the command from plain values on every
  call, as a user's call does: ``run_const_frame_servo(10, {ics: position})`` for 1, 17 and
  35 servos against the peer's ``servo_angle_vector(ids, positions, velocity=10)``, and
  ``read_ram(0x92, 126)`` against its ``write_move_ram_to_com_command(0x92, 126)`` (one frame
  of its ``angle_vector``). Target: ours <= 0.5 x the peer's, and <= 0.01 of the wire time of
  the request and its reply at 1,250,000 baud.
* pty: both clients against one ``rcb4hv emulate --pty --latency 0`` process. The floor is
  measured beside them: a bare pyserial ``write`` and ``read`` of each client's own frames
  (recorded from one call) to the same emulator. Each client's overhead is its time above its
  floor; target: ours <= 0.5 x the peer's.
* paced loop: read every servo's position and command every servo, against an emulator pacing
  each exchange at 1,250,000 baud (``--pace``: a reply leaves when the request's and its own
  bytes would have crossed the wire). The wire limit of a plan is the request and reply bytes
  of its frames; targets: >= 0.9 of that limit and >= 2 x the peer's loop rate (peer_ratio
  <= 0.5). Two plans: the robot's default cost model (150 µs per frame) and one frame per
  servo (no per-frame cost); the floor beside them is a bare pyserial replay of the same
  frames on the same emulator (what the pty itself costs per exchange).

Each row carries ``peer_us`` and ``peer_ratio`` (ours / peer) for ``results.json``.
"""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Callable
from typing import Any

import serial

from bench import peer
from bench.timing import BAUD, interleaved, wire_us
from rcb4hv.client import LinkCost, Rcb4Client, Robot
from rcb4hv.protocol import Ack, DataReply, encode_reply

IDS17 = (0, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19)
HOST_WIRE_TARGET = 0.01
PEER_TARGET = 0.5


def _row(name: str, ours: float, theirs: float, wire: float, **extra: Any) -> dict[str, Any]:
    return {
        "name": name,
        "ours_us": ours,
        "wire_us": wire,
        "ratio": ours / wire,
        "peer_us": theirs,
        "peer_ratio": ours / theirs,
        "peer_target": PEER_TARGET,
        **extra,
    }


# --------------------------------------------------------------------------- host


def host(quick: bool = False) -> list[dict[str, Any]]:
    rows = []
    ack = encode_reply(Ack(0x10))
    for ids in ((2,), IDS17, tuple(range(35))):
        client = Rcb4Client(peer.CannedTransport(ack))
        ri = peer.canned_peer(ack)
        targets = {k: 7600 + k for k in ids}
        id_list, values = list(targets), list(targets.values())
        fns = {
            "ours": lambda c=client, t=targets: c.run_const_frame_servo(10, t),
            "peer": lambda r=ri, i=id_list, v=values: r.servo_angle_vector(i, v, velocity=10),
        }
        with peer.quiet():
            t = interleaved(fns, quick=quick)
        request = 9 + 2 * len(ids)
        rows.append(
            _row(
                f"vs rcb4 host: 10h {len(ids)} servo(s), build+encode+decode ACK",
                t["ours"],
                t["peer"],
                wire_us(request + len(ack)),
                target=HOST_WIRE_TARGET,
            )
        )
    data = encode_reply(DataReply(0, bytes(range(126))))
    client = Rcb4Client(peer.CannedTransport(data))
    ri = peer.canned_peer(data)
    assert client.read_ram(0x92, 126) == bytes(ri.write_move_ram_to_com_command(0x92, 126))
    t = interleaved(
        {
            "ours": lambda: client.read_ram(0x92, 126),
            "peer": lambda: ri.write_move_ram_to_com_command(0x92, 126),
        },
        quick=quick,
    )
    rows.append(
        _row(
            "vs rcb4 host: 126-byte RAM read, build+encode+decode",
            t["ours"],
            t["peer"],
            wire_us(10 + len(data)),
            target=HOST_WIRE_TARGET,
        )
    )
    return rows


# --------------------------------------------------------------------------- pty


def _emulator(*args: str) -> tuple[subprocess.Popen[str], str]:
    proc = subprocess.Popen(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "emulate", *args],
        stdout=subprocess.PIPE,
        text=True,
    )
    assert proc.stdout is not None
    kind, path = proc.stdout.readline().split()
    assert kind == "PTY", kind
    return proc, path


class _Recorder:
    """Wraps a ``write`` callable and keeps what went through it."""

    def __init__(self, write: Callable[[bytes], Any]) -> None:
        self.write = write
        self.frames: list[bytes] = []

    def __call__(self, data: bytes) -> Any:
        self.frames.append(bytes(data))
        return self.write(data)


def _frames_of(obj: Any, attr: str, call: Callable[[], object]) -> list[bytes]:
    """The frames ``call`` writes through ``obj.<attr>.write``."""
    target = getattr(obj, attr)
    rec = _Recorder(target.write)
    target.write = rec
    try:
        call()
    finally:
        target.write = rec.write
    return rec.frames


def _bare(port: serial.Serial, frames: list[bytes]) -> Callable[[], None]:
    """The floor: pyserial write + read of ``frames`` and their replies, nothing else."""
    pairs = []
    for f in frames:
        port.reset_input_buffer()
        port.write(f)
        head = port.read(1)
        pairs.append((f, len(head + port.read(head[0] - 1))))

    def once() -> None:
        for f, n in pairs:
            port.write(f)
            port.read(n)

    return once


class _Pair:
    """Our Robot and the peer's RCB4Interface on one emulator pty, plus a bare port."""

    def __init__(self, path: str) -> None:
        from rcb4.rcb4interface import RCB4Interface

        self.ri = RCB4Interface()
        with peer.quiet():
            if not self.ri.open(path):
                raise RuntimeError("rcb4 could not open the emulator")
        self.client = Rcb4Client.open(path, timeout=1.0)
        self.robot = Robot(self.client)
        self.robot.wait_ready(timeout=5.0)
        self.port = serial.Serial(path, BAUD, parity="E", timeout=1.0)
        self.ids = self.robot.servo_ids()
        peer_ids = [int(i) for i in self.ri.search_servo_ids()]
        if peer_ids != self.ids:
            raise RuntimeError(f"the clients see different servos: {self.ids} / {peer_ids}")
        self.targets = dict.fromkeys(self.ids, 7500)
        self.values = [7500] * len(self.ids)
        self.ri.hold(self.ids)

    def close(self) -> None:
        self.port.close()
        self.client.close()
        self.ri.close()

    def floors(
        self, ours: Callable[[], object], theirs: Callable[[], object]
    ) -> tuple[Callable[[], None], Callable[[], None], int]:
        our_frames = _frames_of(self.client, "transport", ours)
        their_frames = _frames_of(self.ri, "serial", theirs)
        return _bare(self.port, our_frames), _bare(self.port, their_frames), len(our_frames)


def pty(quick: bool = False) -> list[dict[str, Any]]:
    proc, path = _emulator("--pty", "--latency", "0")
    rows = []
    try:
        pair = _Pair(path)
        try:
            cases: list[tuple[str, Callable[[], object], Callable[[], object]]] = [
                ("ACK check", pair.client.acknowledge_check, lambda: pair.ri.check_ack()),
                (
                    f"{len(pair.ids)}-servo const-frame move",
                    lambda: pair.client.run_const_frame_servo(10, pair.targets),
                    lambda: pair.ri.servo_angle_vector(pair.ids, pair.values, velocity=10),
                ),
                (
                    f"read {len(pair.ids)} positions (degrees)",
                    lambda: pair.robot.angles(pair.ids),
                    lambda: pair.ri.angle_vector(),
                ),
            ]
            for name, ours, theirs in cases:
                floor_ours, floor_theirs, n_frames = pair.floors(ours, theirs)
                with peer.quiet():
                    t = interleaved(
                        {
                            "ours": ours,
                            "peer": theirs,
                            "floor_ours": floor_ours,
                            "floor_peer": floor_theirs,
                        },
                        rounds=11,
                        round_s=0.03,
                        quick=quick,
                    )
                over_ours = max(t["ours"] - t["floor_ours"], 0.0)
                over_peer = max(t["peer"] - t["floor_peer"], 0.0)
                rows.append(
                    _row(
                        f"vs rcb4 pty: {name}",
                        t["ours"],
                        t["peer"],
                        t["floor_ours"],
                        peer_target=None,  # the target is on the time above the floor
                        note=(
                            f"wire_us = floor (bare pyserial, our {n_frames} frame(s)); "
                            f"peer floor {t['floor_peer']:.1f} us"
                        ),
                    )
                )
                rows.append(
                    {
                        "name": f"vs rcb4 pty overhead above the floor: {name}",
                        "ours_us": over_ours,
                        "wire_us": t["floor_ours"],
                        "ratio": over_ours / t["floor_ours"],
                        "peer_us": over_peer,
                        "peer_ratio": over_ours / over_peer if over_peer else float("inf"),
                        "peer_target": PEER_TARGET,
                    }
                )
        finally:
            pair.close()
    finally:
        with proc:  # closes its stdout pipe, then waits
            proc.terminate()
    return rows


# --------------------------------------------------------------------------- paced loop


def paced_loop(quick: bool = False) -> list[dict[str, Any]]:
    proc, path = _emulator("--pty", "--latency", "0", "--pace")
    try:
        pair = _Pair(path)
        try:
            client, ri = pair.client, pair.ri
            per_servo = Robot(client, link_cost=LinkCost(frame_overhead_s=0.0))
            per_servo._servos = pair.robot._servos  # same servo table, other read plan

            def loop(robot: Robot) -> Callable[[], None]:
                def once() -> None:
                    robot.positions(pair.ids)
                    client.run_const_frame_servo(1, pair.targets)

                return once

            def theirs() -> None:
                ri.angle_vector()
                ri.servo_angle_vector(pair.ids, pair.values, velocity=1)

            fns: dict[str, Callable[[], object]] = {"peer": theirs}
            plans = {}
            for name, robot in (("ours", pair.robot), ("ours_per_servo", per_servo)):
                fns[name] = loop(robot)
                frames = _frames_of(client, "transport", fns[name])
                fns[f"floor_{name}"] = _bare(pair.port, frames)
                wire = (
                    sum(len(f) for f in frames)
                    + sum(n + 3 for _, n in robot.read_plan(pair.ids))
                    + 4
                )
                plans[name] = (len(frames), wire)
            with peer.quiet():
                t = interleaved(fns, rounds=9, round_s=0.1, quick=quick)
        finally:
            pair.close()
    finally:
        with proc:  # closes its stdout pipe, then waits
            proc.terminate()
    rows = []
    for name, label in (("ours", "cost-model plan"), ("ours_per_servo", "one frame per servo")):
        frames, wire = plans[name]
        limit = wire_us(wire)
        ours, floor = t[name], t[f"floor_{name}"]
        rows.append(
            _row(
                f"vs rcb4 paced loop, {label}: read {len(pair.ids)} + write {len(pair.ids)}",
                ours,
                t["peer"],
                limit,
                target=0.9,
                lower_is_better=False,
                ratio=limit / ours,
                note=(
                    f"ours {1e6 / ours:.0f} Hz, peer {1e6 / t['peer']:.0f} Hz (x"
                    f"{t['peer'] / ours:.2f}), wire limit of the plan ({frames} frames, {wire} "
                    f"bytes at {BAUD} baud) {1e6 / limit:.0f} Hz; bare pyserial replay of the "
                    f"same frames {1e6 / floor:.0f} Hz (ours reaches {floor / ours:.2f} of it); "
                    "ratio = wire limit / ours"
                ),
            )
        )
    return rows


def run(quick: bool = False) -> list[dict[str, Any]]:
    why = peer.available()
    if why is not None:
        print(f"(skipping the peer rows: {why})")
        return []
    return host(quick) + pty(quick) + paced_loop(quick)


if __name__ == "__main__":
    for r in run():
        print(
            f"{r['name']:<70} ours {r['ours_us']:9.1f} peer {r['peer_us']:9.1f} "
            f"x{r['peer_ratio']:.2f}  ref {r['wire_us']:9.1f} ratio {r['ratio']:.4f}"
        )
