"""An edit session on one project: undo / redo history, unsaved-change tracking, atomic save.

:class:`EditSession` holds the project as loaded (its file bytes), the current project and
two stacks of earlier / undone projects. Every edit is a pure function of
:mod:`rcb4hv.hth4.edit` applied with :meth:`EditSession.apply`; an edit that raises leaves
the session as it was. Saving writes :func:`~rcb4hv.hth4.project.dump_project` of the
current project through :func:`rcb4hv.files.write_atomic` (a temp file in the same directory, fsync,
``os.replace``, directory fsync), after checking that the bytes read back to the same
project. A session that was not edited saves the bytes it loaded, unchanged.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Concatenate, ParamSpec

from rcb4hv.errors import EditError
from rcb4hv.files import write_atomic
from rcb4hv.hth4.model import Motion, Project
from rcb4hv.hth4.project import dump_project, parse_project, read_project_file

__all__ = ["EditSession", "HistoryEntry", "changed_slots"]

log = logging.getLogger(__name__)

P = ParamSpec("P")


def changed_slots(before: Project, after: Project) -> list[int]:
    """Slots whose motion entry differs between two projects."""
    old = {m.slot: m for m in before.motions}
    new = {m.slot: m for m in after.motions}
    return sorted(s for s in old.keys() | new.keys() if old.get(s) != new.get(s))


@dataclass(frozen=True)
class HistoryEntry:
    """A project state and the label of the edit that made it."""

    project: Project
    label: str


@dataclass
class EditSession:
    """Undo / redo over immutable projects. ``path`` is where :meth:`save` writes."""

    project: Project
    path: Path | None = None
    loaded: bytes | None = None
    _undo: list[HistoryEntry] = field(default_factory=list)
    _redo: list[HistoryEntry] = field(default_factory=list)
    _saved: Project | None = None

    def __post_init__(self) -> None:
        self._saved = self.project

    @classmethod
    def open(cls, path: str | os.PathLike[str]) -> EditSession:
        """A session on the project file ``path`` (errors name it: :func:`read_project_file`)."""
        project, data = read_project_file(path)
        return cls(project, Path(path), data)

    # ------------------------------------------------------------------ editing

    def apply(
        self,
        edit: Callable[Concatenate[Project, P], Project],
        *args: P.args,
        **kwargs: P.kwargs,
    ) -> Project:
        """Run ``edit(project, *args, **kwargs)`` and make its result current (undoable)."""
        new = edit(self.project, *args, **kwargs)
        if new is self.project or new == self.project:
            return self.project
        label = getattr(edit, "__name__", "edit").replace("_", " ")
        self._undo.append(HistoryEntry(self.project, label))
        self._redo.clear()
        self.project = new
        log.debug("edit: %s", label)
        return new

    @property
    def can_undo(self) -> bool:
        return bool(self._undo)

    @property
    def can_redo(self) -> bool:
        return bool(self._redo)

    @property
    def history(self) -> list[str]:
        """Labels of the edits that can be undone, oldest first."""
        return [e.label for e in self._undo]

    def undo(self) -> Project:
        """Go back one edit; EditError if there is none."""
        if not self._undo:
            raise EditError("nothing to undo")
        entry = self._undo.pop()
        self._redo.append(HistoryEntry(self.project, entry.label))
        self.project = entry.project
        return self.project

    def redo(self) -> Project:
        """Re-apply the last undone edit; EditError if there is none."""
        if not self._redo:
            raise EditError("nothing to redo")
        entry = self._redo.pop()
        self._undo.append(HistoryEntry(self.project, entry.label))
        self.project = entry.project
        return self.project

    # ------------------------------------------------------------------ saving

    def _changed_on_disk(self, target: Path) -> bool:
        """True if ``target`` is the file last read or written here and now holds other bytes."""
        if self.path is None or self.loaded is None:
            return False
        try:
            if target.resolve() != self.path.resolve():
                return False
            return target.read_bytes() != self.loaded
        except FileNotFoundError:  # deleted meanwhile: writing it again loses nothing
            return False

    @property
    def dirty(self) -> bool:
        """True if the project differs from the one last loaded or saved."""
        return self.project != self._saved

    @property
    def changed_slot_numbers(self) -> list[int]:
        """The slots whose motion differs from the last loaded or saved project, emptied
        slots included."""
        assert self._saved is not None
        return sorted(changed_slots(self._saved, self.project))

    @property
    def changed_motions(self) -> list[Motion]:
        """The motions that differ from the last loaded or saved project (used ones)."""
        slots = set(self.changed_slot_numbers)
        return [m for m in self.project.motions if m.slot in slots and not m.is_empty]

    def dump(self) -> bytes:
        """The bytes :meth:`save` writes (the loaded bytes if nothing changed)."""
        if self.loaded is not None and self.project == parse_project(self.loaded):
            return self.loaded
        data = dump_project(self.project)
        if dump_project(parse_project(data)) != data:  # pragma: no cover - a writer bug
            raise EditError("the edited project does not read back the same; nothing written")
        return data

    def save(self, path: str | os.PathLike[str] | None = None, *, overwrite: bool = False) -> Path:
        """Write the project atomically to ``path`` (default: where it was opened).

        Saving over the file it was read from refuses (:class:`~rcb4hv.errors.EditError`,
        nothing written) when that file changed since (another window or program saved it),
        unless ``overwrite``: two editors of one file do not undo each other's work."""
        target = Path(path) if path is not None else self.path
        if target is None:
            raise EditError("no file to save to: give a path")
        if not overwrite and self._changed_on_disk(target):
            raise EditError(
                f"{target}: changed on disk since it was opened here (another window or "
                "program saved it): nothing written; open it again, or save under another name"
            )
        data = self.dump()
        write_atomic(target, data)
        self.path = target
        self.loaded = data
        self._saved = self.project
        log.info("saved %s (%d bytes)", target, len(data))
        return target
