"""A deliberately tiny board for unit tests that must not depend on the emulator: it answers
from a RAM/ROM bytearray using the protocol core, and records every request frame."""

from __future__ import annotations

from rcb4hv.errors import ProtocolError
from rcb4hv.protocol import (
    Ack,
    AcknowledgeCheck,
    Com,
    Data,
    DataReply,
    FrameDecoder,
    GetVersionInfo,
    Move,
    Nak,
    NeedData,
    Ram,
    Reply,
    Rom,
    VersionReply,
    decode_command,
    encode_reply,
)

VERSION = b"CB-4 V1.0      090715          \xc7"


class FakeBoard:
    def __init__(self) -> None:
        self.ram = bytearray(0x490)
        self.rom = bytearray(0x40000)
        self.requests: list[bytes] = []
        self._decoder = FrameDecoder(resync="frame")
        self.closed = False

    def tick(self) -> None:
        pass

    def take_output(self) -> bytes:
        return b""

    def close(self) -> None:
        self.closed = True

    def feed(self, data: bytes) -> bytes:
        self._decoder.receive_data(data)
        out = bytearray()
        while True:
            try:
                frame = self._decoder.next_frame()
            except ProtocolError as exc:
                bad = getattr(exc, "frame", b"")
                if len(bad) > 1:
                    out += encode_reply(Nak(bad[1]))
                continue
            if isinstance(frame, NeedData):
                return bytes(out)
            self.requests.append(frame)
            out += encode_reply(self._execute(frame))

    def _execute(self, frame: bytes) -> Reply:
        cmd = decode_command(frame)
        if isinstance(cmd, AcknowledgeCheck):
            return Ack(0xFE)
        if isinstance(cmd, GetVersionInfo):
            return VersionReply(VERSION)
        if isinstance(cmd, Move):
            mem = {Ram: self.ram, Rom: self.rom}
            size = cmd.nbytes
            if isinstance(cmd.src, Data):
                data = cmd.src.data
            elif isinstance(cmd.src, (Ram, Rom)):
                m = mem[type(cmd.src)]
                data = bytes(m[cmd.src.address : cmd.src.address + size])
            else:
                return Nak(0)
            if isinstance(cmd.dst, Com):
                return DataReply(0, data)
            if isinstance(cmd.dst, (Ram, Rom)):
                m = mem[type(cmd.dst)]
                m[cmd.dst.address : cmd.dst.address + size] = data
                return Ack(0)
            return Nak(0)
        return Ack(cmd.cmd)
