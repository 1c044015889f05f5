"""tools/sample_outcomes.py plays a remote-driven walk as a user drives it: its button held.

Kondo's remote-driven walks read the button word and stop at once when it is not held, so a
walk bound to a button is judged with that button held (``project simulate``'s default, 3 s);
an unbound one is played once from standing. Built from our own keyframe motions on the
fixture project.
"""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import replace
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from rcb4hv.hth4 import load_project, save_project
from rcb4hv.hth4.keyframes import Keyframe, add_motion, motion_from_keyframes
from rcb4hv.protocol import Button
from tests.conftest import KXR_PROJECT_DIR

TOOL = Path(__file__).resolve().parents[2] / "tools" / "sample_outcomes.py"


def _tool() -> ModuleType:
    spec = importlib.util.spec_from_file_location("sample_outcomes", TOOL)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def project_file(tmp_path: Path) -> Path:
    """The fixture project with two short walks of ours: 18 bound to UP+S1, 19 unbound."""
    project = load_project(KXR_PROJECT_DIR / "HAC_KXR_HTH4_project.h4p")
    bend = {12: 7700, 13: 7700}  # both knees a little (ICS 12/13), then back
    frames = [Keyframe(0.2, bend), Keyframe(0.2, {12: 7500, 13: 7500})]
    project = add_motion(
        project,
        motion_from_keyframes(
            frames,
            slot=18,
            name="test walk forward",
            button=int(Button.UP | Button.S1),
            date="2026/01/01",
        ),
    )
    project = add_motion(
        project, motion_from_keyframes(frames, slot=19, name="test walk back", date="2026/01/01")
    )
    path = tmp_path / "walks.h4p"
    save_project(project, path)
    return path


def test_the_held_buttons_are_the_ones_each_motion_reads(project_file: Path) -> None:
    from rcb4hv.cli.project_common import load_image
    from rcb4hv.project.run import bound_buttons

    image, lay, _ = load_image(project_file)
    bound = bound_buttons(image, lay)
    assert bound[9] == int(Button.UP)  # the fixture's fast walk loops while UP is held
    # a carrying walk is called from the grab motion and bound to no button of its own; it
    # loops while UP+S2 is held (its button branch), so that is what a user holds
    assert bound[42] == int(Button.UP | Button.S2)
    assert 5 not in bound  # the slow walk counts its steps and reads no button
    # our walk 18 is bound to UP+S1 in the button table but reads no button: holding would
    # only start it again from the main loop, so it is played once
    assert 18 not in bound and 21 not in bound  # nor the fixture's greeting (TRIANGLE)
    assert bound_buttons(bytes(len(image)), lay) == {}  # no image: no table, no error


def test_a_walk_that_goes_on_while_any_button_is_down_holds_its_binding(tmp_path: Path) -> None:
    """Kondo's KHR-3HV remote walks loop while the buttons are not equal to none: the word a
    user holds is the one the main loop starts them with."""
    from rcb4hv.cli.project_common import load_image
    from rcb4hv.hth4.blocks import Program, put_program
    from rcb4hv.hth4.blocks.kinds import Block
    from rcb4hv.project.run import bound_buttons

    project = load_project(KXR_PROJECT_DIR / "HAC_KXR_HTH4_project.h4p")
    stand = Keyframe(0.1, {12: 7500, 13: 7500})
    for slot, button in ((18, int(Button.DOWN)), (19, 0)):
        motion = motion_from_keyframes([stand], slot=slot, name=f"w{slot}", button=button)
        project = add_motion(project, motion)
        loop = Program(
            (
                Block("pose", {"frames": 4, "positions": {"12": 7600, "13": 7600}}, "L1"),
                Block("button_branch", {"buttons": [], "if": "not_equal", "to": "L1"}),
                Block("return"),
                Block("end"),
            ),
            name=f"w{slot}",
            button=button,
        )
        project = put_program(project, slot, loop)
    path = tmp_path / "any.h4p"
    save_project(project, path)
    image, lay, _ = load_image(path)
    bound = bound_buttons(image, lay)
    assert bound[18] == int(Button.DOWN)
    assert 19 not in bound  # reads "any button" but nothing says which


def test_a_steered_loop_holds_the_word_that_starts_it(tmp_path: Path) -> None:
    """Kondo's KXR-L4R slalom (スラローム2) is bound to UP+S3 and tests UP+CIRCLE+S3 (curve)
    before UP+S3 (straight): a user holds the word that starts it, and it goes straight."""
    from rcb4hv.cli.project_common import load_image
    from rcb4hv.hth4.blocks import Program, put_program
    from rcb4hv.hth4.blocks.kinds import Block
    from rcb4hv.project.run import bound_buttons

    project = load_project(KXR_PROJECT_DIR / "HAC_KXR_HTH4_project.h4p")
    straight = int(Button.UP | Button.S3)
    project = add_motion(
        project, motion_from_keyframes([Keyframe(0.1, {12: 7500})], slot=18, name="slalom")
    )
    blocks = (
        Block("pose", {"frames": 4, "positions": {"12": 7600}}, "L1"),
        Block("button_branch", {"buttons": ["UP", "CIRCLE", "S3"], "if": "equal", "to": "L2"}),
        Block("button_branch", {"buttons": ["UP", "S3"], "if": "equal", "to": "L1"}),
        Block("return"),
        Block("pose", {"frames": 4, "positions": {"12": 7400}}, "L2"),
        Block("jump", {"to": "L1"}),
        Block("end"),
    )
    for slot, button in ((18, straight), (19, 0)):
        if slot == 19:
            motion = motion_from_keyframes([Keyframe(0.1, {12: 7500})], slot=19, name="s2")
            project = add_motion(project, motion)
        program = Program(blocks, name=f"s{slot}", button=button)
        project = put_program(project, slot, program)
    path = tmp_path / "slalom.h4p"
    save_project(project, path)
    image, lay, _ = load_image(path)
    bound = bound_buttons(image, lay)
    assert bound[18] == straight  # its binding, one of the words it tests
    assert bound[19] == int(Button.UP | Button.CIRCLE | Button.S3)  # unbound: the first
    assert _tool().label_of("test walk forward") == "walk forward"


def test_a_remote_walk_is_played_with_its_button_held(project_file: Path) -> None:
    tool = _tool()
    held, once = tool.project_outcomes(project_file, None, [9, 18])
    assert (held.slot, held.how) == (9, "held UP for 3 s")
    assert (once.slot, once.how) == (18, "standing")
    assert held.end_pose == once.end_pose == "upright"
    assert held.dx_m > 0.08  # it kept walking: one pass goes about 2 cm
    plain = tool.project_outcomes(project_file, None, [9], hold=False)
    assert plain[0].how == "standing" and plain[0].dx_m < 0.05


def test_a_what_if_reaches_the_physics(project_file: Path) -> None:
    """``--what-if`` is passed to ``project simulate``: the fixture's fast walk back (slot
    10) is a motion whose outcome the floor's friction changes (docs/physics.md)."""
    tool = _tool()
    (plain,) = tool.project_outcomes(project_file, None, [10])
    (slippery,) = tool.project_outcomes(project_file, None, [10], what_if=("friction=0.5",))
    assert (plain.dx_m, plain.dy_m, plain.end_pose) != (
        slippery.dx_m,
        slippery.dy_m,
        slippery.end_pose,
    )


def test_no_slip_judges_each_motions_design_too(project_file: Path) -> None:
    """``--no-slip``: the fixture's carrying step left (slot 44) is built to go 0.10 m left,
    and that travel is judged by the same rule as the physics outcome."""
    tool = _tool()
    (plain,) = tool.project_outcomes(project_file, None, [44])
    (both,) = tool.project_outcomes(project_file, None, [44], no_slip=True)
    assert plain.no_slip is None and plain.right_no_slip is None
    assert both.no_slip is not None and both.no_slip[1] > 0.05
    assert both.right_no_slip is True
    assert (both.dx_m, both.dy_m, both.right) == (plain.dx_m, plain.dy_m, plain.right)
    assert "right no slip" in tool._table([both]) and "no slip:" in tool.summary({"p": [both]})


def test_mirror_judges_each_walk_steps_and_turns_mirror_image() -> None:
    """``--mirror``: the fixture's fine step left (slot 3) and fast turn left (13), mirrored
    in their own slots, must step and turn right; its walk forward (9) must still go
    forward. The model is left-right symmetric, so each mirror image goes where the
    original goes, reflected."""
    tool = _tool()
    fixture = KXR_PROJECT_DIR / "HAC_KXR_HTH4_project.h4p"
    rows = {r.slot: r for r in tool.mirrored_outcomes(fixture, None, [3, 9, 13, 21])}
    assert sorted(rows) == [3, 9, 13]  # the greeting (21) has no mirror label
    assert [rows[s].label for s in (3, 9, 13)] == ["step right", "walk forward", "turn right"]
    assert all(r.right for r in rows.values()), rows
    assert all(r.how.startswith("mirrored, held") for r in rows.values())
    plain = {r.slot: r for r in tool.project_outcomes(fixture, None, [3, 13])}
    assert rows[3].dy_m == pytest.approx(-plain[3].dy_m, abs=0.002)
    assert rows[13].dyaw_deg == pytest.approx(-plain[13].dyaw_deg, abs=0.5)


@pytest.mark.parametrize(
    ("name", "label"),
    [
        ("XL2G_304_左掴み歩行左", "step left"),
        ("XL2G_305_左掴み歩行右", "step right"),  # the left hand carries; it steps right
        ("XL2G_306_左掴み歩行左旋回", "turn left"),
        ("XL2G_314_右掴み歩行左旋回", "turn left"),
        ("XL2G_310_右掴み歩行前", "walk forward"),
        ("XL2GH_05_Slow_Walk_Foreward_5_times", "walk forward"),  # kxreus's spelling
        ("XL2GH_13_Fast_Walk_Left_Rotation", "turn left"),
        ("XL2GH_02_Left_Grasp_Walk_Foreward", "walk forward"),
        ("XL2GH_13_Right_Grasp_Walk_Right", "step right"),
        ("XL2GH_12_Right_Grasp_Walk_Left", "step left"),
        ("XL2GH_06_Left_Kick_Shoot", "other"),
        ("XL2_111_高速歩行左", "step left"),
    ],
)
def test_names_promise_these_outcomes(name: str, label: str) -> None:
    assert _tool().label_of(name) == label


@pytest.mark.parametrize(
    ("robot", "family"),
    [
        ("khr3hv-22", "KHR-3HV"),
        ("kxr-l2-gripper", "KXR humanoid, 5-axis legs"),
        ("kxr:L2L6A7H2G", "KXR humanoid, 6-axis legs"),
        ("kxr:L2W2L5A3H2G", "KXR humanoid, 5-axis legs, wheeled feet"),
        ("kxr:L2L2A6H2G", "KXR humanoid, 2-axis legs"),
        ("kxr:L4R", "KXR-L4R"),
        ("kxr:L4R2A3G", "KXR-L4R with arms"),
        ("kxr:R4LL", "KXR-R4LL"),
        ("kxr:L6", "KXR-L6"),
    ],
)
def test_each_model_falls_in_a_family(robot: str, family: str) -> None:
    assert _tool().family(robot) == family


def test_the_breakdown_counts_named_outcomes_by_family_and_label() -> None:
    """The summary's breakdown: only walks, steps, turns and greetings count, each once in its
    family's row and once in its label's; projects are counted by file."""
    tool = _tool()

    def row(file: str, robot: str, label: str, right: bool | None) -> Any:
        return tool.Outcome(file, 1, "m", label, "completed", False, "upright", 0, 0, 0, right,
                            robot=robot)  # fmt: skip

    results = {
        "a.h4p": [row("a.h4p", "kxr:L6", "walk forward", True),
                  row("a.h4p", "kxr:L6", "turn left", False),
                  row("a.h4p", "kxr:L6", "other", True)],
        "b.h4p": [replace(row("b.h4p", "kxr-l2", "walk forward", True), slot=2),
                  row("b.h4p", "kxr-l2", "walk forward", False),
                  row("b.h4p", "kxr-l2", "get up back", True),
                  row("b.h4p", "kxr-l2", "greeting", None)],
    }  # fmt: skip
    text = tool.breakdown(results)
    assert "| KXR-L6 | 1 | 1 of 2 (50%) |" in text
    assert "| KXR humanoid, 5-axis legs | 1 | 1 of 2 (50%) |" in text
    assert "| walk forward | 2 | 2 of 3 (67%) |" in text
    assert "| turn left | 1 | 0 of 1 (0%) |" in text
    assert not any(f"| {label} |" in text for label in ("other", "get up back", "greeting"))
    # a's walk forward and turn left, b's walk forward in slot 1 (not the one in slot 2)
    assert "first motion of each label in each project: 1 of 3" in text
