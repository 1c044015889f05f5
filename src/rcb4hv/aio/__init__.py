"""rcb4hv for asyncio: :class:`AsyncRcb4Client` (every command of the reference, as
coroutines) and :class:`AsyncRobot` (the robot-level API).

These modules are the one source of the client: the blocking :class:`rcb4hv.client.Rcb4Client`
and :class:`rcb4hv.client.Robot` are generated from them (``tools/unasync.py``), so both faces
have the same methods, arguments, results, typed errors, deadlines and frames on the wire;
concurrent tasks are serialised by an asyncio lock.

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
