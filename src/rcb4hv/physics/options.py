"""Overrides of the physics model's chosen constants, in one place, for sensitivity studies.

Every figure of the servo model (:mod:`rcb4hv.robot.servos`), the contact
(:mod:`rcb4hv.robot.mjcf`) and the sensors (:mod:`rcb4hv.physics.sensors`) is documented
with its source or named as a choice; a :class:`PhysicsOptions` scales the chosen ones by a
factor (1 = as documented), so a study (``bench/sensitivity.py``, ``make sensitivity``) can
vary one at a time without touching the documented values. The default options change
nothing.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, fields, replace

from rcb4hv.physics.sensors import SensorLayout

__all__ = ["FACTOR_RANGE", "MAY_BE_OFF", "NOT_FACTORS", "PhysicsOptions"]

FACTOR_RANGE = (0.01, 100.0)
"""What a factor on a documented figure may be: a what-if, not another world (a mass x 1e9
made MuJoCo's state NaN, x 1e-6 turned the robot 7565 degrees)."""
MAY_BE_OFF = ("servo_damping",)
"""Factors that may be 0: the servo controller's braking switched off is a what-if worth
asking (tests/physics/test_servo_braking.py)."""

NOT_FACTORS = (
    "floor_tilt_deg",
    "floor_tilt_dir_deg",
    "deadband_deg",
    "carry_left_g",
    "carry_right_g",
)
"""The :class:`PhysicsOptions` fields that are figures of their own (0 = none), not factors."""

MAX_CARRY_G = 2000.0
"""The heaviest load a hand may carry in a what-if (g): beyond any KRS servo's stall torque at
a KXR's arm length, so no plausible study needs more."""


@dataclass(frozen=True, slots=True)
class PhysicsOptions:
    """Factors on the model's chosen figures (each 1.0 by default)."""

    stiffness: float = 1.0
    """x the stretch -> stiffness gain (``servos.stiffness``: FULL_TORQUE_ERROR_DEG)."""
    torque: float = 1.0
    """x every servo's stall torque (its catalogue figure, ``robot.servos``); what the servo
    model derives from it follows: the stiffness at a stretch, the torque limit, the back-EMF
    damping, the armature and the controller's braking. A weaker servo: a lower supply
    voltage, or a KXR built with KRS-3302 servos (6.7 kgf·cm: x0.48 of the KRS-3304R2's
    13.9, the servo kxreus's KXR models assume by default, KXR-KITS.md §6)."""
    speed_cap: float = 1.0
    """x the speed cap (``servos.speed_cap``: the ICS speed as a fraction of no-load speed)."""
    free_damping: float = 1.0
    """x a free servo's damping (``servos.FREE_DAMPING_FRACTION``)."""
    armature: float = 1.0
    """x the gear train's reflected inertia (``servos.armature``: MOTOR_TIME_CONSTANT)."""
    servo_damping: float = 1.0
    """x a powered servo controller's braking (``servos.controller_damping``)."""
    friction: float = 1.0
    """x the feet's sliding friction (``mjcf.FLOOR_FRICTION``)."""
    torsional_friction: float = 1.0
    """x each foot contact's spin friction (``mjcf.TORSIONAL_FRICTION``, MuJoCo's default)."""
    gyro_scale: float = 1.0
    """x the gyro's counts per °/s (``SensorLayout.gyro_counts_per_dps``)."""
    accel_scale: float = 1.0
    """x the accelerometer's counts per g (``SensorLayout.accel_counts_per_g``)."""
    mass: float = 1.0
    """x every link's mass and inertia (the models' masses are estimates)."""
    impratio: float = 1.0
    """x how hard the feet's friction is against their normal force (``mjcf.IMPRATIO``,
    MuJoCo's 1): 100 stops the creep of a loaded foot below its friction limit, at 2-3 times
    the physics time."""
    floor_tilt_deg: float = 0.0
    """The floor's slope (degrees, 0..45), by turning gravity: not a factor."""
    floor_tilt_dir_deg: float = 0.0
    """Which way the floor falls (degrees from +x toward +y, the robot's start frame)."""
    deadband_deg: float = 0.0
    """A servo's dead band (degrees, 0..5; not a factor): it keeps its target until the
    commanded angle moves further than this from it (ICS servos have a dead-band setting)."""
    carry_left_g: float = 0.0
    """An object in the left hand (grams, 0..2000; not a factor): a point mass at the hand's
    tip (:mod:`rcb4hv.physics.load`). No project says what its carrying motions carry."""
    carry_right_g: float = 0.0
    """An object in the right hand (grams, 0..2000; not a factor)."""

    def __post_init__(self) -> None:
        if not 0.0 <= self.floor_tilt_deg <= 45.0:
            raise ValueError(
                f"PhysicsOptions.floor_tilt_deg must be 0..45, not {self.floor_tilt_deg!r}"
            )
        if not 0.0 <= self.deadband_deg <= 5.0:
            raise ValueError(f"PhysicsOptions.deadband_deg must be 0..5, not {self.deadband_deg!r}")
        for name in ("carry_left_g", "carry_right_g"):
            if not 0.0 <= getattr(self, name) <= MAX_CARRY_G:
                raise ValueError(
                    f"PhysicsOptions.{name} must be 0..{MAX_CARRY_G:g} g, "
                    f"not {getattr(self, name)!r}"
                )
        for f in fields(self):
            if f.name in NOT_FACTORS:
                continue
            v = getattr(self, f.name)
            lo = 0.0 if f.name in MAY_BE_OFF else FACTOR_RANGE[0]
            if not isinstance(v, (int, float)) or not lo <= v <= FACTOR_RANGE[1]:
                raise ValueError(
                    f"PhysicsOptions.{f.name} must be a factor of {lo:g}..{FACTOR_RANGE[1]:g}, "
                    f"not {v!r}"
                )

    def changed(self) -> tuple[tuple[str, float], ...]:
        """The fields that differ from the documented figures, as (name, value) in field
        order: empty for the default options. Reports record them (a run on changed figures is
        a what-if, not the model's verdict)."""
        base = PhysicsOptions()
        return tuple(
            (f.name, float(getattr(self, f.name)))
            for f in fields(self)
            if getattr(self, f.name) != getattr(base, f.name)
        )

    @classmethod
    def parse(cls, items: Iterable[str]) -> PhysicsOptions:
        """Options from ``NAME=VALUE`` strings (``friction=0.5``, ``deadband_deg=1``): a
        factor on the documented figure, or a figure of its own for the :data:`NOT_FACTORS`.
        Raises ``ValueError`` naming the fields for an unknown name, and for a value that is
        not a number or is out of range."""
        names = [f.name for f in fields(cls)]
        kw: dict[str, float] = {}
        for item in items:
            name, sep, text = item.partition("=")
            name = name.strip()
            if not sep or name not in names:
                raise ValueError(f"{item!r}: give NAME=VALUE with NAME one of {', '.join(names)}")
            try:
                kw[name] = float(text)
            except ValueError:
                raise ValueError(f"{item!r}: {text.strip()!r} is not a number") from None
        return cls(**kw)

    def gravity(self, g: float) -> tuple[float, float, float]:
        """Gravity (m/s^2, world frame) on the tilted floor: a floor sloping ``floor_tilt_deg``
        downhill toward ``floor_tilt_dir_deg`` is the level floor with gravity turned that way."""
        t, a = math.radians(self.floor_tilt_deg), math.radians(self.floor_tilt_dir_deg)
        return (g * math.sin(t) * math.cos(a), g * math.sin(t) * math.sin(a), -g * math.cos(t))

    def sensors(self, layout: SensorLayout) -> SensorLayout:
        """``layout`` with the gyro and accelerometer scales applied."""
        if self.gyro_scale == 1.0 and self.accel_scale == 1.0:
            return layout
        return replace(
            layout,
            gyro_counts_per_dps=layout.gyro_counts_per_dps * self.gyro_scale,
            accel_counts_per_g=layout.accel_counts_per_g * self.accel_scale,
        )
