"""The robot-level API's remote control, sensors, PIO, timers, counters and user variables.

:class:`AsyncRobotIO` is a mixin of :class:`~rcb4hv.aio.AsyncRobot`: every method reads or
writes one region of RAM through the memory map's views (:mod:`rcb4hv.protocol.memory`).
One source, two faces: ``tools/unasync.py`` writes ``src/rcb4hv/client/robot_io.py``
(blocking) from ``src/rcb4hv/aio/robot_io.py`` (asyncio).
"""

from __future__ import annotations

from asyncio import sleep

from rcb4hv.aio.client import AsyncRcb4Client
from rcb4hv.client.args import integer, seconds
from rcb4hv.errors import ArgumentError
from rcb4hv.protocol.memory import (
    AD_READINGS,
    ADDR,
    PA_VALUES,
    PIO_MASK,
    PIO_WORDS,
    U16_BE,
    USER_VARIABLES,
    AdReadings,
    Button,
    TimerState,
    ad_readings,
    ad_volts,
    read_buttons,
    read_s16,
    read_u16,
    u16_bytes,
)

__all__ = ["AsyncRobotIO"]


class AsyncRobotIO:
    """Remote control, sensors and I/O of the board behind ``self.client``."""

    client: AsyncRcb4Client

    # ------------------------------------------------------------------ remote control

    async def buttons(self) -> Button:
        """The remote-control button word (0350h, high byte first)."""
        return read_buttons(await self.client.read_ram(ADDR.BUTTONS, 2), 0)

    async def set_buttons(self, buttons: Button | int) -> None:
        """Write the button word: a virtual remote control."""
        value = integer("buttons", buttons)
        if not 0 <= value <= 0xFFFF:
            raise ArgumentError(f"the button word is 16 bits (0..65535), not {value}")
        await self.client.write_ram(ADDR.BUTTONS, U16_BE.pack(value))

    async def press_button(self, buttons: Button | int, duration: float = 0.2) -> None:
        """Hold ``buttons`` on the virtual remote for ``duration`` seconds, then release."""
        duration = seconds("duration", duration)
        await self.set_buttons(buttons)
        try:
            await sleep(duration)
        finally:
            await self.set_buttons(Button.NONE)

    async def pa_values(self) -> tuple[int, int, int, int]:
        """The four analogue remote values PA1-PA4 (0352h-0355h)."""
        a, b, c, d = PA_VALUES.unpack(await self.client.read_ram(ADDR.PA[0], PA_VALUES.size))
        return a, b, c, d

    async def set_pa(self, index: int, value: int) -> None:
        """Set PA``index`` (1-4) to ``value`` (0-255)."""
        if not 1 <= integer("index", index) <= 4:
            raise ArgumentError(f"PA inputs are 1-4, not {index}")
        if not 0 <= integer("value", value) <= 0xFF:
            raise ArgumentError(f"PA values are 0-255, not {value}")
        await self.client.write_ram(ADDR.PA[index - 1], bytes((value,)))

    # ------------------------------------------------------------------ sensors and PIO

    async def ad_values(self) -> list[int]:
        """AD0-AD10's measured registers in one frame: the input minus the channel's reference
        (spec 10.4), signed (a gyro at rest reads about 0)."""
        return list((await self.ad_readings()).measured)

    async def ad_readings(self) -> AdReadings:
        """AD0-AD10's references, measured values and inputs in one frame."""
        return ad_readings(await self.client.read_ram(ADDR.AD_REFERENCE, AD_READINGS.size), 0)

    async def battery_voltage(self) -> float:
        """Supply voltage from AD0: AD0 * 25 / 1024 volts."""
        return ad_volts(read_u16(await self.client.read_ram(ADDR.ad(0), 2), 0))

    async def pio(self) -> tuple[int, int]:
        """(direction mask, data) of the 10 PIO pins (1 = output)."""
        direction, data = PIO_WORDS.unpack(await self.client.read_ram(ADDR.PIO_DIRECTION, 4))
        return direction & PIO_MASK, data & PIO_MASK

    async def set_pio_direction(self, mask: int) -> None:
        if not 0 <= integer("mask", mask) <= PIO_MASK:
            raise ArgumentError(f"PIO direction is 10 bits (0..{PIO_MASK}), not {mask}")
        await self.client.write_ram(ADDR.PIO_DIRECTION, u16_bytes(mask))

    async def write_pio(self, value: int) -> None:
        if not 0 <= integer("value", value) <= PIO_MASK:
            raise ArgumentError(f"PIO data is 10 bits (0..{PIO_MASK}), not {value}")
        await self.client.write_ram(ADDR.PIO_DATA, u16_bytes(value))

    # ------------------------------------------------------------------ timers, counters, variables

    async def timer(self, n: int) -> TimerState:
        """Timer ``n`` (0-3): count (100 ms steps) and whether it runs."""
        return TimerState.unpack(await self.client.read_ram(ADDR.timer(n), 2), 0)

    async def set_timer(self, n: int, count: int, *, run: bool = True) -> None:
        """Load timer ``n`` with ``count`` (0-32767) and start it (or leave it stopped)."""
        state = TimerState(integer("count", count), run)
        await self.client.write_ram(ADDR.timer(integer("n", n)), state.to_bytes())

    async def stop_timer(self, n: int) -> None:
        state = await self.timer(n)
        await self.set_timer(n, state.count, run=False)

    async def counter(self, n: int) -> int:
        """Counter ``n`` (0-10), one byte each from 0457h."""
        return (await self.client.read_ram(ADDR.counter(n), 1))[0]

    async def set_counter(self, n: int, value: int) -> None:
        if not 0 <= integer("value", value) <= 0xFF:
            raise ArgumentError(f"counters are 0..255, not {value}")
        await self.client.write_ram(ADDR.counter(integer("n", n)), bytes((value,)))

    async def variable(self, n: int) -> int:
        """User variable ``n`` (0-19), a signed 16-bit value."""
        return read_s16(await self.client.read_ram(ADDR.user_variable(n), 2), 0)

    async def variables(self) -> list[int]:
        """All 20 user variables in one frame."""
        raw = await self.client.read_ram(ADDR.USER_VARIABLES, USER_VARIABLES.size)
        return list(USER_VARIABLES.unpack(raw))

    async def set_variable(self, n: int, value: int) -> None:
        value = integer("value", value)
        if not -0x8000 <= value <= 0xFFFF:
            raise ArgumentError(f"user variables are 16 bits (-32768..65535), not {value}")
        await self.client.write_ram(ADDR.user_variable(integer("n", n)), u16_bytes(value))
