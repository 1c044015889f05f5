"""Models of Kondo's KXR kits, built from KXR parts and a project's own evidence.

* :mod:`~rcb4hv.robot.kit.code`: kit codes in project titles (``Hello_KXR-L2W2L6A4H2``);
* :mod:`~rcb4hv.robot.kit.names`: what a servo name says (``右中脚（先）``);
* :mod:`~rcb4hv.robot.kit.figures`: every dimension and mass with its source (provenance);
* :mod:`~rcb4hv.robot.kit.templates` / :mod:`~rcb4hv.robot.kit.assembly`: the frames;
* :mod:`~rcb4hv.robot.kit.convention`: the kits' signs and stock ICS numbers;
* :mod:`~rcb4hv.robot.kit.detect`: project -> model, with the evidence.
"""

from rcb4hv.robot.kit.build import kit_model, stock_joint_map
from rcb4hv.robot.kit.code import FAMILIES, Family, KitCode, parse_kit_code
from rcb4hv.robot.kit.detect import Detection, detect_kit
from rcb4hv.robot.kit.names import Role, parse_servo_name

__all__ = [
    "FAMILIES",
    "Detection",
    "Family",
    "KitCode",
    "Role",
    "detect_kit",
    "kit_model",
    "parse_kit_code",
    "parse_servo_name",
    "stock_joint_map",
]
