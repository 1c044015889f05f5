"""Run the shared client suite against :class:`rcb4hv.aio.AsyncRcb4Client`.

:class:`BlockingBridge` owns an event loop in a thread and offers the blocking client's
methods: each call runs the async client's coroutine on that loop and waits for it. The
blocking :class:`~rcb4hv.client.Robot` built on a bridge therefore sends every frame through
the asyncio client, its transports and its lock; calls from several threads become
concurrent tasks on the one loop.
"""

from __future__ import annotations

import asyncio
import functools
import inspect
import threading
from collections.abc import Coroutine
from typing import Any, TypeVar

from rcb4hv.aio import AsyncRcb4Client

T = TypeVar("T")


class BlockingBridge:
    def __init__(self, url: str, **options: Any) -> None:
        self.loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self.loop.run_forever, daemon=True)
        self._thread.start()
        try:
            self.inner: AsyncRcb4Client = self.run(AsyncRcb4Client.open(url, **options))
        except BaseException:
            self._stop()
            raise

    def run(self, coro: Coroutine[Any, Any, T]) -> T:
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(timeout=60)

    def __getattr__(self, name: str) -> Any:
        if name == "inner":
            raise AttributeError(name)
        attr = getattr(self.inner, name)
        if not inspect.iscoroutinefunction(attr):
            return attr

        @functools.wraps(attr)
        def call(*args: Any, **kwargs: Any) -> Any:
            return self.run(attr(*args, **kwargs))

        return call

    def close(self) -> None:
        if self._thread.is_alive():
            try:
                self.run(self.inner.close())
            finally:
                self._stop()

    def _stop(self) -> None:
        self.loop.call_soon_threadsafe(self.loop.stop)
        self._thread.join(timeout=5)
        self.loop.close()
