"""Physical figures of the Kondo ICS servos the built-in robots use (shared/robots/FACTS.md).

Unit conversions: 1 kgf·cm = 9.80665 N × 0.01 m = 0.0980665 N·m; a no-load speed given as
"s per 60°" is (π/3) / s rad/s.
"""

from __future__ import annotations

import math

from rcb4hv.robot.model import ServoSpec

__all__ = ["KGF_CM", "KRS_2552RHV", "KRS_3304R2", "speed_from_s_per_60deg"]

KGF_CM = 0.0980665  # N·m per kgf·cm (standard gravity 9.80665 m/s², 1 cm = 0.01 m)


def speed_from_s_per_60deg(seconds: float) -> float:
    """rad/s from a catalogue speed "``seconds`` per 60°"."""
    return (math.pi / 3.0) / seconds


KRS_2552RHV = ServoSpec(
    name="KRS-2552RHV",
    stall_torque=14.0 * KGF_CM,
    no_load_speed=speed_from_s_per_60deg(0.14),
    mass=0.0415,
    source="14.0 kgf·cm, 0.14 s/60° at 11.1 V, 41.5 g (Kondo spec pages; kxreus khrmodels.l "
    "and KHRBan agree; FACTS.md)",
)

KRS_3304R2 = ServoSpec(
    name="KRS-3304R2",
    stall_torque=13.9 * KGF_CM,
    no_load_speed=speed_from_s_per_60deg(0.13),
    mass=0.0337,
    source="13.9 kgf·cm, 0.13 s/60° at 11.1 V, 33.7 g (kxreus eusview/README.md, nominal; "
    "FACTS.md)",
)
