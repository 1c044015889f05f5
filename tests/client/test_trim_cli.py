"""``rcb4hv trim`` against the in-process emulator: a negative trim as written."""

from __future__ import annotations

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
