"""``project motion-export`` / ``motion-import`` / ``motion-xml`` on the fixture: every motion
goes out and back unchanged (``project diff`` exits 0), and hand edits land where they say."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.hth4 import load_project
from rcb4hv.hth4.blocks import motion_program
from rcb4hv.protocol import decode_command

TURN_LEFT = 69


def _run(*args: object) -> tuple[int, str]:
    r = CliRunner().invoke(cli, [str(a) for a in args])
    return r.exit_code, r.output


def test_export_all_import_all_changes_nothing(kxr_project_path: Path, tmp_path: Path) -> None:
    code, out = _run("project", "motion-export", kxr_project_path, "--all", "-o", tmp_path / "p")
    assert code == 0, out
    files = sorted((tmp_path / "p").iterdir())
    assert len(files) == len(load_project(kxr_project_path).used_motions) == 65
    assert files[0].name == "001.json"
    result = tmp_path / "out.h4p"
    code, out = _run(
        "project", "motion-import", kxr_project_path, tmp_path / "p", "--all", "-o", result
    )
    assert code == 0, out
    assert "65 motion(s) imported, 0 changed" in out
    assert _run("project", "diff", kxr_project_path, result)[0] == 0
    assert result.read_bytes() == kxr_project_path.read_bytes()


def test_every_motion_through_xml_changes_nothing(kxr_project_path: Path, tmp_path: Path) -> None:
    for m in load_project(kxr_project_path).used_motions:
        xml = tmp_path / f"{m.slot:03d}.xml"
        assert (
            _run("project", "motion-xml", kxr_project_path, "--motion", m.slot, "-o", xml)[0] == 0
        )
    result = tmp_path / "out.h4p"
    code, out = _run("project", "motion-import", kxr_project_path, tmp_path, "--all", "-o", result)
    assert code == 0, out
    assert _run("project", "diff", kxr_project_path, result)[0] == 0


def test_a_hand_edit_moves_the_branches_with_it(kxr_project_path: Path, tmp_path: Path) -> None:
    program = tmp_path / "turn.json"
    code, _ = _run(
        "project", "motion-export", kxr_project_path, "--motion", TURN_LEFT, "-o", program
    )
    assert code == 0
    obj = json.loads(program.read_text(encoding="utf-8"))
    # a wait before the button test: every later block moves 25 bytes, the loop still closes
    at = next(i for i, b in enumerate(obj["blocks"]) if b["kind"] == "button_branch")
    obj["blocks"].insert(at, {"kind": "wait", "timer": 1, "ms": 300})
    program.write_text(json.dumps(obj), encoding="utf-8")
    result = tmp_path / "out.h4p"
    code, out = _run(
        "project", "motion-import", kxr_project_path, program, "--motion", 70, "-o", result
    )
    assert code == 0 and "1 motion(s) imported, 1 changed" in out, out
    code, out = _run("project", "diff", kxr_project_path, result)
    assert code == 1 and "70" in out
    project = load_project(result)
    blocks = [b.to_json() for b in motion_program(project, 70).blocks]
    assert {"kind": "wait", "timer": 1, "ms": 300} in blocks
    branch = next(b for b in blocks if b["kind"] == "button_branch")
    assert branch["to"] == "L1" and blocks[0]["label"] == "L1"
    jump = decode_command(project.motion(70).frames[at + 4])
    assert getattr(jump, "address", None) == project.motion(70).address  # relocated to slot 70


def test_an_empty_program_empties_the_slot_and_says_so(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    program = tmp_path / "empty.json"
    program.write_text(json.dumps({"blocks": []}), encoding="utf-8")
    result = tmp_path / "out.h4p"
    code, out = _run(
        "project", "motion-import", kxr_project_path, program, "--motion", 1, "-o", result
    )
    assert code == 0, out
    assert "1 changed (slot(s) 1 now empty)" in out
    assert load_project(result).motion(1).is_empty


def test_bad_program_names_the_field(kxr_project_path: Path, tmp_path: Path) -> None:
    program = tmp_path / "bad.json"
    program.write_text(
        json.dumps({"blocks": [{"kind": "pose", "frames": 10, "positions": {"0": -5}}]}),
        encoding="utf-8",
    )
    code, out = _run(
        "project",
        "motion-import",
        kxr_project_path,
        program,
        "--motion",
        1,
        "-o",
        tmp_path / "o.h4p",
    )
    assert code == 1
    assert "blocks[0].positions.0" in out
    assert not (tmp_path / "o.h4p").exists()


def test_one_of_motion_or_all(kxr_project_path: Path, tmp_path: Path) -> None:
    code, out = _run("project", "motion-export", kxr_project_path, "-o", tmp_path / "x")
    assert code == 2 and "--motion N or --all" in out


def test_an_empty_slot_has_nothing_to_export(kxr_project_path: Path, tmp_path: Path) -> None:
    # slot 19 of the fixture is empty: exported, it was an empty program with exit 0
    code, out = _run("project", "motion-export", kxr_project_path, "--motion", 19, "-o",
                     tmp_path / "m19.json")  # fmt: skip
    assert code == 1 and "motion slot 19 is empty" in out
    assert not (tmp_path / "m19.json").exists()


def test_a_copy_does_not_take_the_originals_button(kxr_project_path: Path, tmp_path: Path) -> None:
    """docs/from-hth4.md's "copy a motion": motion 9 (bound to UP) exported and imported into
    free slot 18 gave both UP, so the copy never played from the remote. The copy comes in
    unbound, with a note, and motion 9 keeps UP."""
    code, out = _run("project", "motion-export", kxr_project_path, "--motion", 9, "-o",
                     tmp_path / "m9.json")  # fmt: skip
    assert code == 0, out
    result = tmp_path / "out.h4p"
    r = CliRunner().invoke(
        cli,
        ["project", "motion-import", str(kxr_project_path), str(tmp_path / "m9.json"),
         "--motion", "18", "-o", str(result)],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "motion 18: ↑ already starts motion 9" in r.stderr
    p = load_project(result)
    assert p.motion(9).button_data == 1 and p.motion(18).button_data == 0
    assert p.motion(18).name == p.motion(9).name


def test_a_motion_of_another_robot_is_named_so(kxr_project_path: Path, tmp_path: Path) -> None:
    """motion-import of the KXR fixture's motions into a KHR-3HV project said nothing, though
    the board skips the servos the KHR-3HV's table has not. Servos the project's own motions
    already move without listing them (the fixture's ICS 0 and 1) are not news."""
    khr3 = tmp_path / "k3.h4p"
    assert _run("project", "new", "--robot", "khr3hv", "-o", khr3)[0] == 0
    code, out = _run("project", "motion-export", kxr_project_path, "--motion", TURN_LEFT,
                     "-o", tmp_path / "t.json")  # fmt: skip
    assert code == 0, out
    r = CliRunner().invoke(cli, ["project", "motion-import", str(khr3), str(tmp_path / "t.json"),
                                 "--motion", "5", "-o", str(tmp_path / "k3t.h4p")])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "motion 5 moves servos this project's servo table has not (ICS " in r.stderr
    r = CliRunner().invoke(cli, ["project", "motion-import", str(kxr_project_path),
                                 str(tmp_path / "t.json"), "--motion", str(TURN_LEFT),
                                 "-o", str(tmp_path / "same.h4p")])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "servo table" not in r.stderr


def test_export_all_onto_a_file_is_a_typed_clash(kxr_project_path: Path, tmp_path: Path) -> None:
    """Was: "[Errno 17] File exists: 'HAC.h4p' (FileExistsError)"."""
    target = tmp_path / "hac.h4p"
    target.write_bytes(kxr_project_path.read_bytes())
    code, out = _run("project", "motion-export", target, "--all", "-o", target)
    assert code == 1 and "is a file, not a directory" in out and "(FileClashError)" in out
    assert target.read_bytes() == kxr_project_path.read_bytes()


def test_dash_is_stdout_for_export_and_xml_and_refused_for_import(
    kxr_project_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Was: `-o -` wrote a file named '-'."""
    monkeypatch.chdir(tmp_path)
    code, out = _run("project", "motion-export", kxr_project_path, "--motion", TURN_LEFT, "-o", "-")
    assert code == 0 and json.loads(out)["blocks"] and out.endswith("}\n")
    code, out = _run("project", "motion-xml", kxr_project_path, "--motion", TURN_LEFT, "-o", "-")
    assert code == 0 and out.rstrip().endswith("</CanvasData>") and out.endswith("\n")
    program = tmp_path / "p.json"
    program.write_text(json.dumps({"blocks": [{"kind": "end"}]}), encoding="utf-8")
    code, out = _run(
        "project", "motion-import", kxr_project_path, program, "--motion", 80, "-o", "-"
    )
    assert code == 2 and "not stdout" in out
    assert not (tmp_path / "-").exists()


def test_import_errors_start_with_the_file_name(kxr_project_path: Path, tmp_path: Path) -> None:
    """Was: top-level fields named the file (p.json.foo), block fields did not (blocks[0].bar),
    and a pose's known fields left out kind and label."""
    program = tmp_path / "p.json"
    pose = {"kind": "pose", "frames": 10, "positions": {"2": 7500}}
    for doc, words in (
        ({"blocks": [pose], "foo": 1}, "p.json.foo: unknown field"),
        (
            {"blocks": [{**pose, "bar": 1}]},
            "p.json.blocks[0].bar: unknown field (known: kind, label, frames, positions, update)",
        ),
        ({"blocks": [{**pose, "frames": 999}]}, "p.json.blocks[0].frames"),
    ):
        program.write_text(json.dumps(doc), encoding="utf-8")
        code, out = _run(
            "project",
            "motion-import",
            kxr_project_path,
            program,
            "--motion",
            80,
            "-o",
            tmp_path / "o.h4p",
        )
        assert code == 1 and words in out, out
    assert not (tmp_path / "o.h4p").exists()


def test_project_new_into_a_missing_directory_is_typed(tmp_path: Path) -> None:
    """Was: "[Errno 2] cannot write … (FileNotFoundError)"."""
    code, out = _run("project", "new", "--robot", "kxr-l2", "-o", tmp_path / "nodir" / "x.h4p")
    assert code == 1 and f"no directory {tmp_path / 'nodir'} (MissingFileError)" in out
