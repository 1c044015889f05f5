"""Ways for a host to reach an ICS bus: a serial port in ICS mode, or a board's 0Eh.

An :class:`IcsLink` sends one command and returns the servo's reply without the echo, or
raises :class:`~rcb4hv.errors.IcsNoReply`.

* :class:`SerialIcsLink`: a Kondo USB adapter HS switched to ICS mode (8E1), a pty or TCP
  socket served by ``rcb4hv emulate-ics``, or ``icsemu://`` in process. It reads the echo and
  the reply in one go (the host hears its own bytes first) and checks the echo.
* :class:`BoardIcsLink`: an RCB-4HV in between (``--via-board``): the command goes into the
  board's RAM with MOVE, 0Eh sends it on the SIO line of an ICS number, and the answer is
  read back from RAM with MOVE. 0Eh carries at most 64 bytes, so a whole-EEPROM write (66)
  cannot go this way. The reference calls 0Eh unusable on real boards ("a problem in the
  specification"); the board emulator answers it with ``--ics-comm``.
"""

from __future__ import annotations

import logging
import time
from typing import Final, Protocol

from rcb4hv.errors import IcsError, IcsNoReply, NakError, Rcb4Error
from rcb4hv.ics.codec import BAUD_RATES, Kind, Sc, reply_length, strip_echo
from rcb4hv.protocol import (
    Ack,
    Com,
    Command,
    CommunicateDevice,
    Data,
    DataReply,
    Move,
    Nak,
    Ram,
    decode_reply,
    encode_command,
)
from rcb4hv.protocol import reply_length as frame_reply_length
from rcb4hv.protocol.memory import ADDR
from rcb4hv.protocol.sequences import set_system, suspend_program
from rcb4hv.transport import Transport

__all__ = [
    "DEFAULT_RX_ADDRESS",
    "DEFAULT_TX_ADDRESS",
    "BoardIcsLink",
    "IcsLink",
    "SerialIcsLink",
    "no_reply_message",
    "timeout_for",
]

log = logging.getLogger(__name__)

# A reply comes within a few ms; rcb4 ics.py waits 0.1 s (x3 for ID, x10 for an EEPROM read,
# x50 for an EEPROM write, whose reply alone takes ~0.35 s: FACTS).
REPLY_TIMEOUT_S: Final = 0.1
EEPROM_READ_TIMEOUT_S: Final = 1.0
EEPROM_WRITE_TIMEOUT_S: Final = 2.0
# Scratch RAM for --via-board: HeartToHeart4's vector packages (0357h, 32 x 8 bytes), which
# a project running with vector jumps on reads as its button -> motion table. TX up to 64
# bytes, then RX up to 66 (an EEPROM read). BoardIcsLink pauses the program and saves these
# bytes before its first exchange, and puts both back when it closes.
DEFAULT_TX_ADDRESS: Final = 0x0357
DEFAULT_RX_ADDRESS: Final = 0x0397
TX_MAX: Final = 64
RX_MAX: Final = 66
COPY_CHUNK: Final = 64  # bytes per MOVE when the scratch RAM is saved and put back
BOARD_TIMEOUT_S: Final = 1.0
ECHO_NOT_BOARD: Final = (
    "the port echoes the frame sent: an ICS bus (servos: the adapter in ICS mode, icsemu://, "
    "rcb4hv emulate-ics), not a board, so --via-board does not apply; drop it"
)
"""Why a board link that hears its own frame back is not on a board."""


def timeout_for(command: bytes) -> float:
    """How long to wait for the reply to ``command``."""
    if command[0] & 0xE0 in (Kind.READ, Kind.WRITE) and command[1] == Sc.EEPROM:
        return EEPROM_WRITE_TIMEOUT_S if command[0] & 0xE0 == Kind.WRITE else EEPROM_READ_TIMEOUT_S
    return REPLY_TIMEOUT_S * 3 if command[0] & 0xE0 == Kind.ID else REPLY_TIMEOUT_S


def _who(command: bytes) -> tuple[str, str]:
    """Who does not answer ``command``, and what being absent means for it."""
    if command[0] & 0xE0 == Kind.ID:
        which = "write" if command[1] == 1 else "read"
        return f"no servo answers the ID {which}", "none connected"
    return f"servo {command[0] & 0x1F} does not answer", "absent"


def no_reply_message(
    command: bytes, got: bytes, baud: int | None = None, baud_option: str = ""
) -> str:
    """Why ``command`` got no (whole) reply, for :class:`~rcb4hv.errors.IcsNoReply`: who does
    not answer and the likely causes, then the raw bytes. ``baud``: the host's rate, if
    known; ``baud_option``: how the user picks another (``"--baud"`` on the command line)."""
    kind = command[0] & 0xE0
    who, absent = _who(command)
    others = [str(b) for b in BAUD_RATES if b != baud]
    rate = "at another baud rate" if baud is None else f"at another baud rate than {baud}"
    try_ = f"{baud_option} " if baud_option else ""
    causes = f"{absent}, or {rate}: try {try_}{' or '.join(others)}"
    if kind == Kind.READ and command[1] == Sc.POSITION:
        causes += "; or an ICS 3.5 servo, which has no position read (ICS 3.6 only)"
    elif kind == Kind.WRITE and command[1] == Sc.EEPROM:
        causes += "; or still writing its EEPROM"
    if got:
        who += " in full"
    raw = f"no reply to {command.hex(' ')}, got {got.hex(' ') or 'nothing'}"
    return f"{who} ({causes}) [{raw}]"


class IcsLink(Protocol):
    """One command out, the servo's reply (echo removed) back."""

    def exchange(self, command: bytes) -> bytes: ...

    def follow_baud(self, baud: int) -> None: ...

    def close(self) -> None: ...


class SerialIcsLink:
    """An ICS bus on a serial port (adapter in ICS mode, pty, socket, ``icsemu://``)."""

    def __init__(
        self, transport: Transport, *, timeout_scale: float = 1.0, baud_option: str = ""
    ) -> None:
        self.transport = transport
        self.timeout_scale = timeout_scale
        self.baud_option = baud_option  # how a no-reply error tells the user to pick a rate

    def exchange(self, command: bytes) -> bytes:
        t = self.transport
        want = len(command) + reply_length(command)
        t.reset_input()
        t.write(command)
        got = t.read(want, time.monotonic() + timeout_for(command) * self.timeout_scale)
        rest = strip_echo(command, got)
        if len(got) < len(command):
            raise IcsError(f"no echo of {command.hex(' ')}: is the adapter in ICS mode?")
        if len(rest) < want - len(command):
            baud = getattr(t, "baudrate", None)
            rate = baud if isinstance(baud, int) else None
            raise IcsNoReply(no_reply_message(command, rest, rate, self.baud_option))
        return rest

    def follow_baud(self, baud: int) -> None:
        """Switch the host to ``baud`` (after a servo's baud change)."""
        set_baudrate = getattr(self.transport, "set_baudrate", None)
        if set_baudrate is None:
            raise IcsError(f"{self.transport!r} cannot change its baud rate")
        set_baudrate(baud)

    def close(self) -> None:
        self.transport.close()


class BoardIcsLink:
    """An ICS bus behind an RCB-4HV, through 0Eh (``ics`` picks the SIO line: its low bit
    is the side, SIO1-4 or SIO5-8, as in ICS number = 2 x ID + side).

    0Eh takes its command from RAM and leaves the answer in RAM: the scratch area
    (``tx_address``, ``rx_address``) is HeartToHeart4's vector-jump table, which a project's
    program reads for its button bindings. Before the first exchange the link pauses the
    board's program (ROM_F cleared) and saves the scratch bytes; :meth:`close` writes them
    back and restores the system register, so the program runs on with its bindings intact
    (without this a mere ``ics --via-board scan`` started a walk on a HeartToHeart4 board)."""

    def __init__(
        self,
        transport: Transport,
        ics: int = 0,
        *,
        tx_address: int = DEFAULT_TX_ADDRESS,
        rx_address: int = DEFAULT_RX_ADDRESS,
    ) -> None:
        self.transport = transport
        self.ics = ics
        self.tx_address = tx_address
        self.rx_address = rx_address
        self._saved: tuple[int, int, bytes] | None = None
        """(system register, scratch start, scratch bytes) before the first exchange."""

    def _scratch(self) -> tuple[int, int]:
        """The RAM span (start, end) the exchanges write: TX and RX areas together."""
        lo = min(self.tx_address, self.rx_address)
        return lo, max(self.tx_address + TX_MAX, self.rx_address + RX_MAX)

    def _read_ram(self, address: int, size: int) -> bytes:
        reply = self._board(Move(Com(), Ram(address), size))
        if not isinstance(reply, DataReply):
            raise IcsError(f"the board did not return RAM {address:04X}h")
        return bytes(reply.data)

    def _pause(self) -> None:
        """Pause the program and save the scratch RAM (once, before the first exchange)."""
        if self._saved is not None:
            return
        word = int.from_bytes(self._read_ram(ADDR.SYSTEM, 2), "little")
        for command in suspend_program(word):
            self._board(command)
        lo, hi = self._scratch()
        saved = b"".join(
            self._read_ram(a, min(COPY_CHUNK, hi - a)) for a in range(lo, hi, COPY_CHUNK)
        )
        self._saved = (word, lo, saved)

    def _restore(self) -> None:
        """Put the scratch RAM and the system register back as they were."""
        if self._saved is None:
            return
        word, lo, saved = self._saved
        for i in range(0, len(saved), COPY_CHUNK):
            self._board(Move(Ram(lo + i), Data(saved[i : i + COPY_CHUNK])))
        self._board(set_system(word))
        self._saved = None

    def _board(self, frame_cmd: Command) -> Ack | Nak | DataReply:
        t = self.transport
        frame = encode_command(frame_cmd)
        t.reset_input()
        t.write(frame)
        want = frame_reply_length(frame_cmd)
        got = t.read(want, time.monotonic() + BOARD_TIMEOUT_S)
        if len(got) < 4:
            raise IcsNoReply(f"the board did not answer {frame.hex(' ')}")
        if frame.startswith(got[: len(frame)]) and got[0] != want:
            raise IcsError(f"{t.url}: {ECHO_NOT_BOARD} [sent {frame.hex(' ')}, got it back]")
        reply = decode_reply(got, frame_cmd)
        if not isinstance(reply, (Ack, Nak, DataReply)):
            raise IcsError(f"unexpected board reply {got.hex(' ')}")
        return reply

    def exchange(self, command: bytes) -> bytes:
        if len(command) > TX_MAX:
            raise IcsError(
                f"0Eh sends at most {TX_MAX} bytes; this command has {len(command)} "
                "(write the EEPROM through the USB adapter in ICS mode instead)"
            )
        self._pause()
        if isinstance(self._board(Move(Ram(self.tx_address), Data(command))), Nak):
            raise NakError(f"the board refused the RAM write at {self.tx_address:04X}h")
        comm = CommunicateDevice(self.ics, len(command), self.tx_address, self.rx_address)
        if isinstance(self._board(comm), Nak):
            who, absent = _who(command)
            raise IcsNoReply(
                f"{who} on the SIO line of ICS {self.ics} ({absent}, not at the line's baud "
                "rate, or a board that does not serve 0Eh: the emulator needs --ics-comm) "
                f"[0Eh: NAK, no answer to {command.hex(' ')}]"
            )
        n = reply_length(command)
        reply = self._board(Move(Com(), Ram(self.rx_address), n))
        if not isinstance(reply, DataReply):
            raise IcsError("the board did not return the answer's RAM")
        return bytes(reply.data)

    def follow_baud(self, baud: int) -> None:
        """The board's SIO rate is the board's business: nothing here can follow a servo."""
        raise IcsError(f"the servo now talks at {baud} baud; a board's SIO line cannot follow")

    def close(self) -> None:
        """Put back what the exchanges changed on the board (the scratch RAM, the paused
        program), then close the link; a board that no longer answers is left as it is."""
        try:
            if self.transport.is_open:
                self._restore()
        except (IcsError, Rcb4Error) as exc:
            log.warning("could not restore the board's RAM after --via-board: %s", exc)
        finally:
            self.transport.close()
