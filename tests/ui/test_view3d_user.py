"""The 3D view's logic through NiceGUI's simulated `User`: joint names in the servo table,
the live view following the board, and the motion preview with play, pause and scrubbing."""

from __future__ import annotations

import asyncio
import math
from pathlib import Path
from typing import Any

import pytest
from nicegui.testing.user import User

from rcb4hv.emulator import Board
from rcb4hv.ui.context import UiContext
from rcb4hv.ui.scene3d import RobotBody
from tests.ui.test_user import one, output, run, until, word
from tests.ui.toy_robot import toy_model

MODEL = toy_model()
L_ARM = [link.name for link in MODEL.links].index("l_arm")
TRIM = -600  # counts: 20 degrees


def body(user: User, marker: str) -> RobotBody:
    """The robot object inside the 3D scene marked ``marker``."""
    scene = one(user, marker)
    found = [o for o in scene.objects.values() if isinstance(o, RobotBody)]
    assert len(found) == 1
    return found[0]


def arm(b: RobotBody) -> list[float]:
    """The left arm's transform rows as last sent to the browser."""
    pose: Any = b.args[1]
    return list(pose[0][L_ARM])


def test_servo_table_and_sliders_name_the_joints() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await until(lambda: len(one(user, "servo-table").rows) == 17)
        rows = {r["ics"]: r["joint"] for r in one(user, "servo-table").rows}
        assert rows[2] == "l_shoulder_pitch" and rows[3] == "r_shoulder_pitch"
        assert rows[4] == "-"  # the toy model maps no servo 4
        assert one(user, "joint-16").text == "l_knee"
        await user.should_see("toy humanoid (test)")

    run(scenario, robot=MODEL)


def test_the_live_view_follows_a_servo_on_both_pages() -> None:
    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        servos, remote = body(user, "servos-3d"), body(user, "remote-3d")
        # a trim on ICS 2 (the block's base): the board reports position minus trim, so the
        # view must not subtract it again
        board.ram[word(board, 0x44 + 2 * 2) + 2 : word(board, 0x44 + 2 * 2) + 4] = TRIM.to_bytes(
            2, "little", signed=True
        )
        await until(lambda: len(ctx.session.state.servos) == 17)
        await until(lambda: next(s for s in ctx.session.state.servos if s.ics == 2).trim == TRIM)
        before = arm(servos)
        one(user, "slider-2").set_value(60.0)  # the left shoulder forward by 60 degrees
        await until(lambda: output(board, 2) == ctx.session.robot.to_position(2, 60.0))
        await until(lambda: arm(servos) != before and arm(remote) == arm(servos))
        # rows of the arm's rotation: about +y by the joint angle of ICS 2's measured value
        st = next(s for s in ctx.session.state.servos if s.ics == 2)
        a = MODEL.motion_angle(2, st.measured)
        assert st.trim == TRIM and a == pytest.approx(math.radians(60.0), abs=0.01)
        assert arm(servos)[0] == round(math.cos(a), 5) and arm(servos)[2] == round(math.sin(a), 5)
        sent = ctx.session.state.polls
        await until(lambda: ctx.session.state.polls > sent + 3)
        # a pose that does not change is not sent again
        pose = servos.args[1]
        await asyncio.sleep(0.3)
        assert servos.args[1] is pose

    run(scenario, robot=MODEL)


def test_the_preview_plays_pauses_and_scrubs_a_project_motion(kxr_project_path: Path) -> None:
    from rcb4hv.hth4 import load_project

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        ctx.set_project(load_project(kxr_project_path), "kxr.h4p")
        table = one(user, "project-motions")
        await until(lambda: len(table.rows) == 65)
        assert ctx.robot is not None  # the Project page names the model it plays on
        assert one(user, "preview-3d-caption").text == f"{ctx.robot.title} ({ctx.robot_source})"
        table.selected = [r for r in table.rows if r["slot"] == 21]
        user.find(marker="preview-run").click()
        await until(lambda: "completed" in one(user, "preview-info").text, 30)
        assert "motion 21" in one(user, "preview-info").text
        scrub = one(user, "preview-scrubber")
        duration = float(scrub.props["max"])
        assert 1.0 < duration < 20.0
        b = body(user, "preview-3d")
        await until(lambda: float(scrub.value) > 0.2)  # it plays in real time
        user.find(marker="preview-play").click()  # pause
        await asyncio.sleep(0.1)
        paused = float(scrub.value)
        await asyncio.sleep(0.3)
        assert float(scrub.value) == paused
        scrub.set_value(0.0)
        start = b.args[1]
        scrub.set_value(duration / 2)
        assert b.args[1] != start
        assert one(user, "preview-status").text.startswith(f"t = {duration / 2:.2f}")
        scrub.set_value(duration)
        assert "FELL" not in one(user, "preview-status").text  # the plain simulator has no falls

    run(scenario, robot=MODEL)


def test_opening_a_project_redraws_the_views_with_its_robot(kxr_project_path: Path) -> None:
    from rcb4hv.hth4 import load_project

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        ctx.auto_robot = True
        ctx.set_project(load_project(kxr_project_path), "kxr.h4p")
        for name in ("servos", "remote"):
            await until(lambda n=name: "KXR-L2 with grippers" in one(user, f"{n}-3d-caption").text)
        kxr = ctx.robot
        assert kxr is not None and kxr.name == "kxr-l2-gripper"
        assert len(body(user, "servos-3d").args[0]) == len(kxr.links)
        table = one(user, "servo-table")
        await until(lambda: {r["ics"]: r["joint"] for r in table.rows}[2] == kxr.servo(2).joint)
        ctx.set_project(None)  # no project: the board's servo table decides
        await until(lambda: "22-axis" in one(user, "servos-3d-caption").text)
        assert "matches the board's servos" in one(user, "remote-3d-caption").text

    run(scenario, robot=MODEL)


def test_a_physics_preview_marks_the_fall(
    kxr_project_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    from rcb4hv.hth4 import load_project
    from rcb4hv.robot.builtin import load_builtin
    from rcb4hv.ui import preview
    from rcb4hv.ui.playback import Playback, TimedPose

    robot = load_builtin("kxr-l2-gripper")
    upright = TimedPose(0.0, {}, None)
    lying = TimedPose(1.0, {}, ((0, 0, 1, 0), (0, 1, 0, 0), (-1, 0, 0, 0.05), (0, 0, 0, 1)))
    falls = Playback(
        1, "falls", (upright, TimedPose(0.5, {}, None), lying), "completed", "physics", 0.5
    )

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        ctx.set_project(load_project(kxr_project_path), "kxr.h4p")
        assert one(user, "preview-physics").value  # MuJoCo is installed: physics by default
        table = one(user, "project-motions")
        await until(lambda: len(table.rows) == 65)
        table.selected = [r for r in table.rows if r["slot"] == 1]
        user.find(marker="preview-run").click()
        await until(lambda: "(physics)" in one(user, "preview-info").text, 60)
        assert "motion 1" in one(user, "preview-info").text
        # a playback that falls (a stand-in for the physics result) is marked on the
        # scrubber, in the status line and by the centre-of-mass mark turning red
        monkeypatch.setattr(preview, "physics_playback", lambda *a: falls)
        user.find(marker="preview-run").click()
        await until(lambda: "falls" in one(user, "preview-info").text, 30)
        scrub = one(user, "preview-scrubber")
        assert scrub.props["marker-labels"] == {0.5: "fall"}
        b = body(user, "preview-3d")
        scrub.set_value(0.25)
        assert b.args[1][4] is False and "FELL at 0.50 s" in one(user, "preview-status").text
        scrub.set_value(0.75)
        assert b.args[1][4] is True
        scrub.set_value(1.0)
        assert b.args[1][1][2] < 0.2  # lying: the centre of mass is low
        root = [link.name for link in robot.links].index(robot.root)
        assert b.args[1][0][root][11] == 0.05  # the root link where physics put it

    run(scenario, robot=robot)


def test_the_fallback_model_gives_way_once_the_board_answers() -> None:
    from rcb4hv.robot.builtin import load_builtin

    async def scenario(user: User, ctx: UiContext, board: Board) -> None:
        await until(lambda: "toy humanoid" in one(user, "servos-3d-caption").text)
        # as if the board had not answered when the dashboard started
        ctx.auto_robot, ctx.robot, ctx.robot_source = True, load_builtin("khr3hv"), "default"
        await until(lambda: "22-axis" in one(user, "servos-3d-caption").text)
        assert ctx.robot_source == "matches the board's servos"

    run(scenario, robot=MODEL)


@pytest.mark.parametrize("robot", ["kxr:L6", "kxr:L4T", "khr3hv"])
def test_the_camera_frames_the_whole_robot_tall_or_flat(robot: str) -> None:
    """Every corner of every part of the robot projects inside the view, in the Editor's
    square view and the Project preview's wider one: the flat KXR-L6 was framed by a height
    it does not have, its legs ran off both sides while the top 40 % stayed empty."""
    from nicegui.testing.user_simulation import user_simulation

    from rcb4hv.robot.balance import placed
    from rcb4hv.robot.builtin import load_robot
    from rcb4hv.robot.kinematics import apply, compose, from_xyz_rpy
    from rcb4hv.ui.scene3d import RobotScene

    model = load_robot(robot)
    sizes = [(420, 420), (560, 480), (460, 420)]
    views: list[RobotScene] = []

    def root() -> None:
        views[:] = [RobotScene(model, width=w, height=h) for w, h in sizes]

    async def main() -> None:
        async with user_simulation(root=root) as user:
            await user.open("/")

    asyncio.run(main())
    stance = placed(model, {}, None)
    corners = [
        apply(compose(stance.frames[link.name], from_xyz_rpy(g.pos, g.rpy)), (x, y, z))
        for link in model.links
        for g in link.geoms
        for x, y, z in _corners(g.shape, g.size)
    ]
    for (w, h), view in zip(sizes, views, strict=True):
        cam = view.scene.camera
        tan_v = math.tan(math.radians(cam.params["fov"]) / 2)
        eye = (cam.x, cam.y, cam.z)
        back = _unit(
            tuple(
                e - t
                for e, t in zip(eye, (cam.look_at_x, cam.look_at_y, cam.look_at_z), strict=True)
            )
        )
        right = _unit(_cross((0.0, 0.0, 1.0), back))
        up = _cross(back, right)
        xs, ys = [], []
        for p in corners:
            q = tuple(a - b for a, b in zip(p, eye, strict=True))
            depth = -_dot(q, back)
            assert depth > cam.params["near"]
            xs.append(_dot(q, right) / (depth * tan_v * w / h))
            ys.append(_dot(q, up) / (depth * tan_v))
        # inside the view, and filling it along its tighter direction (not a speck)
        assert max(map(abs, xs)) < 0.95 and max(map(abs, ys)) < 0.95, (robot, w, h)
        assert max(max(xs) - min(xs), max(ys) - min(ys)) > 1.2, (robot, w, h)


def _corners(shape: str, size: tuple[float, float, float]) -> list[tuple[float, float, float]]:
    if shape == "box":
        half = (size[0] / 2, size[1] / 2, size[2] / 2)
    elif shape == "cylinder":
        half = (size[0], size[0], size[1] / 2)
    else:
        half = (size[0], size[0], size[0])
    return [
        (sx * half[0], sy * half[1], sz * half[2])
        for sx in (-1, 1)
        for sy in (-1, 1)
        for sz in (-1, 1)
    ]


def _unit(v: Any) -> tuple[float, float, float]:
    n = math.sqrt(sum(c * c for c in v))
    return (v[0] / n, v[1] / n, v[2] / n)


def _cross(a: Any, b: Any) -> tuple[float, float, float]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a: Any, b: Any) -> float:
    return float(sum(x * y for x, y in zip(a, b, strict=True)))
