"""A board session: the one owner of a link (polling, a command queue, coalesced moves).

>>> from rcb4hv.session import BoardSession
>>> with BoardSession("rcb4emu://") as s:                          # doctest: +SKIP
...     s.wait_connected()
...     s.submit(lambda robot: robot.play_motion(1)).result()
"""

from __future__ import annotations

from rcb4hv.session.core import BoardSession, Progress, StepJob
from rcb4hv.session.meter import MeteredTransport, wire_seconds
from rcb4hv.session.state import AngleHistory, BoardState, ServoRow, poll_state

__all__ = [
    "AngleHistory",
    "BoardSession",
    "BoardState",
    "MeteredTransport",
    "Progress",
    "ServoRow",
    "StepJob",
    "poll_state",
    "wire_seconds",
]
