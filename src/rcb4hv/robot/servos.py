"""The servos the robots are built of: the Kondo ICS servos' figures (each once, with its
source: shared/robots/FACTS.md) and the model of a servo the physics and the MJCF export use.

Figures: :data:`KRS_2552RHV` (the KHR-3HV's), :data:`KRS_3304R2` (the KXR's, and
:data:`DEFAULT_SERVO`: the servo assumed for a joint-map entry without a servo type). Unit
conversions: 1 kgf·cm = 9.80665 N × 0.01 m = 0.0980665 N·m; a no-load speed given as "s per
60°" is (π/3) / s rad/s.

Travel: a servo turns over the documented positions ``POSITION_MIN..POSITION_MAX``
(3500..11500, :mod:`rcb4hv.protocol`) around ``CENTER``, :data:`TRAVEL_DEG` (135°) each way.

The model (:func:`stiffness`, :func:`controller_damping`, :func:`speed_cap`, :func:`armature`,
:func:`back_emf_damping`): a position servo ``torque = kp (target - angle) - kd speed``
clamped to the stall torque, kp growing with the ICS stretch, kd the controller's braking; the
top speed a fraction of the no-load speed set by the ICS speed; a DC motor's back-EMF damping
and the gear train's reflected inertia. ICS stretch and speed are
SetStretch/SetSpeed (12h) values, 1..``STRETCH_MAX`` (:mod:`rcb4hv.protocol.ranges`).
"""

from __future__ import annotations

import math

from rcb4hv.protocol import POSITION_MAX
from rcb4hv.protocol.memory import CENTER, COUNTS_PER_DEGREE
from rcb4hv.protocol.ranges import STRETCH_MAX, STRETCH_MIN
from rcb4hv.robot.model import ServoSpec

__all__ = [
    "DEFAULT_SERVO",
    "DEFAULT_SPEED",
    "DEFAULT_STRETCH",
    "FREE_DAMPING_FRACTION",
    "FULL_TORQUE_ERROR_DEG",
    "KGF_CM",
    "KRS_2552RHV",
    "KRS_3304R2",
    "MOTOR_TIME_CONSTANT",
    "TRAVEL_DEG",
    "WHEEL_FULL_SCALE_DEG",
    "armature",
    "back_emf_damping",
    "controller_damping",
    "speed_cap",
    "speed_from_s_per_60deg",
    "stiffness",
    "wheel_duty",
]

# ---------------------------------------------------------------------------- figures

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

DEFAULT_SERVO = KRS_3304R2
"""The servo assumed for a joint-map entry without a servo type."""

TRAVEL_DEG = (POSITION_MAX - CENTER) / COUNTS_PER_DEGREE
"""How far a servo turns each way from its centre (degrees): 4000 counts at 8000/270 counts a
degree, 135° (FACTS.md "Position scale")."""

# ------------------------------------------------------------------------------ model

DEFAULT_STRETCH = 60
"""Stretch assumed for a servo the board never sent a SetStretch (12h) to. Chosen: the
middle of the 1-127 range (no primary source gives the factory value)."""

DEFAULT_SPEED = STRETCH_MAX
"""Speed parameter assumed when none was sent: full speed (the servo's own maximum)."""

FULL_TORQUE_ERROR_DEG = 2.0
"""At stretch 127 a servo reaches its stall torque at this angle error (degrees); stiffness
scales with stretch (kp = stretch/127 x stall / error). Chosen - no public source converts
stretch to N·m/rad (FACTS.md). It puts kp of a KRS-3304 at stretch 60 at 18.4 N·m/rad, inside
the kp 10-30 kxreus's MuJoCo models of the same servos use."""

MOTOR_TIME_CONSTANT = 0.008
"""Mechanical time constant of a servo's motor (s): the time its speed takes to reach 63% of
no-load speed from rest. Gearing leaves it unchanged (the reflected inertia grows with the
ratio squared, stall torque and 1/speed with the ratio), so it is the servo's as well. Small
DC micromotors of a servo's size have 7-8.5 ms (Faulhaber 1331 SR: 7 ms, 1524 SR: 8.2-8.5 ms,
their datasheets); 8 ms taken. It keeps the "0.13 s/60°" rating honest: a servo with this
time constant turns 60° in 0.14 s from rest."""

FREE_DAMPING_FRACTION = 0.1
"""A free servo's motor is disconnected: only gear and bearing friction remain, taken as this
fraction of the powered back-EMF damping (chosen)."""


def _clamp_parameter(value: int | None, default: int) -> int:
    """An ICS stretch/speed byte as the servo takes it: 1-127; anything else (HeartToHeart4
    motions send 0) leaves the servo at ``default``."""
    if value is None or not STRETCH_MIN <= value <= STRETCH_MAX:
        return default
    return value


def stiffness(spec: ServoSpec, stretch: int | None) -> float:
    """Position gain kp (N·m/rad) of a servo at ``stretch`` (see FULL_TORQUE_ERROR_DEG)."""
    s = _clamp_parameter(stretch, DEFAULT_STRETCH)
    return s / STRETCH_MAX * spec.stall_torque / math.radians(FULL_TORQUE_ERROR_DEG)


def speed_cap(spec: ServoSpec, speed: int | None) -> float:
    """Largest rotation speed (rad/s) at ICS ``speed``: that fraction of the no-load speed."""
    return _clamp_parameter(speed, DEFAULT_SPEED) / STRETCH_MAX * spec.no_load_speed


def armature(spec: ServoSpec) -> float:
    """Reflected inertia (kg·m²) of the servo's motor and gear train at its output shaft:
    J = time constant x stall torque / no-load speed (see MOTOR_TIME_CONSTANT)."""
    return MOTOR_TIME_CONSTANT * spec.stall_torque / spec.no_load_speed


def back_emf_damping(spec: ServoSpec) -> float:
    """Viscous damping (N·m·s/rad) of a powered servo: a DC motor's torque falls linearly
    from the stall torque at rest to 0 at the no-load speed, so b = stall / no-load speed."""
    return spec.stall_torque / spec.no_load_speed


def controller_damping(spec: ServoSpec) -> float:
    """The servo controller's braking gain kd (N·m·s/rad), inside the stall-torque clamp.

    An ICS servo brakes its motor as it nears its target: its EEPROM carries a *damping*
    setting beside stretch and speed (FACTS.md, "ICS 3.5 on the wire"), a velocity term in its
    position loop. Kondo gives no conversion to N·m·s/rad, so the figure is chosen: the least
    braking with which the bare servo settles without overshoot at its stiffest setting
    (stretch 127), i.e. its own motor and gear train (:func:`armature`) critically damped
    together with the back-EMF: ``kd = 2 sqrt(kp(127) J) - b``. A servo whose loop rang at
    its top stretch would be a faulty design; any stretch below that settles slower still.
    For a KRS-3304R2: 0.29 N·m·s/rad (1.7 x its back-EMF damping). Without it the model's
    servos leave the rocking of a robot on its feet nearly undamped (a damping ratio near 0.1
    at the ankles): docs/physics.md, "The servo model"."""
    kp = stiffness(spec, STRETCH_MAX)
    return max(0.0, 2.0 * math.sqrt(kp * armature(spec)) - back_emf_damping(spec))


WHEEL_FULL_SCALE_DEG = TRAVEL_DEG
"""A servo in wheel (rotation) mode turns continuously; the value sent sets its speed: 7500
stops it, the distance from 7500 is the speed and its sign the direction, 3500 and 11500
are full speed (the ICS tools step the command within 3500-11500 in rotation mode,
KXR-KITS.md §5). Kondo publishes no value-to-speed scale, so it is taken linear: the
command's joint-angle equivalent (the model's one conversion, sign and trim included) over
the servo's travel (:data:`TRAVEL_DEG`, 135° = 4000 counts) is the motor's duty, -1..1. A
``wheel`` joint's actuator applies ``duty x stall torque``; with the hinge's back-EMF damping
(stall / no-load speed) that is a DC motor's torque-speed line, so an unloaded wheel settles
at ``duty x no-load speed``."""


def wheel_duty(angle: float) -> float:
    """The motor duty (-1..1) of a wheel servo sent the value whose joint-angle equivalent is
    ``angle`` (rad; see :data:`WHEEL_FULL_SCALE_DEG`)."""
    return max(-1.0, min(1.0, angle / math.radians(WHEEL_FULL_SCALE_DEG)))
