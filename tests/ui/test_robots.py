"""Which robot model the dashboard draws: --robot, the open project, the board, the default."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.errors import RobotModelError
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.rom.default import DEFAULT_ICS
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
    model, why = choose_robot("kxr-l2", project, DEFAULT_ICS)
    assert model.name == "kxr-l2" and why == "--robot kxr-l2"
    model, why = choose_robot(None, project, DEFAULT_ICS)
    assert model.name == "kxr-l2-gripper" and why == "detected from the project"
    model, why = choose_robot(None, None, DEFAULT_ICS)
    assert model.name == "khr3hv-22" and why == "matches the board's servos"
    model, why = choose_robot(None, None, [])
    assert model.name == DEFAULT_ROBOT and why == "default"
    with pytest.raises(RobotModelError, match="unknown robot 'nao'"):
        choose_robot("nao", None, [])


def test_ui_refuses_an_unknown_robot_before_serving() -> None:
    result = CliRunner().invoke(cli, ["ui", "--robot", "nao", "--bind", "127.0.0.1:0"])
    assert result.exit_code == 2
    assert "unknown robot 'nao'" in result.output and "khr3hv" in result.output
