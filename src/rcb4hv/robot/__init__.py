"""Robot models: what the board moves.

A :class:`RobotModel` is links (shape, mass, inertia), joints (axis, limits) and a joint map
(servo index -> joint, sign, offset, servo type). Built-in models, forward kinematics,
URDF/MJCF import and export live in this package; physics lives in :mod:`rcb4hv.physics`.
"""

from rcb4hv.robot.kinematics import Transform, center_of_mass, forward
from rcb4hv.robot.model import (
    Geom,
    Inertial,
    Joint,
    JointKind,
    Link,
    RobotModel,
    ServoJoint,
    ServoSpec,
    Side,
    Vec3,
    chain,
)

__all__ = [
    "Geom",
    "Inertial",
    "Joint",
    "JointKind",
    "Link",
    "RobotModel",
    "ServoJoint",
    "ServoSpec",
    "Side",
    "Transform",
    "Vec3",
    "center_of_mass",
    "chain",
    "forward",
]
