"""rcb4hv for asyncio: :class:`AsyncRcb4Client` (every command of the reference, as
coroutines) and :class:`AsyncRobot` (the common robot-level calls).

Both run on the sans-I/O core the blocking client uses (:mod:`rcb4hv.client.exchange`), with
the same typed errors and deadlines; concurrent tasks are serialised by an asyncio lock.

```python
import asyncio
from rcb4hv.aio import AsyncRobot

async def main() -> None:
    async with await AsyncRobot.open("rcb4emu://") as robot:
        positions = await robot.positions()  # {ics: position}

asyncio.run(main())
```
"""

from __future__ import annotations

from rcb4hv.aio.client import AsyncRcb4Client
from rcb4hv.aio.robot import AsyncRobot
from rcb4hv.aio.transport import (
    AsyncTransport,
    PolledTransport,
    StreamTransport,
    open_async_transport,
)

__all__ = [
    "AsyncRcb4Client",
    "AsyncRobot",
    "AsyncTransport",
    "PolledTransport",
    "StreamTransport",
    "open_async_transport",
]
