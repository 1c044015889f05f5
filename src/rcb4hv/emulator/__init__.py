"""Emulator of the Kondo RCB-4HV firmware (HeartToHeart4 2.2 behaviour).

The core is :class:`Board`: ``feed(bytes) -> bytes`` and ``tick()``, driven by an injected
:class:`Clock` (:class:`VirtualClock` in tests, :class:`RealClock` when serving). Serving is a
thin adapter: :class:`PtyServer`, :class:`TcpServer` (``rcb4hv emulate``).

The board is composed of units over one RAM (see :mod:`rcb4hv.emulator.board`): link
(framing, NAK timeouts), interpreter (one ALU, :mod:`~rcb4hv.emulator.alu`), servos, vectors,
timers, ROM store; the speed work is a separate layer (:mod:`~rcb4hv.emulator.accel`) that
``Board(accelerate=False)`` leaves out. :attr:`Board.last_stop` says why the ROM program last
stopped (:class:`Stop`: ``what``, ``where``, ``why``).

Bad input: the exact rules
--------------------------
Frames are cut by the protocol core's :class:`~rcb4hv.protocol.FrameDecoder` (``resync="frame"``)
and decoded by :func:`~rcb4hv.protocol.decode_command`.

* SIZE byte 0, 1 or 2: that byte is dropped silently (it cannot start a frame).
* SIZE byte above 128 (oversize, spec 13 #13): SIZE bytes in total are swallowed, nothing is
  executed, then ``NAK`` echoing the byte after SIZE (``oversize_frame="silent"``: no reply).
* Whole frame with a wrong checksum: the whole frame is dropped, ``NAK`` echoing its CMD byte.
* Valid checksum but not a valid command (unknown CMD, wrong length, reserved bits, forbidden
  type combination such as AND to COM or MOVE with NW, RAM address or span out of range,
  malformed version/ack request): ``NAK`` echoing its CMD byte.
* Valid command that cannot execute (ICS slot not allocated, ICS/ROM span past the end, call
  stack overflow, RETURN on an empty stack, division by zero, ICS communication 0Eh): ``NAK``.
  The same errors met by the ROM program clear ROM_F (a checksum error also sets ROMERR).
* Partial frame: after ``frame_timeout_s`` of silence (board time, scaled by the clock speed)
  the bytes are dropped and a ``NAK`` echoing the CMD byte is queued (collect it with
  :meth:`Board.take_output`; the servers send it) if a CMD byte arrived; a lone SIZE byte is
  dropped silently (spec 13 #12).
* Any unexpected exception while handling one frame is logged and answered with ``NAK``.
* The decoder never holds more than 127 bytes; queued output is capped
  (``max_pending_output``), so buffers stay bounded whatever arrives.

Time
----
Output periods (10/15/20/25 ms from the system register), the 100 ms timers and the ROM
program (``instructions_per_ms`` instructions per millisecond of board time, default 5: a
real board fetches each instruction from an I2C EEPROM) are stepped in board time, in order.
While nothing can observe them (program stopped or waiting on update flags, no listener, no
time-dependent vector package, no mixing) whole runs of periods are applied in closed form;
RAM always looks exactly as if every period had been stepped when a command or instruction
reads it.

Modelling choices where the spec is silent
------------------------------------------
* A servo command with position 8000h (free) or 7FFFh (hold) takes effect at once (no
  interpolation) and leaves that servo's update flag 0. A move starting from free/hold
  starts from the servo's actual position.
* An update flag clears only when its servo's move finishes (spec 9); a flag set for a servo
  that is not moving keeps the ROM program waiting.
* Vector-jump evaluation does not touch the Z/C flags of the system register (it would break
  a SUB/JUMP pair in a running motion); a vector CALL pushes the current PC.
* ADD..MOD with destination COM compute ``0 OP source`` and only answer the result.
* SetSpeed/SetStretch values are kept per ICS (:attr:`Board.stretch`,
  :attr:`Board.speed_parameter`); they do not change the model's motion. Every byte value is
  accepted and stored as sent, the documented 1-127 included and 0 or 128-255 too (real
  HeartToHeart4 motions send 0): the model has no servo gain, so no value can conflict with it.
* Positions are any 16-bit value: the model interpolates and its virtual servos follow values
  outside 3500-11500 as sent (no servo-side travel limit is modelled). Speed 0 follows
  ``speed_zero`` (spec 13 #7).
* JUMP/CALL and vector-jump targets are 24 bits; one past 3FFFFh wraps modulo the 256 KB ROM.
* RunSingleServo (0Fh) carries a 7-bit ICS number; ICS 36-127 have no allocation entry and are
  skipped like an unallocated slot (ACK; with the update-flag bit clear every flag becomes 0).
* Virtual servos (``virtual_servos``) report position - base into +4 of ``alloc[n]`` every
  period while ICS_F is set, also when free; other allocated blocks keep +4 unchanged.
* MSG_F never sends anything (spec 13 #10: the format is undocumented) - a documented gap.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rcb4hv.emulator.board import Board, ServoMode, ServoState
from rcb4hv.emulator.boot import BootClock, boot_to_main_loop
from rcb4hv.emulator.clock import Clock, RealClock, VirtualClock
from rcb4hv.emulator.config import DEFAULT_VERSION, EmulatorConfig
from rcb4hv.emulator.events import Stop, StopKind
from rcb4hv.emulator.protocol_rcb4emu import emulator_url

if TYPE_CHECKING:  # the servers need pty/termios: imported on first use
    from rcb4hv.emulator.server import PtyServer, TcpServer

__all__ = [
    "DEFAULT_VERSION",
    "Board",
    "BootClock",
    "Clock",
    "EmulatorConfig",
    "PtyServer",
    "RealClock",
    "ServoMode",
    "ServoState",
    "Stop",
    "StopKind",
    "TcpServer",
    "VirtualClock",
    "boot_to_main_loop",
    "emulator_url",
]


def __getattr__(name: str) -> object:
    if name in ("PtyServer", "TcpServer"):
        from rcb4hv.emulator import server

        return getattr(server, name)
    raise AttributeError(name)
