"""Every example in README.md and docs/ runs as pasted.

Fenced blocks are collected per page, in order:

* ``python`` blocks run as scripts (``.venv``'s interpreter);
* ``sh`` / ``bash`` blocks run as bash scripts with ``set -e``;
* ``console`` blocks run each ``$ command``; output lines shown under a command must match
  what it prints;
* any block right after ``<!-- file: NAME -->`` is written to ``NAME`` instead (an ``asm``
  source the next examples assemble, for instance);
* a block right after ``<!-- snippet: skip (REASON) -->`` is not run (it needs a real board
  or root); the reason is required.

A block that uses a file an earlier block of the page made must say so where the reader
sees it: the text between the previous block and this one (HTML comments do not count) names
the file. So must a ``file:`` block name the file it is saved as.

Each page runs in its own temporary directory with ``../shared`` pointing at the shared
fixtures, as from the repository root, and ``rcb4hv`` on the PATH.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from tests.conftest import FIXTURES, REPO

PAGES = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
FENCE = re.compile(r"^```(\w*)[^\n]*\n(.*?)^```\s*$", re.S | re.M)
MARK = re.compile(r"<!--\s*(file|snippet):\s*([^>]*?)\s*-->\s*$")
COMMENT = re.compile(r"<!--.*?-->", re.S)
SCRATCH = {".stdout", ".stderr", "snippet.py"}
RUN = {"python", "sh", "bash", "console"}


@dataclass
class Block:
    page: Path
    line: int
    lang: str
    text: str
    file: str | None = None
    skip: str | None = None
    prose: str = ""  # what the reader sees between the previous block and this one

    @property
    def id(self) -> str:
        return f"{self.page.relative_to(REPO)}:{self.line}"


def blocks(page: Path) -> list[Block]:
    source = page.read_text(encoding="utf-8")
    out = []
    last_end = 0
    for m in FENCE.finditer(source):
        before = source[: m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        block = Block(page, source.count("\n", 0, m.start()) + 1, m.group(1), m.group(2))
        block.prose = COMMENT.sub("", source[last_end : m.start()])
        last_end = m.end()
        mark = MARK.search(before)
        if mark and mark.group(1) == "file":
            block.file = mark.group(2)
        elif mark:
            assert mark.group(2).startswith("skip ("), f"{block.id}: skip needs a (reason)"
            block.skip = mark.group(2)
        out.append(block)
    return out


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    env.pop("RCB4HV_PORT", None)
    env["MPLBACKEND"] = "Agg"
    env["PYTHONWARNINGS"] = "error"
    return env


def _workdir(tmp_path: Path) -> Path:
    shared = tmp_path / "shared"
    shared.symlink_to(FIXTURES.parent.parent)
    work = tmp_path / "work"
    work.mkdir()
    return work


def _console(block: Block) -> list[tuple[str, list[str]]]:
    steps: list[tuple[str, list[str]]] = []
    for line in block.text.splitlines():
        if line.startswith("$ "):
            steps.append((line[2:], []))
        elif steps:
            steps[-1][1].append(line.rstrip())
    return steps


def _matches(want: list[str], got: str) -> bool:
    """Shown output matches what ran; ``...`` stands for any text (machine-dependent)."""
    pattern = re.escape("\n".join(want)).replace(re.escape("..."), ".*?")
    return re.fullmatch(pattern, got, re.S) is not None


def _code_lines(block: Block) -> list[str]:
    lines = [ln.split("#")[0].strip() for ln in block.text.splitlines()]
    return [ln for ln in lines if ln]


def _make_only(block: Block) -> bool:
    lines = _code_lines(block)
    return bool(lines) and all(ln.startswith("make ") for ln in lines)


def run_block(block: Block, cwd: Path) -> None:
    env = _env()
    if block.file is not None:
        (cwd / block.file).write_text(block.text, encoding="utf-8")
        return
    if block.lang == "python":
        script = cwd / "snippet.py"
        script.write_text(block.text, encoding="utf-8")
        commands = [([sys.executable, str(script)], None)]
    elif block.lang in ("sh", "bash") and not _make_only(block):
        commands = [(["bash", "-e", "-c", block.text], None)]
    elif _make_only(block):
        # the project's own entry points (`make test` runs this very test): check that each
        # target exists instead of running it
        makefile = (REPO / "Makefile").read_text()
        for line in _code_lines(block):
            target = line.split()[1]
            assert re.search(rf"^{re.escape(target)}:", makefile, re.M), f"{block.id}: {line}"
        return
    else:
        commands = [(["bash", "-e", "-c", cmd], want) for cmd, want in _console(block)]
    for argv, want in commands:
        code, out, err = _execute(argv, cwd, env)
        where = f"{block.id} ({' '.join(argv)[:200]})"
        assert code == 0, f"{where} failed:\n{out}\n{err}"
        if want:
            got = "\n".join(ln.rstrip() for ln in out.rstrip("\n").splitlines())
            assert _matches(want, got), f"{where}: output differs:\n{got}"


def _execute(argv: list[str], cwd: Path, env: dict[str, str]) -> tuple[int, str, str]:
    """Run ``argv`` in its own process group with its output in files (a background process
    an example starts cannot hold a pipe open); whatever it leaves running is killed."""
    out_path, err_path = cwd / ".stdout", cwd / ".stderr"
    with open(out_path, "w") as out, open(err_path, "w") as err:
        proc = subprocess.Popen(
            argv, cwd=cwd, env=env, stdout=out, stderr=err, start_new_session=True
        )
        try:
            code = proc.wait(timeout=180)
        finally:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(proc.pid, signal.SIGTERM)
            proc.wait()
    return code, out_path.read_text(), err_path.read_text()


def _pages_with_runnable_blocks() -> list[Path]:
    return [p for p in PAGES if any(b.lang in RUN or b.file for b in blocks(p))]


def test_every_page_is_collected() -> None:
    names = {p.name for p in PAGES}
    assert {"README.md", "getting-started.md", "hardware.md", "client.md"} <= names


@pytest.mark.timeout(600)
@pytest.mark.parametrize(
    "page", _pages_with_runnable_blocks(), ids=lambda p: str(p.relative_to(REPO))
)
def test_examples_run(page: Path, tmp_path: Path) -> None:
    cwd = _workdir(tmp_path)
    ran = 0
    made: set[str] = set()  # files earlier blocks left in the work directory
    unsaid: list[str] = []
    for block in blocks(page):
        if block.skip or not (block.lang in RUN or block.file):
            continue
        if block.file is not None and not _mentions(block.prose, block.file):
            unsaid.append(f"{block.id} is saved as {block.file} without saying so")
        unsaid += [
            f"{block.id} uses {name}, made by an earlier block, without saying so"
            for name in sorted(made)
            if _mentions(block.text, name) and not _mentions(block.prose, name)
        ]
        run_block(block, cwd)
        made |= _files(cwd)
        ran += 1
    assert ran
    assert not unsaid, "\n".join(unsaid)


def _files(cwd: Path) -> set[str]:
    """Names of the files in ``cwd`` that a later example could use (names with a suffix)."""
    return {p.name for p in cwd.rglob("*") if p.is_file() and "." in p.name} - SCRATCH


def _mentions(text: str, name: str) -> bool:
    return re.search(rf"(?<![\w.-]){re.escape(name)}(?![\w-])", text) is not None


def test_skip_markers_are_rare() -> None:
    """Only what needs a real board or root may be skipped."""
    skipped = [b for p in PAGES for b in blocks(p) if b.skip]
    assert all(("board" in b.skip or "root" in b.skip) for b in skipped), [
        (b.id, b.skip) for b in skipped
    ]
