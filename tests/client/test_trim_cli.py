"""``rcb4hv trim`` against the in-process emulator: a negative trim as written."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from rcb4hv.cli.main import cli


def test_trim_set_takes_a_negative_value_as_written() -> None:
    """`trim set 2 -240` failed with "No such option '-2'" (click read the value as an
    option); Kondo's trims are as often negative (-1350, -2700) as not."""
    r = CliRunner().invoke(cli, ["trim", "set", "2", "-240", "--port", "rcb4emu://"])
    assert r.exit_code == 0, r.output
    assert "ICS 2: trim 0 -> -240" in r.output
    r = CliRunner().invoke(cli, ["trim", "set", "2", "-9999", "--port", "rcb4emu://"])
    assert r.exit_code == 1 and "trim -9999 outside" in r.output
    r = CliRunner().invoke(cli, ["trim", "set", "2", "-240", "--bogus", "--port", "rcb4emu://"])
    assert r.exit_code != 0


def _fixture_board_and_new_project(fixture: Path, tmp_path: Path, robot: str) -> tuple[str, Path]:
    """A board running the fixture's image (its port) and a new project for ``robot``."""
    image = tmp_path / "fx.bin"
    r = CliRunner().invoke(cli, ["project", "build", str(fixture), "-o", str(image)])
    assert r.exit_code == 0, r.output
    other = tmp_path / f"{robot}.h4p"
    r = CliRunner().invoke(cli, ["project", "new", "--robot", robot, "-o", str(other)])
    assert r.exit_code == 0, r.output
    return f"rcb4emu://?rom={image}", other


def test_trim_save_refuses_another_robots_board(kxr_project_path: Path, tmp_path: Path) -> None:
    """The board runs the fixture's image (ICS 2-19); a KXR-L2 project without grippers
    (ICS 2-17) took its trims with no word. Refused and the file left alone; --force stores
    those of the servos both have; the fixture itself takes them."""
    port, other = _fixture_board_and_new_project(kxr_project_path, tmp_path, "kxr-l2")
    before = other.read_bytes()
    r = CliRunner().invoke(cli, ["trim", "save", str(other), "--port", port])
    assert r.exit_code == 1 and "ICS only on the board: [18, 19]" in r.output, r.output
    assert other.read_bytes() == before
    r = CliRunner().invoke(cli, ["trim", "save", str(other), "--force", "--port", port])
    assert r.exit_code == 0, r.output
    out = tmp_path / "fx.h4p"
    r = CliRunner().invoke(
        cli, ["trim", "save", str(kxr_project_path), "-o", str(out), "--port", port]
    )
    assert r.exit_code == 0 and "trims of 18 servos stored" in r.output, r.output


def test_trim_save_refuses_a_board_that_holds_none_of_the_projects_motions(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """Another robot with the same ICS numbers (a tester's KXR-L6 board, ICS 2-19 as the
    fixture's humanoid) passed the ICS check, and its trims replaced the project's in silence.
    The board's ROM must hold one of the project's motions as uploaded; each change is listed."""
    port, other = _fixture_board_and_new_project(kxr_project_path, tmp_path, "kxr-l2-gripper")
    before = other.read_bytes()
    r = CliRunner().invoke(cli, ["trim", "save", str(other), "--port", port])
    assert r.exit_code == 1 and "holds none of kxr-l2-gripper.h4p's motions" in r.output, r.output
    assert other.read_bytes() == before
    r = CliRunner().invoke(cli, ["trim", "save", str(other), "--force", "--port", port])
    assert r.exit_code == 0 and "  ICS 2: trim 0 -> " in r.output, r.output
