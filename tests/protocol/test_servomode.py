"""The one free / hold / angle rule on a servo block's output word."""

from __future__ import annotations

import pytest

from rcb4hv.protocol.servomode import output_mode


@pytest.mark.parametrize(
    ("output", "hold_is_free", "mode"),
    [
        (0x8000, False, "free"),
        (0x7FFF, False, "hold"),
        (0x7FFF, True, "free"),
        (7500, False, "angle"),
        (0x8000 - 1980, False, "angle"),  # free + a trim is a *sent* value, not an output
        (0x7FFE, True, "angle"),
    ],
)
def test_output_mode(output: int, hold_is_free: bool, mode: str) -> None:
    assert output_mode(output, hold_is_free) == mode
