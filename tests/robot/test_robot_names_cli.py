"""Robot names as a user types them: an unknown one is answered with every form the commands
take (built-in names, KXR kit codes, URDF files); a built-in name in capitals is the same robot."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.errors import RobotModelError
from rcb4hv.robot.builtin import BUILTIN, load_builtin, load_robot


@pytest.mark.parametrize("name", ["KHR-3HV", "nao", "kxr_l2"])
def test_an_unknown_robot_names_the_kit_code_form(name: str) -> None:
    r = CliRunner().invoke(cli, ["robot", "show", name])
    assert r.exit_code == 1
    (line,) = r.output.strip().splitlines()
    assert line.startswith(f"error: unknown robot {name!r}: choose one of {', '.join(BUILTIN)}")
    assert "kxr:CODE" in line and "kxr:L2L5A3" in line and "URDF" in line


@pytest.mark.parametrize(("typed", "name"), [("KHR3HV", "khr3hv"), ("KXR-L2", "kxr-l2")])
def test_built_in_names_in_any_case(typed: str, name: str) -> None:
    assert load_robot(typed).name == load_builtin(name).name == name
    r = CliRunner().invoke(cli, ["robot", "show", typed])
    assert r.exit_code == 0, r.output


def test_the_named_kit_code_loads() -> None:
    assert load_robot("kxr:L2L5A3").indices == load_builtin("kxr-l2").indices
    with pytest.raises(RobotModelError, match="kxr:CODE"):
        load_builtin("khr4")
