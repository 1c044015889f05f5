"""A serial link the client tests script: it records every write and answers each with the
next canned reply (the golden-bytes tests), or, subclassed, as a board would."""

from __future__ import annotations

import time
from collections import deque

from rcb4hv.transport import Transport

__all__ = ["ScriptedTransport"]


class ScriptedTransport(Transport):
    """Records every write and answers each with the next canned reply."""

    url = "scripted://"

    def __init__(self, *replies: bytes) -> None:
        self.writes: list[bytes] = []
        self.replies = deque(replies)
        self._rx = bytearray()
        self.closed = False

    def write(self, data: bytes) -> None:
        self.writes.append(bytes(data))
        if self.replies:
            self._rx += self.replies.popleft()

    def read(self, size: int, deadline: float) -> bytes:
        if len(self._rx) < size:
            time.sleep(max(0.0, min(deadline - time.monotonic(), 0.01)))
        out = bytes(self._rx[:size])
        del self._rx[:size]
        return out

    def reset_input(self) -> None:
        self._rx.clear()

    def close(self) -> None:
        self.closed = True

    @property
    def is_open(self) -> bool:
        return not self.closed
