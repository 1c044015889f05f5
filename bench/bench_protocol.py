"""Protocol core: host CPU time to build a command, encode it and decode its reply, against
wire time.

The measured path is what a user of :mod:`rcb4hv.protocol` does per transaction: build the
command from plain values (``RunConstFrameServo(10, {ics: position, ...})``, validation
included), ``encode_command`` it, then the reply bytes go through a :class:`FrameDecoder`
(framing, checksum) and ``decode_reply``. Wire time is (request + reply bytes) x 11 bits at
1,250,000 baud. Each figure is the median of interleaved rounds (``bench.timing``), in one run.
The client's own path (fast frame builders, whole call on an in-memory link) is in
``bench.bench_peer``'s host rows.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from bench.timing import interleaved, wire_us
from rcb4hv import protocol as p

TARGET = 0.01
IDS17 = (0, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19)


def _transaction(build: Callable[[], p.Command], reply: bytes) -> Callable[[], None]:
    decoder = p.FrameDecoder(max_size=p.MAX_REPLY_SIZE)
    encode, decode_reply = p.encode_command, p.decode_reply

    def once() -> None:
        cmd = build()
        encode(cmd)
        decoder.receive_data(reply)
        frame = decoder.next_frame()
        assert isinstance(frame, bytes)
        decode_reply(frame, cmd)

    return once


def _servos(ids: tuple[int, ...]) -> tuple[str, Callable[[], p.Command], bytes]:
    targets = {k: 7500 + 10 * k for k in ids}
    return (
        f"protocol: build+encode+decode ACK, 10h {len(ids)} servo(s)",
        lambda: p.RunConstFrameServo(10, targets),
        p.encode_reply(p.Ack(p.Op.CONST_FRAME_SERVO)),
    )


def cases() -> list[tuple[str, Callable[[], p.Command], bytes]]:
    return [
        (
            "protocol: build+encode+decode ACK, 0Fh single servo",
            lambda: p.RunSingleServo(2, 30, 7500),
            p.encode_reply(p.Ack(p.Op.SINGLE_SERVO)),
        ),
        _servos((2,)),
        _servos(IDS17),
        _servos(tuple(range(35))),
        (
            "protocol: build+encode+decode, 126-byte RAM read",
            lambda: p.Move(p.Com(), p.Ram(0x0092), 126),
            p.encode_reply(p.DataReply(0, bytes(range(126)))),
        ),
    ]


def run(quick: bool = False) -> list[dict[str, Any]]:
    all_cases = cases()
    fns = {name: _transaction(build, reply) for name, build, reply in all_cases}
    times = interleaved(fns, quick=quick)
    results = []
    for name, build, reply in all_cases:
        wire = wire_us(len(p.encode_command(build())) + len(reply))
        results.append(
            {
                "name": name,
                "ours_us": times[name],
                "wire_us": wire,
                "ratio": times[name] / wire,
                "target": TARGET,
            }
        )
    return results


if __name__ == "__main__":
    for r in run():
        print(r)
