"""The Editor page's posing aids in headless Chromium: a foot handle dragged 2 cm with the
mouse moves that foot 2 cm (in the torso frame) in the pose saved; undo takes the whole drag
back; the balance line reads the pose; easing is previewed."""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import pytest

from rcb4hv import hth4
from rcb4hv.hth4.poses import motion_poses
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.robot.kinematics import link_pose, position
from tests.ui.conftest import shot
from tests.ui.test_editor_browser import (  # noqa: F401 - the fixtures are used by name
    _chart_of,
    _choose,
    _input,
    _wait_text,
    gl_browser,
    gl_page,
)

pytestmark = pytest.mark.slow

HOME = 39  # XL2G_291_ホームポジション: one pose, the robot standing
SIDE_STEP = 11  # XL2G_111_高速歩行左: pose 2 stands on the right foot, its CoM outside it
DRAG_M = 0.02

# screen points of the handle ``name`` and of the point DRAG_M above it on the screen
# (perpendicular to the camera's direction, so the drag plane of three.js's DragControls,
# which faces the camera, holds that point); and a hook keeping where the drag ended
_SCREEN = """([name, drag]) => {
  const scene = getElement(document.querySelector('[data-testid=editor-3d]'));
  let handle = null;
  scene.scene.traverse((o) => { if (o.name === name) handle = o; });
  const camera = scene.camera;
  const view = handle.position.clone().sub(camera.position).normalize();
  // up the screen: the world's up made perpendicular to the view (a foot lifted; at the
  // home pose's nearly straight leg a sideways 2 cm would be out of the leg's reach)
  const up = camera.up.clone().sub(view.clone().multiplyScalar(camera.up.dot(view)));
  const side = up.normalize().multiplyScalar(drag);
  const rect = scene.renderer.domElement.getBoundingClientRect();
  const screen = (p) => {
    const v = p.clone().project(camera);
    return [rect.left + (v.x + 1) / 2 * rect.width, rect.top + (1 - v.y) / 2 * rect.height];
  };
  window.rcb4hvDrop = null;
  scene.drag_controls.addEventListener('dragend', (e) => {
    window.rcb4hvDrop = e.object.position.toArray();
  });
  return [screen(handle.position), screen(handle.position.clone().add(side)),
          handle.position.toArray()];
}"""


def _foot(project_path: Path) -> tuple[float, float, float]:
    model = load_builtin("kxr-l2-gripper")
    pose = motion_poses(hth4.load_project(project_path).motion(HOME))[0]
    angles = model.motion_angles({i: v for i, v in pose.values.items() if i in model.indices})
    return position(link_pose(model, "r_foot", angles))


def test_a_foot_dragged_2cm_moves_2cm_in_the_pose_saved(
    gl_page: Any,  # noqa: F811
    kxr_project_path: Path,
    tmp_path: Path,
) -> None:
    page = gl_page
    src = tmp_path / "kxr.h4p"
    src.write_bytes(kxr_project_path.read_bytes())
    out = tmp_path / "dragged.h4p"
    page.get_by_test_id("tab-editor").click()
    _input(page, "editor-path").fill(str(src))
    page.get_by_test_id("editor-open").click()
    _wait_text(page, "editor-status", "no edits")
    _choose(page, "editor-motion", f"M{HOME:03d} XL2G_291")
    _chart_of(page, 0x0B80 + (HOME - 1) * 0x800)
    page.locator("[data-testid=editor-flowchart] g[data-pose='0']").click()
    _wait_text(page, "editor-balance", "stands")
    page.get_by_test_id("editor-3d").scroll_into_view_if_needed()
    time.sleep(1.0)  # three.js draws the pose and the handles
    (x0, y0), (x1, y1), start = page.evaluate(_SCREEN, ["ik:r_foot", DRAG_M])
    page.mouse.move(x0, y0)
    page.mouse.down()
    for k in range(1, 11):
        page.mouse.move(x0 + (x1 - x0) * k / 10, y0 + (y1 - y0) * k / 10)
    page.mouse.up()
    _wait_text(page, "editor-status", "1 edit ")
    dropped = page.evaluate("window.rcb4hvDrop")
    moved = [b - a for a, b in zip(start, dropped, strict=True)]
    assert math.hypot(*moved) == pytest.approx(DRAG_M, abs=0.002)  # the mouse dragged ~2 cm
    time.sleep(1.0)
    shot(page, "posing-handles")
    page.get_by_test_id("editor-undo").click()
    _wait_text(page, "editor-status", "no edits")
    page.get_by_test_id("editor-redo").click()
    _wait_text(page, "editor-status", "1 edit ")
    _input(page, "editor-path").fill(str(out))
    page.get_by_test_id("editor-save").click()
    _wait_text(page, "editor-status", f"{out} - 1 edit - saved")
    # a pose on one foot: the balance line warns; easing the move into it previews in 3D
    _choose(page, "editor-motion", f"M{SIDE_STEP:03d} XL2G_111")
    _chart_of(page, 0x0B80 + (SIDE_STEP - 1) * 0x800)
    page.locator("[data-testid=editor-flowchart] g[data-pose='1']").click()
    _wait_text(page, "editor-balance", "cannot stand still")
    assert "(r_foot)" in page.get_by_test_id("editor-balance").inner_text()
    page.get_by_test_id("editor-ease-preview").click()
    _wait_text(page, "editor-reach", "previewed 4 eased poses")
    time.sleep(1.0)
    shot(page, "posing-balance")
    before, after = _foot(src), _foot(out)
    foot = [b - a for a, b in zip(before, after, strict=True)]
    # the home pose stands upright: the view's frame and the torso's differ by no turn
    assert math.dist(foot, moved) < 0.001
    assert foot[2] > 0.01  # lifted
    assert math.hypot(*foot) == pytest.approx(DRAG_M, abs=0.002)
