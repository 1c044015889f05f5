"""The gyro and the accelerometer as the board reads them: AD channel inputs (10 bits).

The RCB-4HV reads analog sensors on AD1-AD10 (10-bit, 0-1023 over 0-5 V). The board's
measured register is the input minus the channel's reference (spec 10.4); this module gives
the *inputs*, what the pins see. Where the sensors sit and how they scale is a property of
the robot's wiring, so it is a :class:`SensorLayout` with documented defaults:

* **At rest** a sensor reads what HeartToHeart4's analog calibration recorded for its
  channel: the calibration stores the reading at rest as the channel's reference, so a
  calibrated channel (image reference 1..1023,
  :func:`~rcb4hv.rom.calibration.calibrated_ad_inputs`) reads its reference plus the signal,
  and its measured register reads the signal alone. Kondo's KXR samples and the fixture
  calibrate the gyro (AD1, AD2) to 273. An uncalibrated channel rests at the layout's zero.
* **Accelerometer** (two axes): forward (x) on **AD5**, left (y) on **AD3**. The channels
  and the scale come from the robot's own program: the fixture's "which side am I lying
  on?" motion (KXR-L2 standard set, ``XL2G_117``) reads AD5 to tell lying on the back
  (AD5 >= 500: it plays "get up from the back") from lying on the front (AD5 <= 150), and
  AD3 (>= 480 or <= 180) to tell lying on a side. Both threshold pairs are symmetric about
  325-330 counts, the reading upright (0 g), so the zero is **325** counts (1.59 V of 5 V).
  No public source gives the sensor's sensitivity; **1 V/g** (205 counts per g), a common
  analog accelerometer figure, puts lying flat (±1 g) 25-55 counts beyond every threshold,
  so the program tells the poses apart within about 20° of lying flat, as a program
  written for such a sensor would. The reading is the specific force (acceleration minus
  gravity): lying on the back the forward axis points up and reads +1 g (AD5 = 530).
  (Those channels are uncalibrated in the fixture: their references are 0.)
* **Gyro** (two axes): roll rate (about x) on **AD1**, pitch rate (about y) on **AD2**:
  Kondo's "Hello KXR-L2" sample mixes AD2 into both ankle pitch servos (x 9) and AD1 into
  both ankle roll servos (x 8), so AD2 is the pitch axis and AD1 the roll axis.

  *Sign* (derived, not chosen): the firmware adds measured x multiplier to the value sent
  to the servo (spec 9), Kondo's multipliers are positive on both sides, and the mixing
  damps sway on the real robot. With the KXR's joint map (ankle pitch and roll both sign
  -1: +counts turn the foot by a negative angle about +y / +x relative to the shank), a
  forward pitch rate (+y, the head moving towards +x) is damped by turning the shank back
  over the foot, i.e. the foot by a positive angle relative to the shank: -counts, so the
  measured value must fall as the pitch rate rises: **sign -1**. The roll axis alike
  (+x rate: the head moving right; the damping ankle roll is +angle, -counts): **sign -1**.
  ``tests/physics/test_gyro_mixing.py`` shows the push experiment: with these signs the
  mixing damps sway, with the opposite signs it excites it.

  *Scale* (chosen: no public figure exists for Kondo's KRG-3 / KRG-4 gyros): **0.06 counts per
  °/s** (0.29 mV per °/s). Kondo chose its multipliers (x 8, x 9) on the real robot so that the
  mixing damps sway without shaking it; a feedback loop tuned by hand keeps a gain margin of
  about 2 (6 dB). In this model Kondo's x 9 into the KXR's ankles starts a 5 Hz oscillation of
  the torso from 0.12-0.13 counts per °/s (a push experiment, docs/physics.md; 0.105-0.11 before
  the servos' controller braking, :func:`rcb4hv.robot.servos.controller_damping`); half of that
  is 0.06. For comparison, the calibrated rest reading, 273 counts = 1.33 V, is the null output
  of Murata's ENC-03 family of piezo gyros (1.35 V), whose raw scale factor, 0.67 mV per °/s,
  would be 0.137 counts per °/s: past the onset in this model. At 0.06 Kondo's x 9 moves an
  ankle 0.54 counts (0.018°) per °/s of sway. How much the outcomes depend on the figure is in
  the sensitivity table of docs/physics.md (``make sensitivity``).

Values are clamped to 0..1023 like a real ADC.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

__all__ = ["DEFAULT_SENSORS", "GYRO_COUNTS_PER_DPS", "SensorLayout"]

_COUNTS_PER_VOLT = 1024 / 5.0  # 10-bit ADC over 0-5 V
_ZERO = 325.0  # counts at 0 g: the middle of the fixture program's thresholds
_G = 9.81
GYRO_COUNTS_PER_DPS = 0.06  # chosen (see the module docstring)
_NO_REST: Mapping[int, int] = {}


@dataclass(frozen=True, slots=True)
class SensorLayout:
    """Which AD channel reads which sensor axis, the scales and the gyro's signs (see the
    module docstring). A channel of ``None`` is not wired."""

    accel_x: int | None = 5
    accel_y: int | None = 3
    gyro_x: int | None = 1
    gyro_y: int | None = 2
    accel_zero: float = _ZERO
    accel_counts_per_g: float = 1.0 * _COUNTS_PER_VOLT
    gyro_zero: float = _ZERO
    """The rest reading of an uncalibrated gyro channel."""
    gyro_counts_per_dps: float = GYRO_COUNTS_PER_DPS
    gyro_x_sign: int = -1
    gyro_y_sign: int = -1

    def channels(
        self,
        gyro: tuple[float, float, float],
        accel: tuple[float, float, float],
        rest: Mapping[int, int] = _NO_REST,
    ) -> dict[int, int]:
        """AD inputs from angular velocity (rad/s) and specific force (m/s²) in the root
        frame; ``rest`` the calibrated channels' readings at rest (``{channel: counts}``)."""
        out: dict[int, int] = {}
        g = self.gyro_counts_per_dps
        for ch, zero, v in (
            (self.accel_x, self.accel_zero, accel[0] / _G * self.accel_counts_per_g),
            (self.accel_y, self.accel_zero, accel[1] / _G * self.accel_counts_per_g),
            (self.gyro_x, self.gyro_zero, self.gyro_x_sign * math.degrees(gyro[0]) * g),
            (self.gyro_y, self.gyro_zero, self.gyro_y_sign * math.degrees(gyro[1]) * g),
        ):
            if ch is not None:
                out[ch] = min(1023, max(0, round(rest.get(ch, zero) + v)))
        return out


DEFAULT_SENSORS = SensorLayout()
