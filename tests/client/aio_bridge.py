"""Run the shared client suite on the asyncio face itself: :class:`rcb4hv.aio.AsyncRcb4Client`
and :class:`rcb4hv.aio.AsyncRobot`.

:class:`EventLoopThread` owns an event loop in a thread; :class:`Blocking` wraps any object
living on that loop and offers its methods as blocking calls: each call of a coroutine method
runs it on the loop and waits for it; other attributes (values, plain methods) are passed
through, and setting one sets it on the wrapped object. The suite's ``aio-*`` rigs use a
``Blocking(AsyncRobot)``, so every robot call runs the asyncio robot's own code (its reads,
plans, waits and sleeps), over the asyncio client, its transports and its lock; calls from
several threads become concurrent tasks on the one loop.
"""

from __future__ import annotations

import asyncio
import functools
import inspect
import threading
from collections.abc import Coroutine
from typing import Any, TypeVar

from rcb4hv.aio import AsyncRcb4Client, AsyncRobot

T = TypeVar("T")


class EventLoopThread:
    def __init__(self) -> None:
        self.loop = asyncio.new_event_loop()
        self._thread = threading.Thread(target=self.loop.run_forever, daemon=True)
        self._thread.start()

    def run(self, coro: Coroutine[Any, Any, T]) -> T:
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(timeout=60)

    def stop(self) -> None:
        if self._thread.is_alive():
            self.loop.call_soon_threadsafe(self.loop.stop)
            self._thread.join(timeout=5)
            self.loop.close()


class Blocking:
    """Blocking calls into ``inner``, an object whose coroutines run on ``runner``'s loop."""

    def __init__(self, inner: Any, runner: EventLoopThread) -> None:
        object.__setattr__(self, "inner", inner)
        object.__setattr__(self, "runner", runner)

    def __getattr__(self, name: str) -> Any:
        attr = getattr(self.inner, name)
        if isinstance(attr, AsyncRcb4Client):  # robot.client: blocking calls too
            return Blocking(attr, self.runner)
        if not inspect.iscoroutinefunction(attr):
            return attr

        @functools.wraps(attr)
        def call(*args: Any, **kwargs: Any) -> Any:
            return self.runner.run(attr(*args, **kwargs))

        return call

    def __setattr__(self, name: str, value: Any) -> None:
        setattr(self.inner, name, value)


class BlockingBridge(Blocking):
    """An :class:`AsyncRcb4Client` opened on its own loop thread, as blocking calls."""

    def __init__(self, url: str, **options: Any) -> None:
        runner = EventLoopThread()
        try:
            client = runner.run(AsyncRcb4Client.open(url, **options))
        except BaseException:
            runner.stop()
            raise
        super().__init__(client, runner)

    def robot(self, **options: Any) -> Blocking:
        """An :class:`AsyncRobot` on this client, as blocking calls."""
        return Blocking(AsyncRobot(self.inner, **options), self.runner)

    def close(self) -> None:
        try:
            self.runner.run(self.inner.close())
        finally:
            self.runner.stop()
