"""EditSession: undo / redo, unsaved changes, byte-exact and atomic saves; project diff."""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
from pathlib import Path

import pytest

from rcb4hv import hth4
from rcb4hv.errors import EditError
from rcb4hv.files import write_atomic
from rcb4hv.hth4.diff import diff_projects
from rcb4hv.hth4.edit import mirror_motion, rename_motion, set_pose, set_trim
from rcb4hv.hth4.session import EditSession
from tests.hth4._hth4_fixtures import fixture
from tests.hth4._model import kxr_like

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture
def copy(tmp_path: Path) -> Path:
    path = tmp_path / "project.h4p"
    path.write_bytes(fixture("HAC_KXR_HTH4_project.h4p").read_bytes())
    return path


def test_saving_without_changes_reproduces_the_file(copy: Path, tmp_path: Path) -> None:
    s = EditSession.open(copy)
    assert not s.dirty and not s.can_undo
    out = s.save(tmp_path / "same.h4p")
    assert out.read_bytes() == copy.read_bytes()


def test_undo_redo_and_dirty(copy: Path) -> None:
    s = EditSession.open(copy)
    original = s.project
    s.apply(set_pose, 69, 0, {10: 8000})
    s.apply(rename_motion, 69, "renamed")
    assert s.dirty and s.history == ["set pose", "rename motion"]
    assert [m.slot for m in s.changed_motions] == [69]
    s.undo()
    assert s.project.motion(69).name == "HAC_KXR_TURN_LEFT" and s.can_redo
    s.undo()
    assert s.project == original and not s.dirty
    with pytest.raises(EditError, match="nothing to undo"):
        s.undo()
    s.redo()
    s.apply(set_trim, 10, -240)  # a new edit drops what could be redone
    assert not s.can_redo and s.history == ["set pose", "set trim"]
    with pytest.raises(EditError, match="no ICS position"):
        s.apply(set_pose, 69, 0, {10: 20000})
    assert s.history == ["set pose", "set trim"]  # a refused edit changes nothing
    s.save()
    assert not s.dirty
    assert hth4.load_project(copy) == s.project


def test_two_editors_of_one_file_do_not_undo_each_others_save(copy: Path, tmp_path: Path) -> None:
    """The second of two sessions on one file refuses to save over the first one's save (it
    wrote its own project over it, losing the first one's edit, with no word)."""
    first, second = EditSession.open(copy), EditSession.open(copy)
    first.apply(rename_motion, 69, "first")
    first.save()
    second.apply(rename_motion, 70, "second")
    with pytest.raises(EditError, match="changed on disk since it was opened"):
        second.save()
    assert hth4.load_project(copy).motion(69).name == "first"  # nothing written
    second.save(tmp_path / "other.h4p")  # under another name: fine
    assert hth4.load_project(tmp_path / "other.h4p").motion(70).name == "second"
    third = EditSession.open(copy)
    first.apply(rename_motion, 71, "again")
    first.save()  # its own last save is what the file holds: no conflict
    with pytest.raises(EditError, match="changed on disk"):
        third.save()
    third.save(overwrite=True)  # on purpose
    assert hth4.load_project(copy).motion(71).name != "again"


def test_save_is_atomic_when_the_rename_fails(copy: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    before = copy.read_bytes()
    s = EditSession.open(copy)
    s.apply(set_pose, 69, 0, {10: 8000})

    def broken(src: str, dst: str) -> None:
        raise OSError("disk gone")

    monkeypatch.setattr(os, "replace", broken)
    with pytest.raises(OSError, match="disk gone"):
        s.save()
    assert copy.read_bytes() == before
    assert sorted(p.name for p in copy.parent.iterdir()) == ["project.h4p"]
    assert s.dirty


def test_a_process_killed_mid_write_leaves_the_old_file(copy: Path) -> None:
    """The writer dies (SIGKILL) after writing half the new bytes to its temp file."""
    before = copy.read_bytes()
    code = f"""
import os, signal, sys
sys.path.insert(0, {str(REPO / "src")!r})
from rcb4hv import files as _files
real = os.fdopen
class Half:
    def __init__(self, f): self.f = f
    def __enter__(self): return self
    def __exit__(self, *a): return False
    def write(self, data):
        self.f.write(data[: len(data) // 2]); self.f.flush()
        os.kill(os.getpid(), signal.SIGKILL)
_files.os.fdopen = lambda fd, mode: Half(real(fd, mode))
_files.write_atomic({str(copy)!r}, b"x" * 100000)
"""
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=60)
    assert proc.returncode == -9
    assert copy.read_bytes() == before
    assert hth4.load_project(copy) is not None


def test_write_atomic_replaces(tmp_path: Path) -> None:
    target = tmp_path / "f.bin"
    write_atomic(target, b"one")
    write_atomic(target, b"two")
    assert target.read_bytes() == b"two" and len(list(tmp_path.iterdir())) == 1


def test_diff_ignores_the_file_layout_and_names_a_priority_check(copy: Path) -> None:
    """Line ends and a byte-order mark carry no data (no change); a priority motion check is
    one readable change, not a dump of the whole collection."""
    p = hth4.load_project(copy)
    relaid = copy.with_name("lf.h4p")
    relaid.write_bytes(b"\xef\xbb\xbf" + copy.read_bytes().replace(b"\r\n", b"\n"))
    q = hth4.load_project(relaid)
    assert q.layout != p.layout and diff_projects(p, q) == []
    used = next(i for i, s in enumerate(p.priority_motions) if s.motion is not None)
    slots = list(p.priority_motions)
    slots[used] = dataclasses.replace(slots[used], motion=None)
    (change,) = diff_projects(p, dataclasses.replace(p, priority_motions=tuple(slots)))
    assert change.text.startswith(f"priority motion check {slots[used].key}: '")
    assert change.text.endswith(" -> unused") and "PriorityMotion" not in change.text


def test_diff_names_exactly_the_changes(copy: Path) -> None:
    p = hth4.load_project(copy)
    assert diff_projects(p, p) == []
    q = set_pose(p, 66, 1, {10: 7700, 12: 7000})
    q = mirror_motion(q, 69, kxr_like(), to=73, name="mirror", date=p.motion(73).date)
    q = set_trim(q, 10, -240)
    changes = [c.to_json() for c in diff_projects(p, q)]
    assert [(c["kind"], c.get("slot"), c.get("pose"), c.get("ics")) for c in changes] == [
        ("servo", None, None, 10),
        ("pose-servo", 66, 2, 10),
        ("pose-servo", 66, 2, 12),
        ("motion-added", 73, None, None),
    ]
    assert changes[1]["old"] == 7900 and changes[1]["new"] == 7700
    # the size `project info` gives the motion: its frames, not HeartToHeart4's FF end marker
    assert changes[3]["text"].endswith(f"new motion, 4 poses, {q.motion(73).code_size} bytes")
    assert len(q.motion(73).rom_bytes()) == q.motion(73).code_size + 1
    with pytest.raises(EditError, match="leave out the target slot"):
        mirror_motion(p, 69, kxr_like(), to=69)


def test_a_mixing_rate_is_what_the_block_can_hold(copy: Path) -> None:
    """A mixing rate is a sign and a multiplier 0-127 (spec: the method byte): -8 (a reversed
    gyro) is set and builds; 200 is refused at the edit (it was taken, and the build then
    failed with "cannot build")."""
    from rcb4hv.hth4.newproject import set_mixing
    from rcb4hv.project.relocate import project_image

    project = hth4.load_project(copy)
    mixed = set_mixing(project, 14, 1, 0x0024, -8)
    assert mixed.servo(14).mixing1_rate == -8
    project_image(mixed)  # builds
    with pytest.raises(EditError, match=r"outside -127\.\.127"):
        set_mixing(project, 14, 1, 0x0024, 200)
