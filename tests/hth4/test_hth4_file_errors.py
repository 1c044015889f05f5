"""Opening and saving HeartToHeart4 files: a directory, a missing file, a read-only file and
arguments of the wrong type give typed errors naming the user's path; nothing is written."""

from __future__ import annotations

import os
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from rcb4hv import hth4
from rcb4hv.errors import FileAccessError, FileIsDirectoryError, FilePermissionError, Rcb4Error
from rcb4hv.hth4.edit import rename_motion
from rcb4hv.hth4.flowchart import load_motion_xml
from rcb4hv.hth4.link import load_link
from rcb4hv.hth4.motionlist import load_motion_list
from rcb4hv.hth4.session import EditSession
from rcb4hv.hth4.trim import load_trim

LOADERS: list[Callable[[Any], object]] = [
    hth4.load_project,
    EditSession.open,
    load_motion_xml,
    load_trim,
    load_motion_list,
    load_link,
]


@pytest.mark.parametrize("load", LOADERS, ids=lambda f: f.__qualname__)
def test_a_directory_or_a_missing_file_is_typed_and_named(
    tmp_path: Path, load: Callable[[Any], object]
) -> None:
    with pytest.raises(FileIsDirectoryError, match=f"{tmp_path}: it is a directory"):
        load(tmp_path)
    missing = tmp_path / "nope.h4p"
    with pytest.raises(FileNotFoundError, match=f"{missing}: no such file") as info:
        load(missing)
    assert isinstance(info.value, Rcb4Error)


def test_saving_over_a_read_only_project_refuses(tmp_path: Path, kxr_project_path: Path) -> None:
    target = tmp_path / "ro.h4p"
    shutil.copyfile(kxr_project_path, target)
    target.chmod(0o444)
    before = target.read_bytes()
    session = EditSession.open(target)
    session.apply(rename_motion, 69, "RENAMED")
    for save in (lambda: hth4.save_project(session.project, target), session.save):
        with pytest.raises(FilePermissionError, match=f"cannot write {target}: .*read-only"):
            save()
    assert target.read_bytes() == before and session.dirty
    assert os.listdir(tmp_path) == ["ro.h4p"]


def test_saving_a_non_project_is_a_type_error(tmp_path: Path) -> None:
    with pytest.raises(TypeError, match="project must be a Project, not str"):
        hth4.save_project("not a project", tmp_path / "x.h4p")  # type: ignore[arg-type]
    assert not (tmp_path / "x.h4p").exists()
    with pytest.raises(TypeError, match="bytes or str, not int"):
        hth4.parse_project(5)  # type: ignore[arg-type]


def test_file_errors_are_os_errors_too() -> None:
    assert issubclass(FileAccessError, OSError) and issubclass(FileAccessError, Rcb4Error)
