"""Which robot model the dashboard draws: --robot, the open project, the board, the default."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.errors import RobotModelError
from rcb4hv.hth4 import Project
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.rom.default import DEFAULT_ICS
from rcb4hv.ui.context import UiContext
from rcb4hv.ui.robots import DEFAULT_ROBOT, board_robot, choose_robot


def test_the_default_board_is_a_22_axis_khr3hv() -> None:
    # head, shoulder pitch/roll, upper-arm yaw, hip yaw..ankle pitch: only Ver.2 has them all
    assert board_robot(DEFAULT_ICS) == "khr3hv-22"
    assert board_robot(load_builtin("khr3hv").indices) == "khr3hv"  # the tightest fit wins
    assert board_robot(load_builtin("kxr-l2").indices) == "kxr-l2"
    assert board_robot([2, 3]) == "kxr-l2"  # all have them; the KXR-L2 has fewest to spare
    assert board_robot([]) is None and board_robot([40]) is None


def test_the_choice_order(kxr_project_path: Path) -> None:
    from rcb4hv.hth4 import load_project

    project = load_project(kxr_project_path)
    model, why, _ = choose_robot("kxr-l2", project, DEFAULT_ICS)
    assert model.name == "kxr-l2" and why == "--robot kxr-l2"
    model, why, _ = choose_robot(None, project, DEFAULT_ICS)
    assert model.name == "kxr-l2-gripper" and why == "detected from the project"
    model, why, _ = choose_robot(None, None, DEFAULT_ICS)
    assert model.name == "khr3hv-22" and why == "matches the board's servos"
    model, why, _ = choose_robot(None, None, [])
    assert model.name == DEFAULT_ROBOT and why == "default"
    with pytest.raises(RobotModelError, match="unknown robot 'nao'"):
        choose_robot("nao", None, [])


def test_ui_refuses_an_unknown_robot_before_serving() -> None:
    result = CliRunner().invoke(cli, ["ui", "--robot", "nao", "--bind", "127.0.0.1:0"])
    assert result.exit_code == 2
    assert "unknown robot 'nao'" in result.output and "khr3hv" in result.output


def _ambiguous_turtle() -> Project:
    """A KXR-L4T project without its head and a title with no kit code: its servo names fit
    the KXR-L4T and the KXR-L4N (tests/robot/test_kit.py), so detection must ask."""
    from rcb4hv.hth4.newproject import new_project
    from tests.robot.kit_names import names_for, stock

    _, l4t = stock("kxr:L4T")
    names = {i: n for i, n in names_for(l4t).items() if "首" not in n}
    project = new_project(l4t, title="my turtle")
    servos = tuple(
        replace(s, name=names[s.device_number])
        if s.device_number in names
        else replace(s, mode="None")
        for s in project.servos
    )
    return replace(project, servos=servos)


def test_an_ambiguous_project_is_not_played_on_a_model_nobody_picked() -> None:
    """The dashboard's model for an ambiguous project: the board's fallback with the
    candidates kept (the Project page refuses to play on it); picking one on the Editor page
    makes it every page's model, and opening another project forgets the pick."""
    ctx = UiContext(SimpleNamespace(state=SimpleNamespace(servos=[])), auto_robot=True)  # type: ignore[arg-type]
    ctx.set_project(_ambiguous_turtle(), "turtle.h4p")
    assert set(ctx.robot_candidates) == {"kxr:L4T", "kxr:L4N"}
    assert "pick one on the Editor page" in ctx.robot_source
    heard: list[str] = []
    ctx.on_project(lambda: heard.append(ctx.robot_source))
    with pytest.raises(RobotModelError, match="not one of the models"):
        ctx.pick_robot("khr3hv")
    ctx.pick_robot("kxr:L4N")
    assert ctx.robot is not None and ctx.robot.name == "kxr:L4N"
    assert ctx.robot_candidates == () and heard == ["picked for the project: kxr:L4N"]
    ctx.set_project(_ambiguous_turtle(), "again.h4p")
    assert ctx.robot_candidates and ctx.robot is not None and ctx.robot.name != "kxr:L4N"


def test_opening_a_project_detects_its_robot_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """The model and the candidates come from one detection (they were two, each detecting
    the project again)."""
    from rcb4hv.ui import robots

    calls: list[object] = []
    real = robots.project_model

    def counted(*args: Any, **kwargs: Any) -> Any:
        calls.append(args[0])
        return real(*args, **kwargs)

    monkeypatch.setattr(robots, "project_model", counted)
    ctx = UiContext(SimpleNamespace(state=SimpleNamespace(servos=[])), auto_robot=True)  # type: ignore[arg-type]
    ctx.set_project(_ambiguous_turtle(), "turtle.h4p")
    assert set(ctx.robot_candidates) == {"kxr:L4T", "kxr:L4N"} and len(calls) == 1


def test_a_robot_named_for_the_dashboard_yields_to_a_project_it_does_not_fit(
    kxr_project_path: Path,
) -> None:
    """`rcb4hv ui --robot khr3hv` and a KXR-L2 project: every page, not the Editor alone, uses
    the detected model and says why (the Project page kept the KHR-3HV); a project it fits
    keeps it."""
    from rcb4hv.hth4 import load_project

    ctx = UiContext(SimpleNamespace(state=SimpleNamespace(servos=[])))  # type: ignore[arg-type]
    ctx.choose_robot("khr3hv")
    assert ctx.robot is not None and ctx.robot.name == "khr3hv"
    ctx.set_project(load_project(kxr_project_path), "kxr.h4p")
    assert ctx.robot is not None and ctx.robot.name == "kxr-l2-gripper"
    assert ctx.robot_source.startswith("detected from the project; --robot khr3hv does not fit")
    ctx.set_project(None)
    assert ctx.robot.name == "khr3hv" and ctx.robot_source == "--robot khr3hv"
