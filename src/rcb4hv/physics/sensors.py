"""The gyro and the accelerometer as the board reads them: AD channel values (10 bits).

The RCB-4HV reads analog sensors on AD1-AD10 (10-bit, 0-1023 over 0-5 V). Where the sensors
sit and how they scale is a property of the robot's wiring, so it is a :class:`SensorLayout`
with documented defaults:

* **Accelerometer** (two axes): forward (x) on **AD5**, left (y) on **AD3**. The channels come
  from the fixture's own "which side am I lying on?" motion (KXR-L2 standard set,
  ``XL2G_117``): it reads AD5 to tell lying on the back (AD5 >= 500: get up from the back)
  from lying on the front (AD5 <= 150), and AD3 (>= 480 or <= 180) to tell lying on a side.
  Scale: 0 g at 1.65 V, the mid-supply output of a 3.3 V ratiometric MEMS accelerometer
  (338 counts of 5 V), and 0.8 V/g, the sensitivity of a ±1.5 g analog part (the
  Freescale MMA7361L class), so 164 counts per g: the program's thresholds then sit at
  about ±1 g (lying flat), as a program written for such a sensor would put them.
  The reading is the specific force (acceleration minus gravity): lying on the back the
  forward axis points up and reads +1 g (AD5 = 502).
* **Gyro** (two axes): roll rate (about x) on **AD1**, pitch rate (about y) on **AD2**.
  Chosen: the fixture's ankle servos carry mixing rates but no mixing source, and no public
  source gives a KRG-4's wiring or scale. 0 °/s at 1.65 V (338 counts) like the
  accelerometer, and ±300 °/s over ±1.65 V (a common MEMS gyro range), so 1.126 counts per
  °/s.

Values are clamped to 0..1023 like a real ADC.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["DEFAULT_SENSORS", "SensorLayout"]

_COUNTS_PER_VOLT = 1024 / 5.0  # 10-bit ADC over 0-5 V
_MID_SUPPLY_V = 3.3 / 2  # a 3.3 V ratiometric sensor's zero output
_G = 9.81


@dataclass(frozen=True, slots=True)
class SensorLayout:
    """Which AD channel reads which sensor axis, and the scales (see the module docstring).
    A channel of ``None`` is not wired."""

    accel_x: int | None = 5
    accel_y: int | None = 3
    gyro_x: int | None = 1
    gyro_y: int | None = 2
    accel_zero: float = _MID_SUPPLY_V * _COUNTS_PER_VOLT
    accel_counts_per_g: float = 0.8 * _COUNTS_PER_VOLT
    gyro_zero: float = _MID_SUPPLY_V * _COUNTS_PER_VOLT
    gyro_counts_per_dps: float = _MID_SUPPLY_V * _COUNTS_PER_VOLT / 300.0

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
