"""A udev rule for the Kondo USB adapters (Linux).

The adapters are FTDI chips with Kondo's own USB IDs (VID 165C, PID 0008 for the USB adapter
HS, 0007 for the older one). The kernel's ``ftdi_sio`` driver lists only 165C:0002 (Kondo's
first serial cable) in its table, so the rule first tells the driver about the ID through
``new_id``; then, for the tty it creates, it adds a stable ``/dev/rcb4-<serial>`` symlink,
gives the group read/write access and sets the FTDI latency timer to 1 ms.

Sources for the IDs: 165C:0008 is what the ``rcb4`` library (iory/rcb4) matches to find an
RCB-4 (its ``99-rcb4-udev.rules`` and ``RCB4Interface.from_port``); 0007 is the older adapter
named in the project's working spec (PROTOCOL.md, section 1); 165C:0002 is the Kondo entry in
Linux's ``drivers/usb/serial/ftdi_sio_ids.h``.
"""

from __future__ import annotations

from typing import Final

from rcb4hv.transport import KONDO_PIDS, KONDO_VID

__all__ = ["RULE_PATH", "install_commands", "udev_rule"]

RULE_PATH: Final = "/etc/udev/rules.d/99-rcb4hv.rules"


def udev_rule(group: str = "dialout") -> str:
    """The rule file's text."""
    vid = f"{KONDO_VID:04x}"
    lines = [
        "# rcb4hv: Kondo USB adapters (RCB-4HV). Written by `rcb4hv udev-rule`. Install with:",
        *(f"#   {c}" for c in install_commands(group)),
        "# 1. tell ftdi_sio about the Kondo IDs (the kernel table has only 165c:0002)",
    ]
    new_id = "/sys/bus/usb-serial/drivers/ftdi_sio/new_id"
    for pid in KONDO_PIDS:
        lines.append(
            f'ACTION=="add", SUBSYSTEM=="usb", ATTRS{{idVendor}}=="{vid}", '
            f'ATTRS{{idProduct}}=="{pid:04x}", RUN+="/sbin/modprobe ftdi_sio", '
            f"RUN+=\"/bin/sh -c 'echo {vid} {pid:04x} > {new_id}'\""
        )
    lines.append(f"# 2. the tty: /dev/rcb4-<serial>, group {group} read/write, latency timer 1 ms")
    for pid in KONDO_PIDS:
        lines.append(
            f'ACTION=="add", SUBSYSTEM=="tty", ATTRS{{idVendor}}=="{vid}", '
            f'ATTRS{{idProduct}}=="{pid:04x}", SYMLINK+="rcb4-$attr{{serial}}", '
            f'GROUP="{group}", MODE="0660"'
        )
        lines.append(
            f'ACTION=="add", SUBSYSTEM=="usb-serial", DRIVER=="ftdi_sio", '
            f'ATTRS{{idVendor}}=="{vid}", ATTRS{{idProduct}}=="{pid:04x}", '
            f'ATTR{{latency_timer}}="1"'
        )
    return "\n".join(lines) + "\n"


def install_commands(group: str = "dialout") -> list[str]:
    """The two commands that install the rule and apply it to a plugged-in adapter."""
    option = "" if group == "dialout" else f" --group {group}"
    return [
        f"rcb4hv udev-rule{option} | sudo tee {RULE_PATH}",
        "sudo udevadm control --reload-rules && sudo udevadm trigger",
    ]
