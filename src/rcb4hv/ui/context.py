"""What every page of the dashboard shares: the board session and the open project."""

from __future__ import annotations

import asyncio
import logging
import weakref
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any, TypeVar

from nicegui import Client, ui
from nicegui.element import Element
from nicegui.elements.mixins.value_element import ValueElement
from nicegui.slot import Slot

from rcb4hv.errors import RobotModelError
from rcb4hv.hth4 import Project
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.robot import RobotModel
from rcb4hv.session import BoardSession
from rcb4hv.ui.robots import choose_robot

__all__ = [
    "MAX_UPLOAD",
    "UiContext",
    "attempt",
    "current_client",
    "guard_leaving",
    "guarded",
    "on_commit",
    "tid",
]

log = logging.getLogger(__name__)

MAX_UPLOAD = 4 * 1024 * 1024
"""Largest file the pages accept (a HeartToHeart4 project is ~200 KB, a ROM image 256 KB)."""

E = TypeVar("E", bound=Element)
T = TypeVar("T")


def tid(element: E, name: str) -> E:
    """Name ``element`` for tests: a NiceGUI marker (User tests) and ``data-testid`` (browser)."""
    element.mark(name)
    element.props(f"data-testid={name}")
    return element


def on_commit(element: ValueElement[Any], fn: Callable[[Any], None]) -> None:
    """Call ``fn(value)`` when the user is done with a field (Enter, or leaving it), not at
    every keystroke: typing 8200 must not apply 8, 82 and 820 on the way (each refused or an
    undo step of its own). ``fn`` sees the same value twice (Enter, then leaving): it must
    do nothing for a value that changes nothing."""
    element.on("keydown.enter", lambda: fn(element.value))
    element.on("blur", lambda: fn(element.value))


_LEAVE_JS = (
    "window.onbeforeunload = {on} ? (e) => {{ e.preventDefault(); e.returnValue = ''; }} : null"
)
_unsaved: weakref.WeakKeyDictionary[Client, set[str]] = weakref.WeakKeyDictionary()


def guard_leaving(client: Client, page: str, unsaved: bool) -> None:
    """Whether ``page`` of the browser tab ``client`` holds work a reload would lose: while any
    page does, the browser asks before leaving (its own "leave site?" question, when
    onbeforeunload cancels the event). One question for every page of the tab."""
    pages = _unsaved.setdefault(client, set())
    before = bool(pages)
    (pages.add if unsaved else pages.discard)(page)
    if bool(pages) != before:
        client.run_javascript(_LEAVE_JS.format(on="true" if pages else "false"))


async def guarded(future: Future[T], what: str) -> T | None:
    """Await a session job; a failure becomes a notification, not a stack trace."""
    try:
        return await asyncio.wrap_future(future)
    except Exception as exc:  # shown to the user; the session already logged link errors
        log.info("%s failed: %s", what, exc)
        ui.notify(f"{what} failed: {exc}", type="negative", multi_line=True)
        return None


async def attempt(future: Future[object], what: str) -> bool:
    """Await a session job that returns nothing: True if it worked (failures are notified)."""
    try:
        await asyncio.wrap_future(future)
    except Exception as exc:  # shown to the user
        log.info("%s failed: %s", what, exc)
        ui.notify(f"{what} failed: {exc}", type="negative", multi_line=True)
        return False
    return True


def current_client() -> Client | None:
    """The browser tab whose page is being built, or None outside a page (a test, a
    background task). Unlike ``ui.context.client`` this never creates NiceGUI's stand-in
    client of a script that has not started the app."""
    stack = Slot.get_stack()
    if not stack:
        Slot.prune_stack()  # get_stack made an empty one for this task
        return None
    return stack[-1].parent.client


@dataclass
class UiContext:
    """State shared by all pages and browser tabs (one user, one board).

    ``robot`` is the model the 3D view draws and the servo table names joints from;
    ``robot_source`` says where it came from (``--robot``, a project, the default). With
    ``auto_robot`` the model is chosen again (:func:`rcb4hv.ui.robots.choose_robot`) whenever
    a project opens; otherwise it stays as given."""

    session: BoardSession
    project: Project | None = None
    project_name: str = ""
    robot: RobotModel | None = None
    robot_source: str = ""
    auto_robot: bool = False
    robot_candidates: tuple[str, ...] = ()
    """The models the open project fits when detection must ask (none picked yet): the
    dashboard does not play the project on a model it did not pick (:meth:`pick_robot`)."""
    robot_spec: str | None = None
    """``rcb4hv ui --robot``: the model every page uses while it fits the open project
    (:func:`rcb4hv.ui.robots.named_or_detected`)."""
    max_upload: int = MAX_UPLOAD
    _listeners: list[Callable[[], None]] = field(default_factory=list)

    def choose_robot(self, spec: str | None = None) -> None:
        """Choose the model from ``spec`` (``--robot``, kept for the next project), the open
        project or the board."""
        self.robot_spec = spec if spec is not None else self.robot_spec
        indices = [s.ics for s in self.session.state.servos]
        self.robot, self.robot_source, self.robot_candidates = choose_robot(
            self.robot_spec, self.project, indices
        )

    @property
    def robot_caption(self) -> str:
        """The model's title and where it came from, as the 3D views caption it."""
        return f"{self.robot.title} ({self.robot_source})" if self.robot is not None else ""

    def pick_robot(self, name: str) -> None:
        """The user picked ``name``, one of :attr:`robot_candidates` (on the Editor page): every
        page draws, names joints and plays the project with it, as ``--robot`` would."""
        if name not in self.robot_candidates:
            raise RobotModelError(
                f"{name}: not one of the models the project fits "
                f"({', '.join(self.robot_candidates) or 'none to pick'})"
            )
        self.robot = project_model(self.project, name)
        self.robot_source, self.robot_candidates = f"picked for the project: {name}", ()
        self._notify()

    def recheck_robot(self) -> None:
        """Choose again once the board's servos are known, if the model is the fallback
        default (the board was not answering when the dashboard started)."""
        if (
            self.auto_robot
            and self.project is None
            and self.robot_source == "default"
            and self.session.state.servos
        ):
            self.choose_robot()
            if self.robot_source != "default":
                self._notify()

    def set_project(self, project: Project | None, name: str = "") -> None:
        self.project, self.project_name = project, name
        if self.auto_robot or self.robot_spec is not None:
            self.choose_robot()
        self._notify()

    def _notify(self) -> None:
        for fn in list(self._listeners):
            try:
                fn()
            except Exception:  # a listener of a closed browser tab
                log.debug("project listener failed", exc_info=True)
                self._listeners.remove(fn)

    def on_project(self, fn: Callable[[], None], client: Client | None = None) -> None:
        """Call ``fn`` whenever the project or the robot model changes, until the browser tab
        ``client`` is gone (deleted once it stays disconnected past the reconnect timeout; a
        reload is a new tab). ``client`` defaults to the tab whose page is being built; with
        none (outside a page) ``fn`` stays until :meth:`off_project`. A closed tab's views
        stayed registered before and each re-ran ``project check`` on every change."""
        self._listeners.append(fn)
        if client is None:
            client = current_client()
        if client is not None:
            client.on_delete(lambda: self.off_project(fn))

    @property
    def listener_count(self) -> int:
        """How many views follow the project (see :meth:`on_project`)."""
        return len(self._listeners)

    def off_project(self, fn: Callable[[], None]) -> None:
        """Stop calling ``fn`` (a view of a closed browser tab)."""
        while fn in self._listeners:
            self._listeners.remove(fn)
