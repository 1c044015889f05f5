"""One rule picks a project's robot model for the CLI, physics, the editor and the dashboard."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import pytest

from rcb4hv import hth4
from rcb4hv.cli.project_physics import physics_robot
from rcb4hv.errors import NoRobotModelError, RobotModelError
from rcb4hv.hth4.robotpick import detect_project, project_model, servo_table
from rcb4hv.project.relocate import project_image
from rcb4hv.rom.default import DEFAULT_ICS
from rcb4hv.ui.robots import choose_robot


@pytest.fixture
def project(kxr_project_path: Path) -> hth4.Project:
    return hth4.load_project(kxr_project_path)


def test_detects_names_and_checks_the_project(project: hth4.Project) -> None:
    assert project_model(project).name == "kxr-l2-gripper"
    assert project_model(servo_table(project)).name == "kxr-l2-gripper"
    assert project_model(project, "kxr-l2").name == "kxr-l2"  # a subset of its servos
    with pytest.raises(RobotModelError, match=r"no servo at index 0 \(head_yaw\)"):
        project_model(project, "khr3hv")
    with pytest.raises(RobotModelError, match="unknown robot 'nao'"):
        project_model(project, "nao")
    assert project_model(None, "khr3hv").name == "khr3hv"  # nothing to check against


def test_nothing_matching_is_a_clear_error(project: hth4.Project) -> None:
    # one gripper only: the servo names still describe a KXR humanoid (a kit model)
    odd = replace(project, servos=tuple(s for s in project.servos if s.device_number != 19))
    assert project_model(odd).name == "kxr:L2L5A3G"
    # names that say nothing, and an index set no built-in model has
    mute = replace(
        odd, servos=tuple(replace(s, name=f"servo {s.device_number}") for s in odd.servos)
    )
    with pytest.raises(NoRobotModelError, match=r"matches this project's servos \[2, 3,") as e:
        project_model(mute)
    assert "--robot khr3hv|khr3hv-22|kxr-l2|kxr-l2-gripper|kxr:CODE|FILE" in str(e.value)
    with pytest.raises(NoRobotModelError, match="no project servo table"):
        project_model(None, indices=[2, 3])


def test_every_caller_uses_the_same_rule(project: hth4.Project) -> None:
    # the dashboard: detected from the project, else the board's servos
    model, why, _ = choose_robot(None, project, DEFAULT_ICS)
    assert (model.name, why) == ("kxr-l2-gripper", "detected from the project")
    odd = replace(project, servos=tuple(s for s in project.servos if s.device_number != 19))
    model, why, _ = choose_robot(None, odd, DEFAULT_ICS)  # the servo names describe a KXR kit
    assert (model.name, why) == ("kxr:L2L5A3G", "detected from the project")
    mute = replace(odd, servos=tuple(replace(s, name="") for s in odd.servos))
    model, why, _ = choose_robot(None, mute, DEFAULT_ICS)
    assert (model.name, why) == ("khr3hv-22", "matches the board's servos")
    # physics (`project simulate --physics`): a project, or a bare ROM image (no names)
    rom, _ = project_image(project, None)
    assert physics_robot(project, rom, None).name == "kxr-l2-gripper"
    with pytest.raises(NoRobotModelError, match="no project servo table"):
        physics_robot(None, rom, None)
    assert physics_robot(None, rom, "kxr-l2-gripper").name == "kxr-l2-gripper"


def test_the_editor_does_not_drive_a_project_with_a_named_model_it_cannot(
    project: hth4.Project,
) -> None:
    """`rcb4hv ui --robot khr3hv` and a KXR-L2 project: not the KHR-3HV but the detected
    model, with the reason in a note (the Editor had no model and asked for --robot)."""
    from rcb4hv.hth4 import dump_project
    from rcb4hv.robot.builtin import load_builtin
    from rcb4hv.ui.editor_state import Editor

    ed = Editor()
    ed.open(dump_project(project), None, load_builtin("khr3hv"))  # `rcb4hv ui --robot khr3hv`
    assert ed.model is not None and ed.model.name == "kxr-l2-gripper" and not ed.model_error
    assert "no servo at index 0 (head_yaw)" in ed.model_note
    ed.open(dump_project(project), None, load_builtin("kxr-l2"))
    assert ed.model is not None and ed.model.name == "kxr-l2" and not ed.model_error
    assert project_model(project, load_builtin("kxr-l2")) is load_builtin("kxr-l2")


def test_a_kit_code_the_names_contradict_is_said(
    project: hth4.Project, caplog: pytest.LogCaptureFixture
) -> None:
    # the fixture's servo names have no hip yaw: --robot kxr:L2L6A3G (six-axis legs) builds
    # the five-axis legs they name, and says so instead of answering another model in silence
    with caplog.at_level("INFO", logger="rcb4hv.hth4.robotpick"):
        model = project_model(project, "kxr:L2L6A3G")
    assert model.name == "kxr:L2L5A3G"
    (record,) = caplog.records
    assert record.levelname == "WARNING"
    assert record.message == (
        "--robot kxr:L2L6A3G: the project's servo names make it kxr:L2L5A3G "
        "(--robot kxr:L2L6A3G says legs 6, the servo names 5: names win)"
    )
    _, det = detect_project(project, "kxr:L2L6A3G")  # the same evidence, as data
    assert det is not None
    assert det.conflicts == ("--robot kxr:L2L6A3G says legs 6, the servo names 5: names win",)
    assert det.as_dict()["conflicts"] == list(det.conflicts)
    assert set(det.conflicts) <= set(det.notes)
    _, det = detect_project(project, "kxr:L2L5A3")
    assert det is not None and det.conflicts == ()
    # a code the names only complete (the grippers it does not spell) is said, quietly
    caplog.clear()
    with caplog.at_level("INFO", logger="rcb4hv.hth4.robotpick"):
        assert project_model(project, "kxr:L2L5A3").name == "kxr:L2L5A3G"
    (record,) = caplog.records
    assert record.levelname == "INFO" and record.message.endswith("(the names complete the code)")
    caplog.clear()
    with caplog.at_level("INFO", logger="rcb4hv.hth4.robotpick"):
        assert project_model(project, "kxr:L2L5A3G").name == "kxr:L2L5A3G"
    assert not caplog.records  # the code it asked for: nothing to say
