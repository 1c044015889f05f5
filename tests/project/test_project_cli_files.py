"""What the ``rcb4hv project`` commands make of the files they are given: a project or a ROM
image told apart by content (not by name), errors that name the file, an empty motion slot,
an output path in a missing folder, and no progress bar on a stderr that is no terminal."""

from __future__ import annotations

import io
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner, Result

from rcb4hv.cli import _output
from rcb4hv.cli.main import cli
from rcb4hv.rom import layout

EMPTY_SLOT = 18  # a slot the fixture project leaves empty


def _error(r: Result, code: int = 1) -> str:
    """The one ``error: ...`` line of a failed command."""
    assert r.exit_code == code, r.output
    assert isinstance(r.exception, SystemExit), r.exception
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), r.output
    return lines[0]


def _run(*args: str | Path) -> Result:
    return CliRunner().invoke(cli, [str(a) for a in args])


@pytest.fixture(scope="module")
def image_file(kxr_project_path: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("image") / "kxr.bin"
    r = _run("project", "build", kxr_project_path, "-o", out)
    assert r.exit_code == 0, r.output
    return out


@pytest.fixture
def unnamed_project(kxr_project_path: Path, tmp_path: Path) -> Path:
    """The fixture project under a name without ``.h4p``."""
    path = tmp_path / "project-copy"
    shutil.copyfile(kxr_project_path, path)
    return path


# ------------------------------------------------------------ simulate: content, empty slots


def test_simulate_takes_a_project_without_the_h4p_extension(unnamed_project: Path) -> None:
    r = _run("project", "simulate", unnamed_project, "--motion", "39")
    assert r.exit_code == 0, r.output
    assert "1 motions: 1 completed" in r.output


@pytest.mark.parametrize(
    ("content", "why"),
    [(b"", "no element found"), (b"hello\n", "syntax error"), (b"\x00" * 100, "invalid token")],
)
def test_simulate_of_neither_a_project_nor_an_image(
    content: bytes, why: str, tmp_path: Path
) -> None:
    bad = tmp_path / "thing.h4p"
    bad.write_bytes(content)
    line = _error(_run("project", "simulate", bad))
    assert str(bad) in line and why in line
    assert "not a HeartToHeart4 project" in line
    assert f"nor a {layout.ROM_SIZE}-byte ROM image ({len(content)} bytes)" in line


def test_simulate_of_an_empty_slot_fails_as_poses_does(kxr_project_path: Path) -> None:
    sim = _error(_run("project", "simulate", kxr_project_path, "--motion", EMPTY_SLOT))
    poses = _error(_run("project", "poses", kxr_project_path, "--motion", EMPTY_SLOT))
    assert sim == poses == f"error: motion slot {EMPTY_SLOT} is empty (EditError)"
    assert "ROMERR" not in sim


def test_simulate_checks_every_slot_before_playing(kxr_project_path: Path) -> None:
    r = _run("project", "simulate", kxr_project_path, "--motion", "39", "--motion", EMPTY_SLOT)
    assert _error(r) == f"error: motion slot {EMPTY_SLOT} is empty (EditError)"


# ------------------------------------------------------------------- image: sizes first


def test_image_of_a_project_says_what_to_use(kxr_project_path: Path) -> None:
    size = kxr_project_path.stat().st_size
    for extra in ([], ["--layout", "2.2"]):
        line = _error(_run("project", "image", kxr_project_path, *extra))
        assert f"not a 256 KB ROM image ({size} bytes)" in line
        assert "HeartToHeart4 project" in line and "project info" in line
        assert "project build" in line and "--layout" not in line


@pytest.mark.parametrize("content", [b"", b"hello\n", b"<Rcb4>"])
def test_image_of_a_small_file(content: bytes, tmp_path: Path) -> None:
    bad = tmp_path / "x.bin"
    bad.write_bytes(content)
    line = _error(_run("project", "image", bad))
    assert line == f"error: {bad}: not a 256 KB ROM image ({len(content)} bytes) (ValueError)"


def test_image_layout_help_speaks_of_images_only() -> None:
    r = _run("project", "image", "--help")
    assert r.exit_code == 0
    assert "project is moved" not in r.output


def test_image_still_reads_an_image(image_file: Path) -> None:
    r = _run("project", "image", image_file)
    assert r.exit_code == 0, r.output
    assert "65 motions" in r.output


def test_info_and_image_count_a_motions_bytes_alike(
    kxr_project_path: Path, image_file: Path
) -> None:
    """One answer to "how many bytes is this motion": the frames, not HeartToHeart4's FF end
    marker after them (``project info`` counted it, ``project image`` cannot see it)."""
    import json

    info = json.loads(_run("project", "info", kxr_project_path, "--json").output)
    image = json.loads(_run("project", "image", image_file, "--json").output)
    sizes = {m["slot"]: m["bytes"] for m in info["motions"]}
    assert sizes == {m["slot"]: m["bytes"] for m in image["motions"]}
    assert sizes[1] == 591  # XL2G_101: 592 bytes in the project with its end marker


# --------------------------------------------------------------- errors name the file


def test_diff_names_the_bad_file(kxr_project_path: Path, tmp_path: Path) -> None:
    bad = tmp_path / "bad.h4p"
    bad.write_text("<Rcb4><Config>", encoding="utf-8")
    for args in ([kxr_project_path, bad], [bad, kxr_project_path]):
        # exit status 2, as diff(1): 1 says the projects differ
        line = _error(_run("project", "diff", *args), 2)
        assert line.startswith(f"error: {bad}: not a HeartToHeart4 project: not well-formed"), line


@pytest.mark.parametrize("command", ["info", "diff", "build", "check", "poses", "mirror"])
def test_project_commands_name_a_rom_image(command: str, image_file: Path, tmp_path: Path) -> None:
    args: list[str | Path] = ["project", command, image_file]
    if command == "diff":
        args.append(image_file)
    if command in ("poses", "mirror"):
        args += ["--motion", "1"]
    if command in ("build", "mirror"):
        args += ["-o", tmp_path / "out"]
    line = _error(_run(*args), 2 if command == "diff" else 1)
    assert line.startswith(f"error: {image_file}: looks like a 256 KB ROM image"), line
    assert "project image" in line


def test_project_commands_take_a_project_by_content(unnamed_project: Path) -> None:
    for args in (["info"], ["poses", "--motion", "39"], ["check"]):
        r = _run("project", args[0], unnamed_project, *args[1:])
        assert r.exit_code in (0, 1) and not r.output.startswith("error:"), r.output


@pytest.mark.parametrize("command", ["build", "mirror"])
def test_output_in_a_missing_folder_names_the_users_path(
    command: str, kxr_project_path: Path, tmp_path: Path
) -> None:
    out = tmp_path / "no" / "such" / "m.bin"
    extra = ["--motion", "39"] if command == "mirror" else []
    line = _error(_run("project", command, kxr_project_path, *extra, "-o", out))
    assert f"cannot write {out}: no directory {out.parent}" in line
    assert ".tmp" not in line


# ------------------------------------------------------------------ progress on no TTY


class _Tty(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize(("stream", "drawn"), [(io.StringIO, False), (_Tty, True)])
def test_progress_bar_only_on_a_terminal(
    stream: type[io.StringIO], drawn: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    err = stream()
    monkeypatch.setattr("sys.stderr", err)
    with _output.progress(100, "write", None) as update:
        update(100, 100)
    assert ("write: 100%" in err.getvalue()) is drawn


def test_progress_flag_forces_the_bar(monkeypatch: pytest.MonkeyPatch) -> None:
    err = io.StringIO()
    monkeypatch.setattr("sys.stderr", err)
    with _output.progress(100, "write", True) as update:
        update(100, 100)
    assert "write: 100%" in err.getvalue()


def test_upload_draws_no_bar_when_stderr_is_no_terminal(image_file: Path, tmp_path: Path) -> None:
    rom = tmp_path / "board.bin"
    shutil.copyfile(image_file, rom)  # the board holds the image: nothing to write
    r = _run(
        "project", "upload", image_file, "--port", f"rcb4emu://?rom={rom}", "--only-changed",
        "--no-verify", "--no-restart",
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert r.output == "wrote 0 of 2048 pages (0 bytes)\n"


@pytest.mark.parametrize("option", ["--trace", "--plot"])
def test_simulate_does_not_write_its_output_over_the_project(
    kxr_project_path: Path, tmp_path: Path, option: str
) -> None:
    """--trace or --plot naming the project simulated wrote over it; refused before the run,
    as is a plot file matplotlib cannot write (it failed after the whole simulation)."""
    copy = tmp_path / "kxr.h4p"
    shutil.copyfile(kxr_project_path, copy)
    before = copy.read_bytes()
    r = _run("project", "simulate", copy, "--physics", "--motion", "39", option, copy)
    assert r.exit_code == 2 and "is the file simulated" in r.output, r.output
    assert copy.read_bytes() == before
    r = _run("project", "simulate", copy, "--motion", "39", "--plot", tmp_path / "out.txt")
    assert r.exit_code == 2 and "a picture" in r.output, r.output
