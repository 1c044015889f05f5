"""Servo tools page: ICS servo maintenance (scan, ID, parameters, EEPROM backup and restore).

The ICS bus is its own link, not the board's: the Kondo USB adapter HS switched to ICS mode,
the pty or ``socket://`` of ``rcb4hv emulate-ics``, or ``icsemu://`` (an emulated bus in this
process, kept while the page lives). Every call runs in a worker thread, one at a time.
"""

from __future__ import annotations

import asyncio
import json
import logging
import os
import threading
from collections.abc import Callable
from typing import Any, TypeVar

from nicegui import events, ui

from rcb4hv.ics import BAUD_RATES, IcsBus
from rcb4hv.ics.backup import backup_json, load_backup, restore
from rcb4hv.ui.context import UiContext, tid

__all__ = ["EDITABLE", "ID_WARNING", "IcsTools", "build", "param_rows"]

log = logging.getLogger(__name__)
T = TypeVar("T")

ID_WARNING = (
    "Only ONE servo may be on the bus for ID commands: every servo connected answers an ID "
    "read at once, and every one takes a new ID."
)
# the parameters the page edits (the EEPROM's documented fields and flags)
EDITABLE = (
    "stretch",
    "speed",
    "punch",
    "dead_band",
    "damping",
    "response",
    "min_pulse",
    "max_pulse",
    "reverse",
    "free",
    "rotation",
    "baud",
)


def param_rows(fields: dict[str, int | None]) -> list[dict[str, Any]]:
    """The parameters table: one row per field."""
    return [{"name": k, "value": "-" if v is None else v} for k, v in fields.items()]


class IcsTools:
    """One ICS link, opened on first use and reopened when the URL or baud changes."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._bus: IcsBus | None = None
        self._key: tuple[str, int] | None = None

    def call(self, url: str, baud: int, fn: Callable[[IcsBus], T]) -> T:
        with self._lock:
            key = (url.strip(), baud)
            if not key[0]:
                raise ValueError("give the ICS port (adapter in ICS mode, pty, icsemu://)")
            if self._bus is None or self._key != key:
                self.close_locked()
                self._bus, self._key = IcsBus.open(key[0], baud), key
            return fn(self._bus)

    def close_locked(self) -> None:
        if self._bus is not None:
            try:
                self._bus.close()
            finally:
                self._bus, self._key = None, None

    def close(self) -> None:
        with self._lock:
            self.close_locked()


def build(ctx: UiContext) -> None:
    tools = IcsTools()
    # closing may wait for a call in progress (an EEPROM write takes 0.35 s): not in the loop
    ui.context.client.on_disconnect(
        lambda: threading.Thread(target=tools.close, name="ics-close", daemon=True).start()
    )
    with ui.row().classes("items-center"):
        url = tid(
            ui.input("ICS port", value=os.environ.get("RCB4HV_ICS_PORT", "")).classes("w-96"),
            "ics-url",
        )
        baud = tid(ui.select(list(BAUD_RATES), value=115200, label="baud"), "ics-baud")
        scan_btn = tid(ui.button("Scan", icon="search"), "ics-scan")
        found = tid(ui.label(""), "ics-found")

    async def do(fn: Callable[[IcsBus], T], what: str) -> T | None:
        try:
            return await asyncio.to_thread(tools.call, url.value or "", int(baud.value), fn)
        except Exception as exc:  # shown to the user
            log.info("%s failed: %s", what, exc)
            ui.notify(f"{what} failed: {exc}", type="negative", multi_line=True)
            return None

    async def scan() -> None:
        ids = await do(lambda bus: bus.scan(), "scan")
        if ids is not None:
            found.text = f"IDs answering: {' '.join(map(str, ids))}" if ids else "no servo answered"
            if ids:
                servo_id.value = ids[0]

    scan_btn.on_click(scan)

    ui.separator()
    ui.label("Servo ID").classes("text-lg")
    tid(ui.label(ID_WARNING).classes("bg-amber-100 text-amber-900 p-2"), "ics-id-warning")
    with ui.row().classes("items-center"):
        id_label = tid(ui.label("ID: ?"), "ics-id")
        read_id_btn = tid(ui.button("Read ID"), "ics-read-id")
        new_id = tid(ui.number("new ID", value=0, min=0, max=31, step=1), "ics-new-id")
        set_id_btn = tid(ui.button("Set ID", color="orange"), "ics-set-id")

    async def read_id() -> None:
        got = await do(lambda bus: bus.read_id(), "read ID")
        if got is not None:
            id_label.text = f"ID: {got}"

    with ui.dialog() as confirm, ui.card():
        ui.label(ID_WARNING)
        confirm_text = ui.label("")
        with ui.row():
            tid(ui.button("Yes, change the ID", color="orange"), "ics-confirm-id").on_click(
                lambda: confirm.submit(True)
            )
            ui.button("Cancel").on_click(lambda: confirm.submit(False))

    async def set_id() -> None:
        target = int(new_id.value or 0)
        confirm_text.text = f"Give the servo on the bus ID {target}?"
        if not await confirm:
            return
        got = await do(lambda bus: bus.write_id(target), "set ID")
        if got is not None:
            id_label.text = f"ID: {got}"
            servo_id.value = got
            ui.notify(f"servo ID is now {got}", type="positive")

    read_id_btn.on_click(read_id)
    set_id_btn.on_click(set_id)

    ui.separator()
    ui.label("Parameters").classes("text-lg")
    with ui.row().classes("items-center"):
        servo_id = tid(ui.number("servo ID", value=0, min=0, max=31, step=1), "ics-servo-id")
        read_btn = tid(ui.button("Read", icon="download"), "ics-read")
        field = tid(ui.select(list(EDITABLE), value="stretch", label="parameter"), "ics-field")
        value = tid(ui.number("value", value=60, step=1), "ics-value")
        write_btn = tid(ui.button("Write", icon="upload"), "ics-write")
    table = tid(
        ui.table(
            columns=[
                {"name": "name", "label": "Parameter", "field": "name", "align": "left"},
                {"name": "value", "label": "Value", "field": "value", "align": "left"},
            ],
            rows=[],
            row_key="name",
        ).props("dense flat"),
        "ics-params",
    )
    changes = tid(ui.label(""), "ics-changes")

    def sid() -> int:
        return int(servo_id.value or 0)

    async def read() -> None:
        e = await do(lambda bus: bus.servo(sid()).eeprom(), "read")
        if e is not None:
            table.rows = param_rows(e.fields())
            table.update()

    async def write() -> None:
        name, v = str(field.value), int(value.value or 0)
        diff = await do(lambda bus: bus.servo(sid()).update({name: v}), f"write {name}")
        if diff is None:
            return
        changes.text = (
            "; ".join(f"{k} {a} -> {b}" for k, (a, b) in diff.items()) or "nothing changed"
        )
        if "baud" in diff:
            baud.value = diff["baud"][1]
            ui.notify(f"the servo now talks at {diff['baud'][1]} baud", type="warning")
        await read()

    read_btn.on_click(read)
    write_btn.on_click(write)

    ui.separator()
    ui.label("EEPROM backup").classes("text-lg")
    with ui.row().classes("items-center"):
        backup_btn = tid(ui.button("Download backup", icon="save"), "ics-backup")

        async def restored(e: events.UploadEventArguments) -> None:
            try:
                backup = load_backup(await e.file.read())
            except Exception as exc:  # a bad file: say so
                ui.notify(f"cannot restore {e.file.name}: {exc}", type="negative")
                return
            diff = await do(lambda bus: restore(bus.servo(sid()), backup), "restore")
            if diff is not None:
                changes.text = (
                    "; ".join(f"{k} {a} -> {b}" for k, (a, b) in diff.items()) or "nothing changed"
                )
                await read()

        tid(
            ui.upload(label="Restore from backup", auto_upload=True, on_upload=restored).props(
                "accept=.json"
            ),
            "ics-restore",
        )

    async def backup() -> None:
        e = await do(lambda bus: bus.servo(sid()).eeprom(), "backup")
        if e is not None:
            text = json.dumps(backup_json(e, sid()), indent=2) + "\n"
            data = text.encode("utf-8")
            ui.download.content(data, f"ics-servo-{sid()}.json", "application/json")

    backup_btn.on_click(backup)
