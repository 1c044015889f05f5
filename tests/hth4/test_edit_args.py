"""An edit accepts only what the project file can hold, so a session can always be saved:
floats, strings and control characters are refused at the edit (EditError naming the
value), numpy integers are ints; lookups raise typed errors that are still KeyErrors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rcb4hv import hth4
from rcb4hv.cli.teach_cmd import parse_keyframes
from rcb4hv.errors import EditError, NoRobotModelError, NotFoundError, RobotModelError
from rcb4hv.hth4.edit import (
    bind_button,
    delete_pose,
    mirror_motion,
    rename_motion,
    set_home,
    set_pose,
    set_trim,
)
from rcb4hv.hth4.keyframes import Keyframe, motion_from_keyframes
from rcb4hv.hth4.poses import Checks
from rcb4hv.hth4.session import EditSession
from rcb4hv.robot.builtin import load_builtin


@pytest.fixture(scope="module")
def project(kxr_project_path: Path) -> hth4.Project:
    return hth4.load_project(kxr_project_path)


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (lambda p: set_home(p, 10, 7500.5), "ICS 10: home position must be an int, not 7500.5"),
        (lambda p: set_home(p, 10, np.float64(7500.0)), "home position must be an int"),
        (lambda p: set_home(p, 10, "7500"), "home position must be an int, not '7500'"),
        (lambda p: rename_motion(p, 69, "bad\x01name"), "control characters (U+0001)"),
        (lambda p: rename_motion(p, 69, 123), "motion name must be a str, not int 123"),
        (lambda p: set_pose(p, 66, 1, {10: "7700"}), "ICS 10: position must be an int"),
        (lambda p: set_pose(p, 66, 1.0, {10: 7700}), "pose index must be an int, not 1.0"),
        (lambda p: delete_pose(p, 66, "1"), "pose index must be an int, not '1'"),
        (lambda p: set_trim(p, 10, 1.0), "ICS 10: trim must be an int, not 1.0"),
        (lambda p: bind_button(p, 69, 1, "Bogus"), "unknown CompareType 'Bogus'"),
        (lambda p: bind_button(p, 69, 1.5), "the button word must be an int, not 1.5"),
    ],
)
def test_a_value_the_file_cannot_hold_is_refused_at_the_edit(
    project: hth4.Project, edit: object, words: str
) -> None:
    with pytest.raises(EditError) as info:
        edit(project)  # type: ignore[operator]
    assert words in str(info.value)


def test_a_refused_edit_leaves_the_session_savable(tmp_path: Path, kxr_project_path: Path) -> None:
    """Was: set_home(7500.5) accepted, then every save raised a plain ValueError."""
    target = tmp_path / "p.h4p"
    target.write_bytes(kxr_project_path.read_bytes())
    session = EditSession.open(target)
    with pytest.raises(EditError):
        session.apply(set_home, 10, 7500.5)
    with pytest.raises(EditError):
        session.apply(rename_motion, 69, "a\x07b")
    session.apply(rename_motion, 69, "fine")
    session.save()
    assert hth4.load_project(target).motion(69).name == "fine"


def test_numpy_integers_are_ints(project: hth4.Project) -> None:
    """Was: "trim np.int64(5) outside -4000..4000", and set_pose refused int64 positions."""
    assert set_trim(project, 10, np.int64(5)).servo(10).trim == 5
    assert bind_button(project, 69, np.int64(1), force=True).motion(69).button_data == 1
    edited = set_pose(project, 66, np.int64(1), {np.int64(10): np.int64(7700)})
    assert edited != project
    assert type(set_home(project, 10, np.int32(7400)).servo(10).position) is int


def test_keyframes_refuse_floats_and_infinite_times() -> None:
    with pytest.raises(EditError, match="finite"):
        Keyframe(float("inf"), {2: 7500})
    float_position = r"keyframe 1: .*ICS 2: position must be an int, not 7500\.7"
    with pytest.raises(EditError, match=float_position):
        parse_keyframes([{"time": 1, "positions": {"2": 7500.7}}])
    with pytest.raises(EditError, match="keyframe 1: keyframe time must be a finite number"):
        parse_keyframes([{"time": float("inf"), "positions": {"2": 7500}}])
    with pytest.raises(EditError, match="keyframe 2: needs 'time' and 'positions'"):
        parse_keyframes([{"time": 1, "positions": {"2": 7500}}, {"time": 1}])
    assert Keyframe(1, {np.int64(2): np.int64(7500)}).positions == {2: 7500}


def test_motion_from_keyframes_checks_its_arguments() -> None:
    kf = [Keyframe(0.5, {2: 7500})]
    with pytest.raises(EditError, match="motion slot must be an int, not '1'"):
        motion_from_keyframes(kf, slot="1", name="m")  # type: ignore[arg-type]
    with pytest.raises(EditError, match="unknown CompareType 'Bogus'"):
        motion_from_keyframes(kf, slot=1, name="m", compare_type="Bogus")
    with pytest.raises(EditError, match="control characters"):
        motion_from_keyframes(kf, slot=1, name="a\x07b")


def test_project_lookups_are_typed_key_errors(project: hth4.Project) -> None:
    with pytest.raises(NotFoundError, match="no motion slot 999") as info:
        project.motion(999)
    assert isinstance(info.value, KeyError) and str(info.value).startswith("the project")
    with pytest.raises(NotFoundError, match="no servo configuration for ICS 99"):
        project.servo(99)


def test_mirror_refuses_a_model_that_does_not_fit_the_project(project: hth4.Project) -> None:
    """Was: khr3hv accepted, a wrong mirror returned; project_model refuses the same model."""
    with pytest.raises(NoRobotModelError, match="the project has no servo at index 0"):
        mirror_motion(project, 69, load_builtin("khr3hv"), to=73, name="M")
    with pytest.raises(NoRobotModelError, match="must be a RobotModel"):
        mirror_motion(project, 69, "kxr-l2", to=73)  # type: ignore[arg-type]
    with pytest.raises(RobotModelError, match="must be a RobotModel"):
        Checks("kxr-l2")  # type: ignore[arg-type]
    mirror_motion(project, 69, load_builtin("kxr-l2-gripper"), to=73, name="M")
