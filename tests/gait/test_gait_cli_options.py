"""`rcb4hv gait` refuses the options a walk would ignore (a tester's `--direction back --turn
45` reported "turn_deg": 45 for a walk that does not turn; `--slot`, `--button`, `--name`
without `--into` went nowhere in silence), and its JSON says which figure applies."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli

BASE = ["gait", "--robot", "kxr-l2", "--steps", "2"]


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--direction", "back", "--turn", "45"], "a back walk does not turn"),
        (["--direction", "turn-left", "--stride", "0.02"], "turn-left turns on the spot"),
        (["--play", "--slot", "3", "--name", "zzz"], "--slot, --name: the motion is stored"),
        (["--play", "--button", "CIRCLE"], "--button: the motion is stored only with --into"),
    ],
)
def test_an_option_the_walk_would_ignore_is_a_usage_error(args: list[str], words: str) -> None:
    r = CliRunner().invoke(cli, [*BASE, *args])
    assert r.exit_code == 2 and words in r.output, r.output


def test_the_json_names_the_figure_that_applies(tmp_path: Path) -> None:
    into = tmp_path / "w.h4p"
    r = CliRunner().invoke(cli, [*BASE, "--direction", "back", "--into", str(into), "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.output)
    assert out["turn_deg"] is None and out["stride_m"] > 0 and out["commanded_unit"] == "m"
    turn = ["gait", "--robot", "kxr:L2W2L6A4H2", "--steps", "2", "--direction", "turn-left"]
    r = CliRunner().invoke(cli, [*turn, "--into", str(tmp_path / "t.h4p"), "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.output)
    assert out["stride_m"] is None and out["turn_deg"] > 0 and out["commanded_unit"] == "deg"
