"""Protocol core: host CPU time to encode a command and decode its reply, against wire time.

The measured path is what a client does per transaction: ``encode_command`` on a ready command
object, then the reply bytes go through a :class:`FrameDecoder` (framing, checksum) and
``decode_reply``. Wire time is (request + reply bytes) x 11 bits at 1,250,000 baud.
Each figure is the best of several repeats of a tight loop (``timeit``), in one run.
"""

from __future__ import annotations

import timeit
from typing import Any

from rcb4hv import protocol as p

BAUD = 1_250_000
BITS_PER_BYTE = 11
TARGET = 0.02


def wire_us(nbytes: int) -> float:
    return nbytes * BITS_PER_BYTE / BAUD * 1e6


def _transaction(cmd: p.Command, reply: bytes) -> Any:
    decoder = p.FrameDecoder(max_size=p.MAX_REPLY_SIZE)
    encode, decode_reply = p.encode_command, p.decode_reply

    def once() -> None:
        encode(cmd)
        decoder.receive_data(reply)
        frame = decoder.next_frame()
        assert isinstance(frame, bytes)
        decode_reply(frame, cmd)

    return once


def cases() -> list[tuple[str, p.Command, bytes]]:
    single = p.RunSingleServo(2, 30, 7500)
    const = p.RunConstFrameServo(10, {k: 7500 + 10 * k for k in range(35)})
    read = p.Move(p.Com(), p.Ram(0x0092), 126)
    return [
        ("protocol: single servo + ACK", single, p.encode_reply(p.Ack(single.cmd))),
        ("protocol: const-frame 35 servos + ACK", const, p.encode_reply(p.Ack(const.cmd))),
        (
            "protocol: 126-byte RAM read + 129-byte reply",
            read,
            p.encode_reply(p.DataReply(0, bytes(range(126)))),
        ),
    ]


def run() -> list[dict[str, Any]]:
    results = []
    for name, cmd, reply in cases():
        fn = _transaction(cmd, reply)
        number = 20000
        best = min(timeit.repeat(fn, number=number, repeat=7)) / number * 1e6
        wire = wire_us(len(p.encode_command(cmd)) + len(reply))
        results.append(
            {
                "name": name,
                "ours_us": best,
                "wire_us": wire,
                "ratio": best / wire,
                "target": TARGET,
            }
        )
    return results


if __name__ == "__main__":
    for r in run():
        print(r)
