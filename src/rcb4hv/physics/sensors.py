"""The gyro and the accelerometer as the board reads them: AD channel values (10 bits).

The RCB-4HV reads analog sensors on AD1-AD10 (10-bit, 0-1023 over 0-5 V). Where the sensors
sit and how they scale is a property of the robot's wiring, so it is a :class:`SensorLayout`
with documented defaults:

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
* **Gyro** (two axes): roll rate (about x) on **AD1**, pitch rate (about y) on **AD2**.
  Chosen: the fixture's ankle servos carry mixing rates but no mixing source, and no public
  source gives a KRG-4's wiring or scale. Zero at the accelerometer's zero (the same sensor
  supply) and ±300 °/s over ±1.5 V (a common MEMS gyro range), so 1.024 counts per °/s.

Values are clamped to 0..1023 like a real ADC.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["DEFAULT_SENSORS", "SensorLayout"]

_COUNTS_PER_VOLT = 1024 / 5.0  # 10-bit ADC over 0-5 V
_ZERO = 325.0  # counts at 0 g / 0 °/s: the middle of the fixture program's thresholds
_G = 9.81


@dataclass(frozen=True, slots=True)
class SensorLayout:
    """Which AD channel reads which sensor axis, and the scales (see the module docstring).
    A channel of ``None`` is not wired."""

    accel_x: int | None = 5
    accel_y: int | None = 3
    gyro_x: int | None = 1
    gyro_y: int | None = 2
    accel_zero: float = _ZERO
    accel_counts_per_g: float = 1.0 * _COUNTS_PER_VOLT
    gyro_zero: float = _ZERO
    gyro_counts_per_dps: float = 1.5 * _COUNTS_PER_VOLT / 300.0

    def channels(
        self, gyro: tuple[float, float, float], accel: tuple[float, float, float]
    ) -> dict[int, int]:
        """AD values from angular velocity (rad/s) and specific force (m/s²), root frame."""
        out: dict[int, int] = {}
        for ch, v in (
            (self.accel_x, self.accel_zero + accel[0] / _G * self.accel_counts_per_g),
            (self.accel_y, self.accel_zero + accel[1] / _G * self.accel_counts_per_g),
            (self.gyro_x, self.gyro_zero + math.degrees(gyro[0]) * self.gyro_counts_per_dps),
            (self.gyro_y, self.gyro_zero + math.degrees(gyro[1]) * self.gyro_counts_per_dps),
        ):
            if ch is not None:
                out[ch] = min(1023, max(0, round(v)))
        return out


DEFAULT_SENSORS = SensorLayout()
