"""What the Editor page shows and does, without NiceGUI: the edit session, the chosen motion
and pose, the joint rows of the sliders, and the files a save produces.

Joint angles follow :mod:`rcb4hv.hth4.poses`: a motion value ``v`` of servo ``i`` is at
``model.motion_angle(i, v)`` (the board adds the trim only when it sends, spec 9, so the trim
does not enter), and the slider's angle goes back through :meth:`Editor.value_for`
(``model.motion_value``, its inverse rounded to a count).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Concatenate, ParamSpec

from rcb4hv.errors import AmbiguousRobotError, EditError, Rcb4Error
from rcb4hv.hth4 import Project
from rcb4hv.hth4.blocks.flowxml import motion_xml
from rcb4hv.hth4.poses import Block, Checks, Pose, motion_blocks, motion_poses
from rcb4hv.hth4.project import parse_named_project
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.hth4.session import EditSession
from rcb4hv.protocol import POSITION_MAX, POSITION_MIN
from rcb4hv.protocol.memory import CENTER, COUNTS_PER_DEGREE
from rcb4hv.robot import RobotModel
from rcb4hv.robot.servos import TRAVEL_DEG
from rcb4hv.ui.robots import named_or_detected

__all__ = ["Editor", "JointRow"]

P = ParamSpec("P")


@dataclass(frozen=True)
class JointRow:
    """One slider: servo ``ics`` of the selected pose."""

    ics: int
    label: str
    value: int
    degrees: float
    lower: float
    upper: float
    advisory: str = ""
    """Non-empty when the value lies outside the joint's advisory range (kept: a warning)."""


class Editor:
    """The Editor page's state (one per browser tab)."""

    def __init__(self) -> None:
        self.session: EditSession | None = None
        self.model: RobotModel | None = None
        self.model_error = ""
        self.model_note = ""  # why the model is not the one given with --robot
        #: the models the project's evidence fits when detection must ask (pick_robot)
        self.model_candidates: tuple[str, ...] = ()
        self.slot: int | None = None
        self.pose_index: int | None = None
        self.force = False

    # ------------------------------------------------------------------ opening

    def open(
        self, data: bytes, path: Path | None = None, model: RobotModel | str | None = None
    ) -> None:
        """Edit the project file ``data`` (read from ``path``, where Save writes) with
        ``model`` (``--robot``), else the model detected from it: the rule of
        :mod:`rcb4hv.hth4.robotpick` (a model needing servos the project lacks is refused)."""
        name = str(path) if path is not None else "the project"
        self.session = EditSession(parse_named_project(data, name), path, data)
        self.model, self.model_error, self.model_candidates = None, "", ()
        self.model_note = ""
        try:
            if model is None:
                self.model = project_model(self.session.project)
            else:  # the dashboard's one rule for --robot and a project it may not fit
                self.model, why = named_or_detected(model, self.session.project)
                self.model_note = f"{why}: the Editor uses {self.model.name}" if why else ""
        except AmbiguousRobotError as exc:
            self.model_error, self.model_candidates = str(exc), exc.candidates
        except Rcb4Error as exc:
            self.model_error = str(exc)
        used = self.project.used_motions
        self.select(used[0].slot if used else None)

    def pick_robot(self, name: str) -> None:
        """Use model ``name`` (one of :attr:`model_candidates`, as ``--robot`` would)."""
        self.model = project_model(self.project, name)
        self.model_error, self.model_candidates = "", ()

    @property
    def project(self) -> Project:
        if self.session is None:
            raise EditError("no project open")
        return self.session.project

    @property
    def checks(self) -> Checks:
        return Checks(self.model, self.force)

    # ------------------------------------------------------------------ selection

    def motion_options(self) -> dict[int, str]:
        if self.session is None:
            return {}
        return {m.slot: f"M{m.slot:03d} {m.name}" for m in self.project.used_motions}

    def free_slots(self) -> list[int]:
        return [] if self.session is None else [m.slot for m in self.project.motions if m.is_empty]

    def select(self, slot: int | None, pose: int | None = 0) -> None:
        self.slot = slot
        n = len(self.poses())
        self.pose_index = None if not n or pose is None else max(0, min(pose, n - 1))

    def blocks(self) -> tuple[Block, ...]:
        if self.session is None or self.slot is None:
            return ()
        m = self.project.motion(self.slot)
        return () if m.is_empty else motion_blocks(m)

    def poses(self) -> tuple[Pose, ...]:
        if self.session is None or self.slot is None:
            return ()
        m = self.project.motion(self.slot)
        return () if m.is_empty else motion_poses(m)

    @property
    def pose(self) -> Pose | None:
        poses = self.poses()
        i = self.pose_index
        return poses[i] if i is not None and 0 <= i < len(poses) else None

    # ------------------------------------------------------------------ joints

    def degrees(self, ics: int, value: int) -> float | None:
        """The joint angle of motion value ``value`` in degrees (None: not a joint or special)."""
        if self.model is None or ics not in self.model.indices:
            return None
        if not POSITION_MIN <= value <= POSITION_MAX:
            return None
        return math.degrees(self.model.motion_angle(ics, value))

    def value_for(self, ics: int, degrees: float) -> int:
        """The motion value that puts servo ``ics``'s joint at ``degrees``."""
        if self.model is None or ics not in self.model.indices:
            return round(CENTER + degrees * COUNTS_PER_DEGREE)
        return self.model.motion_value(ics, math.radians(degrees))

    def joint_rows(self) -> list[JointRow]:
        pose = self.pose
        if pose is None:
            return []
        rows = []
        for ics, value in pose.positions:
            deg = self.degrees(ics, value)
            label, lo, hi = f"ICS {ics}", -TRAVEL_DEG, TRAVEL_DEG  # the servo's own travel
            note = ""
            if self.model is not None and ics in self.model.indices:
                joint = self.model.joint(self.model.servo(ics).joint)
                label = f"{joint.name} (ICS {ics})"
                lo, hi = math.degrees(joint.lower), math.degrees(joint.upper)
                note = "; ".join(self.checks.advisories({ics: value}))
            rows.append(
                JointRow(ics, label, value, deg if deg is not None else math.nan, lo, hi, note)
            )
        return rows

    def pose_angles(self) -> dict[str, float]:
        """Joint angles (radians by joint name) of the selected pose, for the 3D view."""
        pose, model = self.pose, self.model
        if pose is None or model is None:
            return {}
        out = {}
        for ics, value in pose.positions:
            if ics in model.indices and POSITION_MIN <= value <= POSITION_MAX:
                out[model.servo(ics).joint] = model.motion_angle(ics, value)
        return out

    # ------------------------------------------------------------------ editing

    def apply(
        self, edit: Callable[Concatenate[Project, P], Project], *args: P.args, **kw: P.kwargs
    ) -> None:
        """One undoable edit (EditError when refused: the session is unchanged)."""
        if self.session is None:
            raise EditError("no project open")
        self.session.apply(edit, *args, **kw)
        self.select(self.slot, self.pose_index)

    def undo(self) -> None:
        if self.session is not None and self.session.can_undo:
            self.session.undo()
            self.select(self.slot, self.pose_index)

    def redo(self) -> None:
        if self.session is not None and self.session.can_redo:
            self.session.redo()
            self.select(self.slot, self.pose_index)

    @property
    def dirty(self) -> bool:
        return self.session is not None and self.session.dirty

    def status(self) -> str:
        s = self.session
        if s is None:
            return "no project open: open one here or on the Project page"
        n = len(s.history)
        edits = "no edits" if not n else "1 edit" if n == 1 else f"{n} edits"
        if s.path is None:  # the Project page's project: no file of its own yet
            return f"no file yet - {edits}" + (" - save it to a file" if s.dirty else "")
        return f"{s.path} - {edits}" + (" - unsaved changes" if s.dirty else " - saved")

    def overwrite_question(self, path: Path | None) -> str | None:
        """Why saving to ``path`` needs the user's yes: it is an existing file other than the
        one this session was read from or last saved to (None: no question; ``path`` None
        saves to that file)."""
        if path is None or self.session is None or not path.exists():
            return None
        own = self.session.path
        try:
            if own is not None and path.resolve() == own.resolve():
                return None
        except OSError:  # an unreadable path: ask rather than guess
            pass
        what = "the file you opened" if own is not None else "the project you edit"
        return f"{path} exists and is not {what}" + (f" ({own})" if own is not None else "")

    def save(self, path: Path | None, *, overwrite: bool = False) -> tuple[Path, dict[str, bytes]]:
        """Save atomically; returns the path and the HeartToHeart4 flowchart files of the
        changed motions (name -> bytes, :func:`~rcb4hv.hth4.blocks.flowxml.motion_xml`).

        Refuses (:class:`EditError`, nothing written) to write over another existing file
        (:meth:`overwrite_question`) unless ``overwrite``: the user said yes."""
        if self.session is None:
            raise EditError("no project open")
        question = self.overwrite_question(path)
        if question is not None and not overwrite:
            raise EditError(f"{question}: nothing written")
        changed = [m.slot for m in self.session.changed_motions]
        target = self.session.save(path)
        charts = {}
        for slot in changed:
            name = self.project.motion(slot).name or f"M{slot:03d}"
            charts[f"{name}.xml"] = motion_xml(self.project, slot)
        return target, charts
