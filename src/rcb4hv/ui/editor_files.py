"""The Editor page's files: Open (a path on this computer), "Edit the Project page's project"
and Save, with the two questions that keep work from being lost.

- Open and "Edit the Project page's project" replace the session: with unsaved edits they
  ask first (discard / cancel). Undo cannot bring a replaced session back.
- Save writes over an existing file only if it is the one the session was read from or last
  saved to; another existing file (a path typed in the box, or any file when the session came
  from the Project page and has no file of its own) is overwritten only after a yes
  (overwrite / cancel), :meth:`~rcb4hv.ui.editor_state.Editor.overwrite_question`.

The path box always names the session's file: the Project page's project has none, so taking
it empties the box; a cancelled Open puts the session's path back.
"""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Any, Protocol

from nicegui import ui

from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import dump_project
from rcb4hv.ui.context import UiContext, tid
from rcb4hv.ui.editor_state import Editor

__all__ = ["EditorPage", "ask", "open_path", "save", "take_project"]

log = logging.getLogger(__name__)


class EditorPage(Protocol):
    """What these functions use of :class:`rcb4hv.ui.editor_page.EditorPage`."""

    ctx: UiContext
    ed: Editor
    path_in: Any  # ui.input
    downloads: Any  # ui.row

    def fail(self, exc: Exception) -> None: ...
    def named_robot(self) -> str | None: ...
    def rebuild_view(self) -> None: ...
    def redraw(self) -> None: ...


async def ask(question: str, detail: str, button: str, marker: str) -> bool:
    """A dialog: True when ``button`` (red, marked ``marker``) is pressed, False on Cancel
    (marked ``marker-cancel``) or when the dialog is closed."""
    with ui.dialog() as dialog, ui.card():
        ui.label(question).classes("font-bold")
        ui.label(detail)
        with ui.row():
            tid(ui.button(button, color="red", on_click=lambda: dialog.submit(True)), marker)
            tid(ui.button("Cancel", on_click=lambda: dialog.submit(False)), f"{marker}-cancel")
    try:
        return bool(await dialog)
    finally:
        dialog.delete()


def _session_path(page: EditorPage) -> str:
    s = page.ed.session
    return str(s.path) if s is not None and s.path is not None else ""


async def _may_discard(page: EditorPage, instead: str) -> bool:
    """True if the session may be replaced: no unsaved edits, or the user said discard."""
    ed = page.ed
    if not ed.dirty or ed.session is None:
        return True
    n = len(ed.session.history)
    if await ask(
        f"Discard your unsaved changes ({n} edit{'' if n == 1 else 's'})?",
        f"{instead} replaces the project you edit; Undo cannot bring the edits back. "
        "Cancel keeps them (Save first to keep them in a file).",
        "Discard",
        "editor-discard-confirm",
    ):
        log.info("editor: %d unsaved edit(s) discarded for %s", n, instead)
        return True
    page.path_in.value = _session_path(page)  # the box names the file still being edited
    ui.notify("kept your unsaved changes")
    return False


async def open_path(page: EditorPage) -> None:
    if not (page.path_in.value or "").strip():
        page.fail(ValueError("type the path of a .h4p project file to open"))
        return
    path = Path(page.path_in.value.strip()).expanduser()
    if path.suffix.lower() != ".h4p":
        page.fail(ValueError(f"{path}: not a .h4p project file"))
        return
    if not await _may_discard(page, f"Opening {path}"):
        return
    limit = page.ctx.max_upload
    try:
        data = path.read_bytes()
        if len(data) > limit:
            raise ValueError(f"{path}: {len(data):,} bytes; the limit is {limit:,}")
        page.ed.open(data, path, page.named_robot())
    except (OSError, Rcb4Error, ValueError) as exc:
        page.fail(exc)
        return
    page.path_in.value = str(path)
    ui.notify(f"editing {path}")
    page.rebuild_view()
    page.redraw()


async def take_project(page: EditorPage) -> None:
    if page.ctx.project is None:
        page.fail(ValueError("no project is open on the Project page"))
        return
    if not await _may_discard(page, "Taking the Project page's project"):
        return
    project = page.ctx.project
    if project is None:  # closed while the question was open
        page.fail(ValueError("no project is open on the Project page"))
        return
    page.ed.open(dump_project(project), None, page.named_robot())
    page.path_in.value = ""  # no file of its own yet: Save asks for one
    ui.notify(
        f"editing the Project page's project {page.ctx.project_name or ''}".rstrip()
        + ": type a path to save it to"
    )
    page.rebuild_view()
    page.redraw()


async def save(page: EditorPage) -> None:
    ed = page.ed
    text = (page.path_in.value or "").strip()
    target = Path(text).expanduser() if text else None
    if target is not None and target.suffix.lower() != ".h4p":
        page.fail(ValueError(f"{target}: save to a .h4p file"))
        return
    question = ed.overwrite_question(target)
    if question is not None and not await ask(
        f"Overwrite {target}?",
        f"{question}: saving replaces what it holds. Cancel writes nothing.",
        "Overwrite",
        "editor-overwrite-confirm",
    ):
        ui.notify(f"not saved: {target} kept as it was")
        return
    try:
        saved, charts = ed.save(target, overwrite=question is not None)
    except (OSError, Rcb4Error, ValueError) as exc:
        page.fail(exc)
        return
    page.path_in.value = str(saved)
    page.ctx.set_project(ed.project, saved.name)
    page.downloads.clear()
    with page.downloads:
        data = saved.read_bytes()
        tid(
            ui.button(f"{saved.name}", icon="download").props("flat dense"),
            "editor-download-h4p",
        ).on_click(lambda: ui.download.content(data, saved.name))
        for i, (name, xml) in enumerate(sorted(charts.items())):
            tid(
                ui.button(name, icon="download").props("flat dense"), f"editor-download-xml-{i}"
            ).on_click(lambda xml=xml, name=name: ui.download.content(xml, name))
    ui.notify(f"saved {saved}")
    page.redraw()
