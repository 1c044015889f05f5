"""Host side: the typed wire-level client and the robot-level API.

>>> from rcb4hv.client import Robot
>>> with Robot.open("rcb4emu://") as robot:          # doctest: +SKIP
...     robot.discover_servos()
"""

from __future__ import annotations

from rcb4hv.client.core import (
    DEFAULT_TIMEOUT,
    MAX_READ,
    MAX_WRITE,
    ROM_WRITE_CHUNK,
    Progress,
    Rcb4Client,
)
from rcb4hv.client.readplan import FRAME_OVERHEAD_S, LinkCost, plan_cheapest, plan_reads
from rcb4hv.client.recorder import PositionRecorder, Sample
from rcb4hv.client.robot import Robot
from rcb4hv.client.robot_types import (
    HTH4_20,
    BoardInfo,
    Calibration,
    MotionStatus,
    ServoInfo,
    TimerState,
)
from rcb4hv.rom.layout import HTH4_22, MotionLayout

__all__ = [
    "DEFAULT_TIMEOUT",
    "FRAME_OVERHEAD_S",
    "HTH4_20",
    "HTH4_22",
    "MAX_READ",
    "MAX_WRITE",
    "ROM_WRITE_CHUNK",
    "BoardInfo",
    "Calibration",
    "LinkCost",
    "MotionLayout",
    "MotionStatus",
    "PositionRecorder",
    "Progress",
    "Rcb4Client",
    "Robot",
    "Sample",
    "ServoInfo",
    "TimerState",
    "plan_cheapest",
    "plan_reads",
]
