"""``project new`` for every built-in model builds, checks clean and stands in physics;
``project bind`` and ``project settings`` edit what they say and nothing else."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.cli.project_common import load_image
from rcb4hv.errors import EditError
from rcb4hv.hth4 import dump_project, load_project, parse_project
from rcb4hv.hth4.blocks import motion_program
from rcb4hv.hth4.diff import diff_projects
from rcb4hv.hth4.newproject import HOME_NAME, new_project, set_priority
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.project.check import check_project
from rcb4hv.project.run import run_motions
from rcb4hv.protocol.memory import Button
from rcb4hv.protocol.memory.map import SystemRegister
from rcb4hv.robot.builtin import BUILTIN, load_builtin


def _run(*args: object) -> tuple[int, str]:
    r = CliRunner().invoke(cli, [str(a) for a in args])
    return r.exit_code, r.output


@pytest.fixture(scope="module", params=BUILTIN)
def made(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("new") / f"{request.param}.h4p"
    code, out = _run("project", "new", "--robot", request.param, "-o", path)
    assert code == 0, out
    return path


def test_new_project_holds_the_model(made: Path) -> None:
    project = load_project(made)
    model = load_builtin(made.stem)
    assert project_model(project, None).name == model.name  # detected back from its servos
    used = [s for s in project.servos if s.in_use]
    assert sorted(s.device_number for s in used) == list(model.indices)
    assert all(s.trim == 0 for s in project.servos)
    home = project.motion(1)
    assert home.name == HOME_NAME and project.startup_motion == home
    blocks = motion_program(project, 1).blocks
    assert [b.kind for b in blocks] == ["pose", "end"]
    assert blocks[0].fields["positions"] == {str(s.device_number): s.position for s in used}
    assert dump_project(parse_project(made.read_bytes())) == made.read_bytes()


def test_new_project_checks_clean_and_stands(made: Path) -> None:
    assert [f for f in check_project(load_project(made)) if f.severity == "error"] == []
    image, layout, names = load_image(made)
    run = run_motions(image, [1], names=names, motion_layout=layout, robot=load_builtin(made.stem))
    (motion,) = run.motions
    assert motion.result.status == "completed"
    assert not motion.outcome.fell and motion.outcome.end_pose == "upright"
    assert motion.outcome.max_tilt_deg < 5.0


def test_new_project_does_not_overwrite(tmp_path: Path) -> None:
    path = tmp_path / "x.h4p"
    path.write_bytes(b"keep")
    code, out = _run("project", "new", "--robot", "kxr-l2", "-o", path)
    assert code == 1 and "exists" in out
    assert path.read_bytes() == b"keep"


def test_bind_and_settings_change_only_what_they_say(tmp_path: Path) -> None:
    base = tmp_path / "base.h4p"
    base.write_bytes(dump_project(new_project(load_builtin("kxr-l2"), date="2026-01-01T00:00:00")))
    bound = tmp_path / "bound.h4p"
    assert _run("project", "bind", base, "--motion", 1, "--button", "UP,S1", "-o", bound)[0] == 0
    assert load_project(bound).motion(1).button_data == Button.UP | Button.S1
    assert len(diff_projects(load_project(base), load_project(bound))) == 1
    out = tmp_path / "set.h4p"
    code, text = _run(
        "project", "settings", bound, "--low-power", 1, "--low-power-value", 300,
        "--mixing", "14.1=AD1*8", "--ad-reference", "1=273", "--startup", 0, "-o", out,
    )  # fmt: skip
    assert code == 0, text
    p = load_project(out)
    assert p.startup_motion_address == -1
    assert (p.low_power_motion_address, p.low_power_value) == (p.motion(1).address, 300)
    assert (p.servo(14).mixing1_address, p.servo(14).mixing1_rate) == (0x0024, 8)
    assert p.adc_reference_words[1] == 273
    code, text = _run(
        "project", "settings", out, "--ad-reference", "11=5", "-o", tmp_path / "y.h4p"
    )
    assert code == 1 and "AD channel 11" in text


def test_settings_refuse_a_check_that_cannot_build_or_never_fires(tmp_path: Path) -> None:
    """A priority check on a port the board has not (AD99) was written, and the build then
    refused the project; a low-power motion with no value compared AD0 <= 0, never true.
    Both are refused when set, and the file is not written."""
    base = tmp_path / "base.h4p"
    base.write_bytes(dump_project(new_project(load_builtin("kxr-l2"), date="2026-01-01T00:00:00")))
    out = tmp_path / "out.h4p"
    code, text = _run("project", "settings", base, "--priority", "0=1,AD99,Equals,2", "-o", out)
    assert code == 2 and "unknown priority-motion port 'AD99'" in text, text
    with pytest.raises(EditError, match="unknown priority-motion port 'AD99'"):
        set_priority(load_project(base), 0, 1, "AD99", "Equals", 2)
    with pytest.raises(EditError, match="unknown comparison 'Same'"):
        set_priority(load_project(base), 0, 1, "AD3", "Same", 2)
    code, text = _run("project", "settings", base, "--low-power", 1, "-o", out)
    assert code == 1 and "would never run" in text, text
    # a channel the board has not: said so (it was "not ICS.N=SOURCE*RATE")
    code, text = _run("project", "settings", base, "--mixing", "14.1=AD11*8", "-o", out)
    assert code == 2 and "the board has AD0-AD10" in text, text
    assert not out.exists()
    code, text = _run("project", "settings", base, "--priority", "0=1,ad3,LessThan,2", "-o", out)
    assert code == 0, text


@pytest.mark.parametrize("ms", [10, 15, 20, 25])
def test_settings_period_sets_the_output_period_and_motions_play_at_its_pace(
    tmp_path: Path, ms: int
) -> None:
    base = tmp_path / "base.h4p"
    base.write_bytes(dump_project(new_project(load_builtin("kxr-l2"), date="2026-01-01T00:00:00")))
    out = tmp_path / f"{ms}.h4p"
    code, text = _run("project", "settings", base, "--period", ms, "-o", out)
    assert code == 0, text
    before, after = load_project(base), load_project(out)
    word = after.system_register
    assert word & 0x30 == [10, 15, 20, 25].index(ms) << 4
    assert word & ~0x30 == before.system_register & ~0x30  # nothing else in the register
    assert [c.field for c in diff_projects(before, after)] in ([], ["config"])
    image, layout, _ = load_image(out)
    run = run_motions(image, [1], motion_layout=layout, hold=0)
    # slot 1 moves to the home pose in HOME_FRAMES output periods
    assert run.motions[0].result.duration == pytest.approx(30 * ms / 1000, abs=2 * ms / 1000)


def test_messages_name_the_stub_and_count_servos_once(tmp_path: Path) -> None:
    """`project new` printed "(16 servos)" twice (the title has it); `project info` called
    the start-up stub 3CB80h, HeartToHeart4's "no start-up motion" (nine of Kondo's samples
    have it), "not the start of a motion slot"."""
    from dataclasses import replace

    from rcb4hv.cli.project_check_cmd import settings_lines

    out = tmp_path / "n.h4p"
    code, text = _run("project", "new", "--robot", "kxr-l2", "-o", out)
    assert code == 0 and text.count("16 servos") == 1, text
    project = replace(load_project(out), startup_motion_address=0x3CB80)
    assert settings_lines(project)[0] == (
        "startup motion: 3CB80h (the start-up stub, a RETURN: no motion)"
    )


def test_diff_says_what_a_settings_change_means(tmp_path: Path) -> None:
    """`project diff` printed the output period as the Config bytes (1B 82 -> 2B 82) and an
    AD reference as 38 bytes of which one changed; it names the period and the channel."""
    base = tmp_path / "base.h4p"
    base.write_bytes(dump_project(new_project(load_builtin("kxr-l2"), date="2026-01-01T00:00:00")))
    out = tmp_path / "out.h4p"
    code, text = _run(
        "project", "settings", base, "--period", 20, "--ad-reference", "3=100", "-o", out
    )  # fmt: skip
    assert code == 0, text
    before = load_project(base)
    was = SystemRegister.from_word(before.system_register).frame_period_ms
    changes = {c.field: c.text for c in diff_projects(before, load_project(out))}
    assert f"(frame_period_ms {was} -> 20)" in changes["config"]
    assert changes["adc_reference"].endswith(f"AD3 {before.adc_reference_words[3]} -> 100")
