"""The RCB-4HV's commands, one method each: the data commands (00h-0Ah), control flow
(0Bh-0Eh) and the servo commands (0Fh-12h) of Kondo's command reference.

:class:`AsyncRcb4Commands` is the base of :class:`~rcb4hv.aio.client.AsyncRcb4Client`, which
sends them (:meth:`transact`, :meth:`_ack`); the transactions, the system commands and the
memory helpers are there. One source, two faces: ``tools/unasync.py`` writes
``src/rcb4hv/client/core_commands.py`` (blocking) from this module (asyncio).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from rcb4hv.client.plans import data_of
from rcb4hv.protocol import (
    ALWAYS,
    Add,
    And,
    Call,
    Command,
    CommunicateDevice,
    Condition,
    DataReply,
    Destination,
    Div,
    Jump,
    Mod,
    Move,
    Mul,
    Not,
    Or,
    Reply,
    Return,
    RunSeriesServo,
    SetSpeed,
    SetStretch,
    Shift,
    Source,
    Sub,
    Xor,
)
from rcb4hv.protocol.servoframes import const_frame_servo_frame, single_servo_frame

__all__ = ["AsyncRcb4Commands"]


class AsyncRcb4Commands:
    """One method per command; the client supplies the round trip."""

    async def transact(self, command: Command, timeout: float | None = None) -> Reply:
        """Send ``command`` and return its reply (the client's)."""
        raise NotImplementedError

    async def _ack(self, frame: bytes, cmd: int, name: str, timeout: float | None = None) -> None:
        """Send a command ``frame`` answered by an ACK (the client's)."""
        raise NotImplementedError

    # ------------------------------------------------------------------ data commands

    async def move(self, dst: Destination, src: Source, size: int | None = None) -> bytes | None:
        """00h MOVE: ``dst <- src``. Returns the bytes read when ``dst`` is ``Com()``."""
        reply = await self.transact(Move(dst, src, size))
        return reply.data if isinstance(reply, DataReply) else None

    async def _data(self, command: Command) -> bytes:
        return data_of(await self.transact(command), command)

    async def _int(self, command: Command) -> int:
        return int.from_bytes(await self._data(command), "little")

    async def and_(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """01h AND; returns the result bytes."""
        return await self._data(And(dst, src, size, no_write))

    async def or_(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """02h OR; returns the result bytes."""
        return await self._data(Or(dst, src, size, no_write))

    async def xor(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> bytes:
        """03h XOR; returns the result bytes."""
        return await self._data(Xor(dst, src, size, no_write))

    async def not_(self, dst: Destination, size: int, no_write: bool = False) -> bytes:
        """04h NOT; returns the result bytes."""
        return await self._data(Not(dst, size, no_write))

    async def shift(self, dst: Destination, size: int, count: int, no_write: bool = False) -> bytes:
        """05h SHIFT (count 1-127 right, 128-255 left by 256 - count); returns the result."""
        return await self._data(Shift(dst, size, no_write, count))

    async def add(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """06h ADD (1 or 2 bytes); returns the result as an unsigned int."""
        return await self._int(Add(dst, src, size, no_write))

    async def sub(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """07h SUB (1 or 2 bytes); returns the result as an unsigned int."""
        return await self._int(Sub(dst, src, size, no_write))

    async def multiply(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """08h MUL (1 or 2 bytes, low bytes kept); returns the result."""
        return await self._int(Mul(dst, src, size, no_write))

    async def division(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """09h DIV (1 or 2 bytes, unsigned); returns the quotient."""
        return await self._int(Div(dst, src, size, no_write))

    async def modulo(
        self, dst: Destination, src: Source, size: int | None = None, no_write: bool = False
    ) -> int:
        """0Ah MOD (1 or 2 bytes, unsigned); returns the remainder."""
        return await self._int(Mod(dst, src, size, no_write))

    # ------------------------------------------------------------------ control flow

    async def jump(self, address: int, condition: Condition = ALWAYS) -> None:
        """0Bh JUMP: set the ROM program counter (if ``condition`` holds)."""
        await self.transact(Jump(address, condition))

    async def call(self, address: int, condition: Condition = ALWAYS) -> None:
        """0Ch CALL: push the PC and jump (how a host starts a motion)."""
        await self.transact(Call(address, condition))

    async def return_(self) -> None:
        """0Dh RETURN: pop the PC."""
        await self.transact(Return())

    async def communicate_device(
        self, ics: int, tx_count: int, tx_address: int, rx_address: int
    ) -> None:
        """0Eh ICS communication. Refused (CommandNotAllowedError) unless the client was created
        with ``allow_communicate_device=True``: the reference says it must not be used."""
        await self.transact(CommunicateDevice(ics, tx_count, tx_address, rx_address))

    # ------------------------------------------------------------------ servo commands

    async def run_single_servo(
        self, ics: int, speed: int, position: int, set_update_flag: bool = True
    ) -> None:
        """0Fh: one servo to ``position`` in ``speed`` output periods (any 7-bit ICS number,
        speed and 16-bit position: the wire layer takes what the board takes)."""
        frame = single_servo_frame(ics, speed, position, set_update_flag)
        await self._ack(frame, 0x0F, "RunSingleServo")

    async def run_const_frame_servo(
        self,
        speed: int,
        positions: Mapping[int, int] | Iterable[tuple[int, int]],
        set_update_flag: bool = True,
    ) -> None:
        """10h: several servos, one speed; ``positions`` maps ICS number to position."""
        frame = const_frame_servo_frame(speed, positions, set_update_flag)
        await self._ack(frame, 0x10, "RunConstFrameServo")

    async def run_series_servo(
        self, moves: Iterable[tuple[int, int, int]], set_update_flag: bool = True
    ) -> None:
        """11h: several servos, each ``(ics, speed, position)``. One report says it resets a
        real RCB-4HV; HeartToHeart4 never sends it."""
        await self.transact(RunSeriesServo(moves, set_update_flag))

    async def set_speed(self, values: Mapping[int, int] | Iterable[tuple[int, int]]) -> None:
        """12h sub 02: servo speed parameter per ICS number (any byte; documented 1-127,
        which :meth:`Robot.set_speed` checks)."""
        await self.transact(SetSpeed(values))

    async def set_stretch(self, values: Mapping[int, int] | Iterable[tuple[int, int]]) -> None:
        """12h sub 01: servo stretch (holding gain) per ICS number (any byte; documented
        1-127, which :meth:`Robot.set_stretch` checks)."""
        await self.transact(SetStretch(values))
