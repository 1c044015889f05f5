"""``rcb4hv trim save`` against another robot's board: a typed EditError, and --force stores
only the trims of the servos both use (the project's unused ICS 0 keeps its entry)."""

from __future__ import annotations

import shutil
from pathlib import Path

from click.testing import CliRunner

from rcb4hv import hth4
from rcb4hv.cli.main import cli


def test_trim_save_force_stores_only_the_servos_both_use(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """The default emulated board has 17 servos, ICS 0 (a head) among them; the KXR project
    leaves ICS 0 unused. Was: ValueError, and --force wrote the head's trim into ICS 0 and
    said "trims of 17 servos stored"."""
    target = tmp_path / "hac.h4p"
    shutil.copyfile(kxr_project_path, target)
    before = target.read_bytes()
    r = CliRunner().invoke(cli, ["trim", "save", str(target), "--port", "rcb4emu://"])
    assert r.exit_code == 1 and "(EditError)" in r.output
    assert "ICS only on the board: [0]" in r.output
    assert target.read_bytes() == before
    r = CliRunner().invoke(cli, ["trim", "save", str(target), "--force", "--port", "rcb4emu://"])
    assert r.exit_code == 0, r.output
    assert "trims of 16 servos stored (1 of the board's not in the project: left out)" in r.output
    old, new = hth4.load_project(kxr_project_path), hth4.load_project(target)
    assert new.servo(0) == old.servo(0)
