"""Overrides of the physics model's chosen constants, in one place, for sensitivity studies.

Every figure of the servo model (:mod:`rcb4hv.robot.servos`), the contact
(:mod:`rcb4hv.robot.mjcf`) and the sensors (:mod:`rcb4hv.physics.sensors`) is documented
with its source or named as a choice; a :class:`PhysicsOptions` scales the chosen ones by a
factor (1 = as documented), so a study (``bench/sensitivity.py``, ``make sensitivity``) can
vary one at a time without touching the documented values. The default options change
nothing.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

from rcb4hv.physics.sensors import SensorLayout

__all__ = ["PhysicsOptions"]


@dataclass(frozen=True, slots=True)
class PhysicsOptions:
    """Factors on the model's chosen figures (each 1.0 by default)."""

    stiffness: float = 1.0
    """x the stretch -> stiffness gain (``servos.stiffness``: FULL_TORQUE_ERROR_DEG)."""
    speed_cap: float = 1.0
    """x the speed cap (``servos.speed_cap``: the ICS speed as a fraction of no-load speed)."""
    free_damping: float = 1.0
    """x a free servo's damping (``servos.FREE_DAMPING_FRACTION``)."""
    armature: float = 1.0
    """x the gear train's reflected inertia (``servos.armature``: MOTOR_TIME_CONSTANT)."""
    friction: float = 1.0
    """x the feet's sliding friction (``mjcf.FLOOR_FRICTION``)."""
    gyro_scale: float = 1.0
    """x the gyro's counts per °/s (``SensorLayout.gyro_counts_per_dps``)."""
    accel_scale: float = 1.0
    """x the accelerometer's counts per g (``SensorLayout.accel_counts_per_g``)."""

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if not isinstance(v, (int, float)) or not v > 0:
                raise ValueError(f"PhysicsOptions.{f.name} must be a factor > 0, not {v!r}")

    def sensors(self, layout: SensorLayout) -> SensorLayout:
        """``layout`` with the gyro and accelerometer scales applied."""
        if self.gyro_scale == 1.0 and self.accel_scale == 1.0:
            return layout
        return replace(
            layout,
            gyro_counts_per_dps=layout.gyro_counts_per_dps * self.gyro_scale,
            accel_counts_per_g=layout.accel_counts_per_g * self.accel_scale,
        )
