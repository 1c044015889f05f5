"""Physics: the robot in MuJoCo as a servo backend of the emulator (optional extra ``sim``).

* :class:`PhysicsWorld` - one robot model on a flat floor in MuJoCo;
* :class:`PhysicsBackend` - hangs on an emulated :class:`~rcb4hv.emulator.Board`: its servo
  outputs drive the simulated servos, the joint angles and the IMU come back as measured
  positions and AD values;
* :class:`SensorLayout` - the gyro's and accelerometer's AD channels and scales;
* :class:`PhysicsOptions` - factors on the model's chosen figures (sensitivity studies).

MuJoCo is imported when a world is built: without ``pip install 'rcb4hv[sim]'`` that raises
:class:`~rcb4hv.errors.PhysicsUnavailableError`; importing this package never needs it.
The servo model's figures (stall torque, speed, stretch, damping) are in
:mod:`rcb4hv.robot.servos`, the contact's (friction) in :mod:`rcb4hv.robot.mjcf`; the
documentation page "Physics" lists them with their sources.
"""

from rcb4hv.physics.backend import PhysicsBackend
from rcb4hv.physics.options import PhysicsOptions
from rcb4hv.physics.sensors import DEFAULT_SENSORS, SensorLayout
from rcb4hv.physics.world import BasePose, PhysicsWorld, engine_version, require_mujoco

__all__ = [
    "DEFAULT_SENSORS",
    "BasePose",
    "PhysicsBackend",
    "PhysicsOptions",
    "PhysicsWorld",
    "SensorLayout",
    "engine_version",
    "require_mujoco",
]
