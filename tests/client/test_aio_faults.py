"""The fault matrix of test_client_faults, against the asyncio client: the same injected faults
(rcb4hv.transport.FaultyTransport over a real TCP link and a pty to the emulator) end every call
within its timeout with the same typed error, and the next calls work."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Iterator

import pytest

from rcb4hv.aio import AsyncRcb4Client, AsyncTransport
from rcb4hv.transport import Fault, FaultConfig, FaultyTransport, Transport
from tests.client.conftest import Rig, make_rig
from tests.client.test_client_faults import (
    CALM_TIMEOUT,
    DELAY,
    EXPECTED,
    SLACK,
    fault_timeout,
)


class Bridged(AsyncTransport):
    """A blocking transport as an AsyncTransport: reads block at most 0.5 ms, the loop polls."""

    def __init__(self, inner: Transport) -> None:
        self.inner = inner
        self.url = inner.url

    @property
    def is_open(self) -> bool:
        return self.inner.is_open

    def write(self, data: bytes) -> None:
        self.inner.write(data)

    async def read(self, size: int, deadline: float) -> bytes:
        buf = b""
        while True:
            buf += self.inner.read(size - len(buf), time.monotonic() + 0.0005)
            if len(buf) >= size or time.monotonic() >= deadline:
                return buf
            await asyncio.sleep(0.0005)

    def reset_input(self) -> None:
        self.inner.reset_input()

    async def close(self) -> None:
        """The rig closes the blocking transport."""


@pytest.fixture(params=["tcp", "pty"])
def rig(request: pytest.FixtureRequest) -> Iterator[Rig]:
    yield from make_rig(request.param)


@pytest.mark.parametrize("fault", list(Fault), ids=[f.value for f in Fault])
def test_scripted_fault(rig: Rig, fault: Fault) -> None:
    ft = FaultyTransport(rig.client.transport, FaultConfig(delay_s=DELAY))
    client = AsyncRcb4Client(Bridged(ft), timeout=CALM_TIMEOUT)
    expected = EXPECTED[fault]

    async def main() -> None:
        await client.write_ram(0x0462, b"\x11\x22\x33\x44")
        ft.inject(fault)
        client.timeout = fault_timeout(fault)
        t0 = time.monotonic()
        if expected is None:
            assert await client.read_ram(0x0462, 4) == b"\x11\x22\x33\x44"
        else:
            with pytest.raises(expected):
                await client.read_ram(0x0462, 4)
        assert time.monotonic() - t0 < client.timeout + SLACK
        client.timeout = CALM_TIMEOUT
        assert ft.history[-1][1] is fault
        await client.acknowledge_check()
        assert await client.read_ram(0x0462, 4) == b"\x11\x22\x33\x44"
        await asyncio.sleep(DELAY)  # a delayed reply lands now and must be discarded
        await client.acknowledge_check()
        assert (await client.get_version_info()).text.startswith("CB-4")

    asyncio.run(main())
