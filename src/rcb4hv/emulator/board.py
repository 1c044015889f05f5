"""The RCB-4HV board model: bytes in, bytes out, driven by an injected clock.

:class:`Board` is composed of small units over one RAM and one ROM (see
:mod:`rcb4hv.emulator` for the exact bad-input rules and the model of time):

* :class:`~rcb4hv.emulator.link.Link`: framing, oversize swallowing, NAK timeouts, output;
* :class:`~rcb4hv.emulator.interpreter.Interpreter`: COM commands and the ROM program, with
  the one ALU and condition evaluator of :mod:`~rcb4hv.emulator.alu`;
* :class:`~rcb4hv.emulator.servos.Servos`: servo blocks, interpolation, virtual servos;
* :class:`~rcb4hv.emulator.vectors.Vectors`: the vector-jump table;
* :mod:`~rcb4hv.emulator.timers`: the four 100 ms timers;
* :class:`~rcb4hv.emulator.adc.AdConverter`: the AD inputs and their sampling;
* :class:`~rcb4hv.emulator.romstore.RomStore`: the persistent ROM image.

The speed work (:mod:`~rcb4hv.emulator.accel`) is on by default; ``accelerate=False`` builds
the plain model, which the differential tests hold the fast one to.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Final

from rcb4hv.emulator import accel
from rcb4hv.emulator.adc import AdConverter, check_input
from rcb4hv.emulator.clock import Clock, VirtualClock
from rcb4hv.emulator.config import EmulatorConfig
from rcb4hv.emulator.events import Stop
from rcb4hv.emulator.icslines import IcsLines
from rcb4hv.emulator.interpreter import STACK_DEPTH, Interpreter
from rcb4hv.emulator.link import Link, nak, received
from rcb4hv.emulator.memmap import (
    AD_CHANNELS,
    AD_VALUES,
    ALLOC,
    ALLOC_END,
    BUTTONS,
    CALL_DEPTH,
    NO_BLOCK,
    PA,
    PIO_DIRECTION,
    RAM_SIZE,
    ROM_SIZE,
    SYS_ICS,
    SYS_ROM,
    SYSTEM,
    VECTOR_TABLE,
    read_u16,
    write_u16,
)
from rcb4hv.emulator.romstore import RomStore, initial_rom
from rcb4hv.emulator.servos import Servos, ServoState, check_reading, servo_slots
from rcb4hv.emulator.timers import TIMER_PERIOD_US, reset_timers, tick_timers, timers_idle
from rcb4hv.emulator.vectors import Vectors
from rcb4hv.errors import EmulatedCommandError, EmulatedReset, ProtocolError, RomFileError
from rcb4hv.protocol import FRAME_PERIODS_MS, FrameDecoder, Rom, decode_command, encode_reply
from rcb4hv.protocol.memory import (
    PIO_MASK,
    SERVO,
    pack_alloc,
    read_system,
    read_update_flags,
    write_buttons,
    write_system,
)
from rcb4hv.protocol.servomode import ServoMode

__all__ = ["Board", "ServoMode", "ServoState", "Stop"]

log = logging.getLogger(__name__)

FRAME_US: Final = tuple(ms * 1000 for ms in FRAME_PERIODS_MS)

OutputListener = Callable[[float, dict[int, int]], None]


class Board:
    """An emulated RCB-4HV (HeartToHeart4 2.2 firmware behaviour)."""

    def __init__(
        self,
        config: EmulatorConfig | None = None,
        *,
        clock: Clock | None = None,
        rom_image: bytes | bytearray | None = None,
        rom_path: str | Path | None = None,
        accelerate: bool = True,
    ) -> None:
        self.config = config if config is not None else EmulatorConfig()
        self.clock: Clock = clock if clock is not None else VirtualClock()
        self.accelerate = accelerate
        self._store: RomStore | None = None
        if rom_path is not None:
            self._store = RomStore(rom_path, ROM_SIZE, self.config.rom_flush_delay_s)
        self.rom = initial_rom(self._store, rom_image)
        self.ram = bytearray(RAM_SIZE)
        self._link = Link(self.config, self.clock)
        self._listeners: list[OutputListener] = []
        self._servos = Servos(self.ram, self.config, accelerate)
        self._vectors = Vectors(self.ram, accelerate)
        self._interp = Interpreter(
            self.ram,
            self.rom,
            self.config,
            self._servos,
            self._vectors,
            on_rom_write=self._rom_written,
            on_reset=self.power_on,
            on_ad_reference=self._sample_ad,
            accelerate=accelerate,
        )
        self.ics_lines: IcsLines | None = None  # the SIO lines' ICS servos, for 0Eh
        self.frames_handled = 0
        self._closed = False
        # what the AD pins see: the world outside the board, which a reset leaves alone
        self._adc = AdConverter(self.ram, [self.config.ad0, *self.config.ad_inputs])
        self.power_on()

    # ------------------------------------------------------------------ lifecycle

    def power_on(self) -> None:
        """Reset RAM and the program state to the power-on values (spec 10.1)."""
        cfg = self.config
        r = self.ram
        r[:] = bytes(RAM_SIZE)
        write_system(r, cfg.power_on_system_register)
        self._sample_ad()
        write_u16(r, PIO_DIRECTION, PIO_MASK)  # every PIO pin an output
        reset_timers(r)
        r[ALLOC:ALLOC_END] = pack_alloc(())
        write_u16(r, VECTOR_TABLE, NO_BLOCK)
        t = self._us(self.clock.now())
        self._now = t
        self._interp.reset(t)
        self._next_period = t + self._period_us()
        self._next_timer = t + TIMER_PERIOD_US
        slots = servo_slots(self.config, self.rom)  # the image's robot
        self._servos.reset(slots)
        if cfg.ics_comm and (self.ics_lines is None or slots != self.ics_lines.slots):
            self.ics_lines = IcsLines(self._servos, self.config, self.clock)
            self._interp.ics_comm = self.ics_lines.exchange
        self._link.reset()

    def close(self) -> None:
        """Flush a persistent ROM image (:class:`~rcb4hv.errors.RomFileError` when it cannot
        be saved)."""
        self._closed = True
        self.flush_rom()

    def __enter__(self) -> Board:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def flush_rom(self) -> None:
        """Write the persistent ROM image now (no-op without ``rom_path``)."""
        if self._store is not None and self._store.dirty:
            self._store.flush(self.rom)

    def take_rom_error(self) -> RomFileError | None:
        """A failure to save the persistent ROM image not reported yet (the port serving the
        board raises it at the next host call), else None."""
        return self._store.take_error() if self._store is not None else None

    def _rom_written(self) -> None:
        if self._store is not None:
            self._store.mark_dirty()
        self._servos.follow(servo_slots(self.config, self.rom))  # an upload for another robot

    # ------------------------------------------------------------------ time

    @staticmethod
    def _us(seconds: float) -> int:
        return int(seconds * 1_000_000)

    def _period_us(self) -> int:
        return FRAME_US[(self.ram[SYSTEM] >> 4) & 3]

    @property
    def now(self) -> float:
        """Board time (seconds) the model has been brought up to."""
        return self._now / 1_000_000

    @property
    def output_period(self) -> float:
        """The current output period in seconds (system register bits 5-4)."""
        return self._period_us() / 1_000_000

    def tick(self) -> None:
        """Bring the model up to ``clock.now()``; may queue a NAK for a timed-out frame."""
        now = self.clock.now()
        self._advance(int(now * 1_000_000))
        link = self._link
        if link.decoder.pending or link.discard_left:
            link.check_timeout(now)
        if self._store is not None:
            self._store.maybe_flush(self.rom)

    def run_for(self, seconds: float) -> None:
        """Virtual clock only: advance the clock by ``seconds`` and tick."""
        if not isinstance(self.clock, VirtualClock):
            raise TypeError("run_for needs a VirtualClock")
        self.clock.advance(seconds)
        self.tick()

    def poll_timeout(self) -> float | None:
        """Real seconds a server may wait before the next tick is needed (None: no need)."""
        clock = self.clock
        now = clock.now()
        waits: list[float] = []
        if self._interp.runnable() or self._servos.active:
            waits.append(max(0.0, clock.real_seconds(self._next_period / 1e6 - now)))
        due = self._link.timeout_due()
        if due is not None:
            waits.append(max(0.0, clock.real_seconds(due - now)))
        if self._store is not None:
            w = self._store.seconds_until_flush()
            if w is not None:
                waits.append(w)
        return min(waits) if waits else None

    def _advance(self, t: int) -> None:
        run = self._interp.run
        r = self.ram
        while True:
            np, nt = self._next_period, self._next_timer
            nxt = np if np < nt else nt
            if nxt > t:
                break
            run(nxt)
            do_timer = nt <= np
            if np <= nt:  # (a skip past nt is fine: the timers are all stopped then)
                if self.accelerate and not self._listeners:
                    horizon = t if timers_idle(r) else min(t, nt)
                    np = accel.skip_periods(
                        self._servos, self._vectors, np, horizon, self._period_us(), 2 * FRAME_US[0]
                    )
                    run(np)
                self._now = np
                self._period()
                self._next_period = np + self._period_us()
                do_timer = np == nt
                if np > nt:  # skipped past stopped timers: keep their 100 ms grid
                    self._next_timer = nt + (np - nt) // TIMER_PERIOD_US * TIMER_PERIOD_US
                    do_timer = False
            if do_timer:
                self._now = nt
                tick_timers(r)
                self._next_timer = nt + TIMER_PERIOD_US
        run(t)
        self._now = t

    def _sample_ad(self) -> None:
        """The board samples its AD inputs (:meth:`AdConverter.sample`, spec 10.4)."""
        self._adc.sample()
        self._touch(AD_VALUES, 2 * AD_CHANNELS)

    def _period(self) -> None:
        self._sample_ad()
        self._servos.period()
        if self.ram[SYSTEM] & SYS_ICS:
            self._servos.report()
        if self._listeners:
            t = self._now / 1e6
            outs = self._servos.outputs()
            for cb in self._listeners:
                cb(t, outs)

    # ------------------------------------------------------------------ input / output

    def feed(self, data: bytes | bytearray | memoryview) -> bytes:
        """Process received bytes; return the reply bytes of every complete frame. ``data`` not
        bytes-like (an int, a str) is refused at once: ArgumentTypeError (a TypeError)."""
        raw = received(data)
        self.tick()
        return self._link.receive(raw, self._handle_frame) if raw else b""

    def reset_input(self) -> None:
        """Drop partial input silently (the link was closed)."""
        self._link.reset()

    def take_output(self) -> bytes:
        """Bytes produced outside :meth:`feed` (a NAK after a frame timeout)."""
        return self._link.take_output()

    @property
    def _decoder(self) -> FrameDecoder:
        return self._link.decoder

    def _handle_frame(self, frame: bytes) -> bytes:
        self.frames_handled += 1
        try:
            cmd = decode_command(frame)
        except ProtocolError as exc:
            log.debug("NAK for undecodable frame %s: %s", frame.hex(" "), exc)
            return nak(frame[1])
        running = self.ram[SYSTEM] & SYS_ROM
        try:
            reply = self._interp.execute(cmd, None)
        except EmulatedCommandError as exc:
            log.debug("NAK for %s: %s", frame.hex(" "), exc)
            return nak(frame[1])
        except EmulatedReset:
            log.info("board reset by %s", frame.hex(" "))
            self.power_on()
            return b""
        except Exception:
            log.exception("internal error while executing %s; answering NAK", frame.hex(" "))
            return nak(frame[1])
        if running and not self.ram[SYSTEM] & SYS_ROM:
            self._interp.suspended(cmd)
        return encode_reply(reply) if reply is not None else b""

    # ------------------------------------------------------------------ state

    @property
    def pc(self) -> int:
        return self._interp.pc

    @property
    def system_register(self) -> int:
        return read_system(self.ram)

    @property
    def call_stack(self) -> list[int]:
        """The return addresses currently on the stack (depth from RAM 0005h)."""
        return self._interp.stack[: min(self.ram[CALL_DEPTH], STACK_DEPTH)]

    @property
    def last_stop(self) -> Stop | None:
        """Why the ROM program last stopped (None since power-on: it has not)."""
        return self._interp.last_stop

    @property
    def instructions_executed(self) -> int:
        return self._interp.instructions_executed

    @property
    def periods(self) -> int:
        """Output periods elapsed (stepped or skipped)."""
        return self._servos.periods

    @property
    def stretch(self) -> dict[int, int]:
        """SetStretch values per ICS, as sent."""
        return self._servos.stretch

    @property
    def speed_parameter(self) -> dict[int, int]:
        """SetSpeed values per ICS, as sent."""
        return self._servos.speed_parameter

    @property
    def virtual_servos(self) -> tuple[int, ...]:
        """The ICS numbers with a virtual servo (:func:`~rcb4hv.emulator.servos.servo_slots`)."""
        return self._servos.ics

    def alloc(self, ics: int) -> int:
        """``alloc[ics]``: RAM address of the device block of ICS ``ics`` (FFFF = none)."""
        return read_u16(self.ram, ALLOC + 2 * ics)

    # ------------------------------------------------------------------ test / host hooks

    def _touch(self, a: int, n: int) -> None:
        """A host hook wrote RAM ``a``..``a+n-1`` directly: keep the servo cache honest."""
        self._servos.wrote(a, n)

    def load_rom(self, address: int, data: bytes) -> None:
        """Write ``data`` into ROM at ``address`` (as a MOVE to ROM would; persisted)."""
        if not 0 <= address <= ROM_SIZE - len(data):
            raise ValueError("ROM write out of range")
        if data:
            self._interp.write(Rom(address), bytes(data))

    def set_buttons(self, buttons: int) -> None:
        """Set the remote button word (RAM 0350h, high byte first)."""
        if not 0 <= int(buttons) <= 0xFFFF:
            raise ValueError("the button word is 16 bits")
        self.tick()
        write_buttons(self.ram, int(buttons))
        self._touch(BUTTONS, 2)

    def set_pa(self, n: int, value: int) -> None:
        """Set analog pad value PA1-PA4 (one byte each at 0352h-0355h)."""
        if not 1 <= n <= 4 or not 0 <= value <= 0xFF:
            raise ValueError("PA1-PA4 take 0..255")
        self.tick()
        self.ram[PA[n - 1]] = value
        self._touch(PA[n - 1], 1)

    def set_ad_input(self, channel: int, counts: int) -> None:
        """Set the input of AD0-AD10 (0..1023 counts of 0-5 V, what the pin sees). The measured
        register (0022h) then reads the input minus the channel's reference (spec 10.4)."""
        channel, counts = check_input(channel, counts)  # ArgumentError: AD0-AD10, 0..1023
        self.tick()
        self._adc.inputs[channel] = counts
        self._sample_ad()

    def sensors_at_rest(self) -> None:
        """The robot stands still: each calibrated channel of the ROM image (reference
        1..1023, :func:`~rcb4hv.rom.calibration.calibrated_ad_inputs`) whose input is unset
        (0) reads its reference, as HeartToHeart4's calibration recorded it."""
        from rcb4hv.rom.calibration import calibrated_ad_inputs

        for ch, counts in calibrated_ad_inputs(self.rom).items():
            if not self._adc.inputs[ch]:
                self.set_ad_input(ch, counts)

    def ad_input(self, channel: int) -> int:
        """The input of AD``channel`` (0..1023 counts), as set by the host or a backend."""
        return self._adc.inputs[channel]

    def ad_reference(self, channel: int) -> int:
        """The reference word of AD``channel`` (RAM 000Ch + 2 x channel)."""
        return self._adc.reference(channel)

    def ad_measured(self, channel: int) -> int:
        """The measured register of AD``channel`` (RAM 0022h + 2 x channel), signed."""
        return self._adc.measured(channel)

    def set_servo_position(self, ics: int, position: int) -> None:
        """Move a virtual servo by hand (as if pushed while free)."""
        physical = self._servos.physical
        ics, position = check_reading(ics, position, physical)  # ArgumentError: none there
        self.tick()
        physical[ics] = position

    @property
    def external_servos(self) -> bool:
        """True while a servo backend (:mod:`rcb4hv.physics`) measures the virtual servos'
        positions: a powered servo then reports what :meth:`measure` last set, not the value
        sent to it."""
        return self._servos.external

    @external_servos.setter
    def external_servos(self, on: bool) -> None:
        self._servos.external = bool(on)

    def measure(self, positions: Mapping[int, int], ad: Mapping[int, int]) -> None:
        """A servo backend's measurements: virtual servo positions (ICS 0..35 -> 0..65535,
        reported at the next output period; an ICS without a virtual servo is ignored) and AD
        inputs (AD0-AD10 -> 0..1023 counts). All are checked before any is set: an ICS number,
        channel or value out of range is an ArgumentError. Unlike :meth:`set_servo_position`
        and :meth:`set_ad_input` this does not tick, so an output listener may call it."""
        readings = [check_reading(ics, p) for ics, p in positions.items()]
        inputs = [check_input(ch, v) for ch, v in ad.items()]
        physical = self._servos.physical
        physical.update((ics, p) for ics, p in readings if ics in physical)
        for ch, v in inputs:
            self._adc.inputs[ch] = v
        if inputs:
            self._sample_ad()

    def add_output_listener(self, callback: OutputListener) -> None:
        """Call ``callback(board_time_s, {ics: sent value})`` after every output period."""
        self._listeners.append(callback)

    def remove_output_listener(self, callback: OutputListener) -> None:
        self._listeners.remove(callback)

    def servo_outputs(self) -> dict[int, int]:
        """The value sent to each allocated servo: output + base + mixing (spec 9)."""
        return self._servos.outputs()

    def servo_state(self, ics: int) -> ServoState | None:
        return self._servos.state(ics)

    def servo_mode(self, ics: int) -> ServoMode | None:
        """Whether servo ``ics`` is ``"free"``, ``"hold"`` or at an ``"angle"``: its block's
        output (the trim is not in it) under the config's ``position_7fff``; None without a
        servo block. The one answer to that question
        (:func:`rcb4hv.protocol.servomode.output_mode`)."""
        return self._servos.mode(ics)

    def sent_angles(self, *, trim: bool = True) -> dict[int, int | None]:
        """:meth:`servo_outputs` with None for each servo that is free or holds (no angle).
        ``trim=False``: each value less its block's trim (output + mixing: the motion's own
        value; 16-bit, as the board adds)."""
        servos = self._servos
        ram = self.ram
        out: dict[int, int | None] = {}
        for k, v in servos.outputs().items():
            if servos.mode(k) != "angle":
                out[k] = None
            elif trim:
                out[k] = v
            else:
                out[k] = (v - SERVO.F_BASE.get(ram, self.alloc(k))) & 0xFFFF
        return out

    def update_flag_wait(self) -> int | None:
        """Output periods until the program's update flags have all cleared (0: none set;
        None: never, a flagged servo is not moving): the wait the board itself skips over."""
        return self._servos.flag_wait(read_update_flags(self.ram))
