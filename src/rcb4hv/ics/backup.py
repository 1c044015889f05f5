"""EEPROM backups: a JSON file per servo, saved atomically, restored with the target servo's
"do not change" bytes and ID kept as read (shared by ``rcb4hv ics eeprom`` and the dashboard).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from rcb4hv.errors import IcsError
from rcb4hv.files import write_atomic
from rcb4hv.ics.eeprom import Eeprom
from rcb4hv.ics.host import IcsServo

__all__ = ["backup_json", "load_backup", "restore", "save_backup"]


def backup_json(eeprom: Eeprom, servo_id: int) -> dict[str, Any]:
    """The backup document of one servo's EEPROM."""
    return {**eeprom.to_json(), "servo_id": servo_id}


def save_backup(path: str | Path, eeprom: Eeprom, servo_id: int) -> None:
    """Write the backup atomically (:func:`rcb4hv.files.write_atomic`)."""
    path = Path(path)
    text = json.dumps(backup_json(eeprom, servo_id), indent=2) + "\n"
    write_atomic(path, text)


def load_backup(source: str | Path | bytes) -> Eeprom:
    """Read a backup from a file (or its bytes); :class:`IcsError` if it is not one."""
    try:
        raw = source if isinstance(source, bytes) else Path(source).read_bytes()
        obj = json.loads(raw)
    except (OSError, ValueError) as exc:
        raise IcsError(f"cannot read the EEPROM backup: {exc}") from exc
    return Eeprom.from_json(obj)


def restore(servo: IcsServo, backup: Eeprom) -> dict[str, tuple[int | None, int | None]]:
    """Write ``backup`` to ``servo`` keeping its own "do not change" bytes and ID; verified by
    reading back. Returns ``{field: (before, after)}``."""
    current = servo.eeprom()
    new = current.merged_from(backup)
    if new.data == current.data:
        return {}
    back = servo.write_eeprom(new)
    return current.differences(back)
