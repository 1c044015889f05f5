"""Free, hold or angle: what a servo does with its block's output word (spec 9).

The one rule, for the emulator (:meth:`rcb4hv.emulator.Board.servo_mode`), the physics backend
and a host reading a real board's servo blocks (:attr:`rcb4hv.client.ServoInfo.state`).
"""

from __future__ import annotations

from typing import Literal

from rcb4hv.protocol.operands import POSITION_FREE, POSITION_HOLD

__all__ = ["ServoMode", "output_mode"]

ServoMode = Literal["free", "hold", "angle"]
"""What a servo does with its block's output: goes limp, keeps the angle it has, or drives to
the angle sent (output + trim + mixing, spec 9)."""


def output_mode(output: int, hold_is_free: bool = False) -> ServoMode:
    """The mode of a block's output word (motion space: the trim is not in it): 8000h frees the
    servo, 7FFFh holds it (frees it where an emulated board's config says
    ``position_7fff="free"``: ``hold_is_free``), anything else is an angle. The value *sent*
    is output + trim, so it must not be compared with 8000h / 7FFFh."""
    if output == POSITION_FREE or (output == POSITION_HOLD and hold_is_free):
        return "free"
    return "hold" if output == POSITION_HOLD else "angle"
