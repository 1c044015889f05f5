"""The Servo tools page through NiceGUI's simulated `User`, on an in-process emulated ICS bus
(``icsemu://?bus=N``, so the test can look at the servos)."""

from __future__ import annotations

import json

from nicegui.elements.upload_files import SmallFileUpload
from nicegui.testing.user import User

from rcb4hv.emulator import Board, RealClock
from rcb4hv.emulator.protocol_icsemu import ics_emulator_url
from rcb4hv.ics import EmulatedBus
from rcb4hv.ics.eeprom import Eeprom
from rcb4hv.ui.context import UiContext
from rcb4hv.ui.ics_page import ID_WARNING
from tests.ui.test_user import one, run, until


def test_scan_read_write_backup_and_restore() -> None:
    bus = EmulatedBus.with_ids([0, 3], clock=RealClock())
    url = ics_emulator_url(bus)

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await user.should_see("Servo tools")
        one(user, "ics-url").set_value(url)
        user.find(marker="ics-scan").click()
        await until(lambda: "0 3" in one(user, "ics-found").text)
        await user.should_see(ID_WARNING)
        one(user, "ics-servo-id").set_value(3)
        user.find(marker="ics-read").click()
        await until(lambda: {"name": "stretch", "value": 90} in one(user, "ics-params").rows)
        one(user, "ics-field").set_value("stretch")
        one(user, "ics-value").set_value(44)
        user.find(marker="ics-write").click()
        await until(lambda: "stretch 90 -> 44" in one(user, "ics-changes").text)
        servo = bus.servo(3)
        assert servo is not None and servo.eeprom.stretch == 44
        await until(lambda: {"name": "stretch", "value": 44} in one(user, "ics-params").rows)

        user.find(marker="ics-backup").click()
        response = await user.download.next(timeout=5.0)
        saved = json.loads(response.content)
        assert saved["fields"]["stretch"] == 44 and saved["servo_id"] == 3

        one(user, "ics-servo-id").set_value(0)
        upload = one(user, "ics-restore")
        await upload.handle_uploads(
            [SmallFileUpload("s3.json", "application/json", json.dumps(saved).encode())]
        )
        s0 = bus.servo(0)
        assert s0 is not None
        await until(lambda: s0.eeprom.stretch == 44)
        assert s0.eeprom.servo_id == 0  # the restore kept the target's ID
        await until(lambda: "stretch 90 -> 44" in one(user, "ics-changes").text)
        await upload.handle_uploads([SmallFileUpload("bad.json", "application/json", b"{}")])
        await user.should_see("cannot restore bad.json")

    run(scenario)


def test_an_id_change_asks_first() -> None:
    bus = EmulatedBus.with_ids([0], clock=RealClock())
    url = ics_emulator_url(bus)

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        one(user, "ics-url").set_value(url)
        user.find(marker="ics-read-id").click()
        await until(lambda: one(user, "ics-id").text == "ID: 0")
        one(user, "ics-new-id").set_value(9)
        user.find(marker="ics-set-id").click()
        await user.should_see("Give the servo on the bus ID 9?")
        assert bus.servo(9) is None  # nothing before the answer
        user.find(marker="ics-confirm-id").click()
        await until(lambda: one(user, "ics-id").text == "ID: 9")
        assert bus.servo(9) is not None

    run(scenario)


def test_a_bad_port_is_a_notification() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        one(user, "ics-url").set_value("icsemu://?ids=nope")
        user.find(marker="ics-scan").click()
        await user.should_see("scan failed")

    run(scenario)


def test_eeprom_backup_of_the_page_is_what_the_cli_reads() -> None:
    from rcb4hv.ics.backup import backup_json, load_backup

    e = Eeprom().replace(stretch=12)
    assert load_backup(json.dumps(backup_json(e, 4)).encode()) == e
