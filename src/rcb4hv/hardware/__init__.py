"""Getting a real board talking: :func:`run_doctor` (``rcb4hv doctor``) checks a setup step by
step, :func:`udev_rule` (``rcb4hv udev-rule``) writes the Linux udev rule for the Kondo USB
adapters."""

from __future__ import annotations

from rcb4hv.hardware.doctor import Check, all_passed, run_doctor
from rcb4hv.hardware.host import Host, PortInfo, latency_command
from rcb4hv.hardware.udev import RULE_PATH, install_commands, udev_rule

__all__ = [
    "RULE_PATH",
    "Check",
    "Host",
    "PortInfo",
    "all_passed",
    "install_commands",
    "latency_command",
    "run_doctor",
    "udev_rule",
]
