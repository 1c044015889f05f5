"""The dashboard's logic through NiceGUI's simulated `User` (no browser): every page against
an in-process emulated board behind a real BoardSession."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import pytest
from nicegui.testing.user import User
from nicegui.testing.user_simulation import user_simulation

from rcb4hv.emulator import Board, EmulatorConfig, RealClock, emulator_url
from rcb4hv.robot import RobotModel
from rcb4hv.rom.default import DEFAULT_ICS, default_image
from rcb4hv.session import BoardSession
from rcb4hv.ui.app import build_root
from rcb4hv.ui.context import UiContext

Scenario = Callable[[User, UiContext, Board], Awaitable[None]]


def run(scenario: Scenario, *, robot: RobotModel | None = None) -> None:
    board = Board(
        EmulatorConfig(virtual_servos=DEFAULT_ICS),
        clock=RealClock(speed=2.0),
        rom_image=default_image(),
    )
    session = BoardSession(emulator_url(board), poll_hz=20)
    ctx = UiContext(session, robot=robot, robot_source="test")

    async def main() -> None:
        async with user_simulation(root=build_root(ctx)) as user:
            await user.open("/")
            await scenario(user, ctx, board)

    try:
        session.start()
        session.wait_connected(timeout=10)
        asyncio.run(main())
    finally:
        session.close()
        board.close()


def one(user: User, marker: str) -> Any:
    found = user.find(marker=marker).elements
    assert len(found) == 1, f"{marker}: {len(found)} elements"
    return next(iter(found))


async def until(cond: Callable[[], bool], timeout: float = 10.0) -> None:
    deadline = time.monotonic() + timeout
    while not cond():
        assert time.monotonic() < deadline, "condition not met in time"
        await asyncio.sleep(0.05)


async def open_in_editor(user: User, path: Path, motions: int = 65) -> None:
    """Open ``path`` on the Editor page and wait for its ``motions`` motions to be listed."""
    one(user, "editor-path").set_value(str(path))
    user.find(marker="editor-open").click()
    await until(lambda: len(one(user, "editor-motion").options) == motions)


def word(board: Board, address: int) -> int:
    return int(board.ram[address]) | int(board.ram[address + 1]) << 8


def output(board: Board, ics: int) -> int:
    return word(board, word(board, 0x44 + 2 * ics) + 6)


def test_every_page_and_the_stop_button_are_there() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        for tab in ("Board", "Servos", "Remote", "Motions", "Project", "Teach"):
            await user.should_see(tab)
        await user.should_see(marker="stop")
        await until(lambda: len(one(user, "servo-table").rows) == 17)
        await until(
            lambda: any(
                r["field"] == "version" and "CB-4" in r["value"]
                for r in one(user, "board-table").rows
            )
        )
        assert one(user, "link-status").text.startswith("rcb4emu://")

    run(scenario)


def test_slider_coalesced_move_and_hold_free() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        for v in range(0, 40, 2):  # a burst of slider events
            one(user, "slider-2").set_value(float(v))
        await until(lambda: output(board, 2) == ctx.session.robot.to_position(2, 38.0))
        assert ctx.session.moves_sent < 20
        user.find(marker="free-3").click()
        await until(lambda: output(board, 3) == 0x8000)
        user.find(marker="servos-hold-all").click()
        await until(lambda: all(output(board, k) == 0x7FFF for k in DEFAULT_ICS))
        one(user, "slider-4").set_value(500.0)  # past the range: refused, nothing sent
        await user.should_see("outside 3500..11500")
        assert output(board, 4) == 0x7FFF

    run(scenario)


def test_a_slider_follows_its_servo_when_left_alone() -> None:
    """A servo moved by something else (a motion, another client, a hand) takes its slider
    along once the user has left the slider alone, and the page sends nothing for that (the
    slider stayed where it was left, so touching it jumped the servo back)."""

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        robot = ctx.session.robot
        assert robot is not None
        target = robot.to_position(5, 30.0)
        ctx.session.submit(lambda r: r.move({5: target})).result(5)
        sent = ctx.session.moves_sent
        await until(lambda: abs(one(user, "slider-5").value - 30.0) < 1.0, 10)
        assert ctx.session.moves_sent == sent  # following sends no move
        assert output(board, 5) == target

    run(scenario)


def test_pad_press_and_hold_sets_and_clears_the_button_word() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        user.find(marker="pad-triangle").trigger("pointerdown")
        await until(lambda: (board.ram[0x350], board.ram[0x351]) == (0x00, 0x10))
        user.find(marker="pad-up").trigger("pointerdown")
        await until(lambda: (board.ram[0x350], board.ram[0x351]) == (0x00, 0x11))
        user.find(marker="pad-triangle").trigger("pointerup")
        user.find(marker="pad-up").trigger("pointerleave")
        await until(lambda: (board.ram[0x350], board.ram[0x351]) == (0, 0))
        await until(lambda: ctx.session.state.motion == 1)  # the triangle's vector jump
        one(user, "pa-2").set_value(200)
        await until(lambda: board.ram[0x353] == 200)

    run(scenario)


def test_motion_play_and_wait_then_pause_resume() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        one(user, "motion-slot").set_value(2)
        user.find(marker="motion-play-wait").click()
        await user.should_see("waiting for motion 2")
        await until(lambda: "ended after" in one(user, "motion-status").text, 20)
        user.find(marker="motion-play").click()
        await until(lambda: ctx.session.state.motion == 2)
        user.find(marker="motion-pause").click()
        await until(lambda: "(paused)" in one(user, "motion-current").text)
        user.find(marker="motion-resume").click()
        await until(lambda: "(paused)" not in one(user, "motion-current").text)
        user.find(marker="stop").click()
        await until(lambda: ctx.session.state.motion is None)
        await until(lambda: all(output(board, k) == 0x7FFF for k in DEFAULT_ICS))
        user.find(marker="motion-scan").click()
        await until(lambda: [r["slot"] for r in one(user, "motion-table").rows] == [1, 2], 20)
        # a slot with no motion stops the board's program: said at once, not "started"
        one(user, "motion-slot").set_value(50)
        user.find(marker="motion-play").click()
        await user.should_see("stopped with a ROM error")
        assert "stopped (ROM error)" in one(user, "motion-status").text
        for bad in (None, 2.5):  # an empty box or a fraction plays nothing
            one(user, "motion-slot").set_value(bad)
            user.find(marker="motion-play").click()
            await user.should_see("a motion is a whole number")

    run(scenario)


def test_project_page_shows_the_project(kxr_project_path: Path) -> None:
    from nicegui.elements.upload_files import SmallFileUpload

    from rcb4hv.ui.project_page import load_upload

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        load_upload(ctx, "kxr.h4p", kxr_project_path.read_bytes())
        await until(lambda: len(one(user, "project-motions").rows) == 65)
        assert len(one(user, "project-servos").rows) == 18
        binds = one(user, "project-bindings").rows
        assert {"button": "△", "slot": 21, "name": "XL2G_201_挨拶", "compare": "Equals"} in binds
        assert "65 motions" in one(user, "project-summary").text
        from rcb4hv.project.check import check_project

        findings = check_project(ctx.project)  # type: ignore[arg-type]
        assert len(one(user, "project-checks").rows) == len(findings)
        errors = sum(f.severity == "error" for f in findings)
        assert f"project check: {errors} errors" in one(user, "project-check-summary").text
        await until(lambda: len(one(user, "motion-table").rows) == 65)
        up = one(user, "project-upload")
        await up.handle_uploads([SmallFileUpload("junk.h4p", "application/octet-stream", b"<nope")])
        await user.should_see("cannot open junk.h4p: not a HeartToHeart4 project")
        await up.handle_uploads([SmallFileUpload("empty.h4p", "application/octet-stream", b"")])
        await user.should_see("empty.h4p: an empty file, not a HeartToHeart4 project")
        assert ctx.project_name == "kxr.h4p"  # a bad file loses nothing
        with pytest.raises(ValueError, match="limit"):
            load_upload(ctx, "big.h4p", b"x" * (ctx.max_upload + 1))

    run(scenario)


def test_teach_captures_and_saves_into_the_project(kxr_project_path: Path) -> None:
    from rcb4hv.hth4 import dump_project, load_project, parse_project

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        ctx.set_project(load_project(kxr_project_path), "kxr.h4p")
        one(user, "teach-free-select").set_value([2, 3])
        user.find(marker="teach-free").click()
        await until(lambda: output(board, 2) == 0x8000 and output(board, 3) == 0x8000)
        user.find(marker="teach-capture").click()
        await until(lambda: one(user, "teach-count").text == "1 keyframes")
        ctx.session.set_target(4, 9000)
        await until(lambda: output(board, 4) == 9000)
        await asyncio.sleep(0.1)
        user.find(marker="teach-capture").click()
        await until(lambda: one(user, "teach-count").text == "2 keyframes")
        slot = one(user, "teach-slot").value
        one(user, "teach-button").set_value("○ (circle)")
        user.find(marker="teach-save").click()
        await until(lambda: "saved as motion" in one(user, "teach-status").text, 30)
        assert ctx.project is not None
        m = ctx.project.motion(slot)
        assert m.button_data == 0x0040 and len(m.frames) == 4
        data = dump_project(ctx.project)
        assert dump_project(parse_project(data)) == data
        assert slot not in one(user, "teach-slot").options
        user.find(marker="teach-play").click()
        await until(lambda: output(board, 4) == 9000 and output(board, 2) != 0x8000, 10)
        await user.should_see("played 2 keyframes on the board")  # it said nothing
        user.find(marker="teach-clear").click()
        await until(lambda: one(user, "teach-count").text == "0 keyframes")

    run(scenario)


def test_link_error_shows_a_banner() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        ctx.session.reconnect("socket://127.0.0.1:9")
        await until(lambda: "not connected" in one(user, "link-status").text, 10)
        await until(lambda: ctx.session.state.error is not None, 10)
        await user.should_see("Link error", retries=40)
        await user.should_see("Retrying")

    run(scenario)


def test_the_dashboard_builds_without_a_board() -> None:
    """No board behind the link (the session never connects): every page is there, and the
    header says the link is down."""
    session = BoardSession("socket://127.0.0.1:9")

    async def main() -> None:
        async with user_simulation(root=build_root(UiContext(session))) as user:
            await user.open("/")
            for tab in ("Board", "Servos", "Remote", "Motions", "Project", "Teach"):
                await user.should_see(tab)
            await until(lambda: "not connected" in one(user, "link-status").text, 10)
            assert not session.state.connected

    try:
        asyncio.run(main())
    finally:
        session.close()


def test_the_walk_page_generates_a_walk_into_a_new_project_and_simulates_it() -> None:
    from rcb4hv.robot.builtin import load_builtin

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        assert ctx.project is None
        one(user, "gait-steps").set_value(1)
        user.find(marker="gait-go").click()
        await until(lambda: "commanded" in one(user, "gait-status").text, 60)
        text = one(user, "gait-status").text
        assert "stayed up" in text
        assert ctx.project is not None
        (walk,) = [m for m in ctx.project.used_motions if m.name == "gait forward"]
        assert f"motion {walk.slot}:" in text

    run(scenario, robot=load_builtin("kxr-l2"))
