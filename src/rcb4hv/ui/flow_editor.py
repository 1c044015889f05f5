"""The Editor page's program panel: every block of the chosen motion, editable.

The motion is drawn as its program (:mod:`rcb4hv.hth4.blocks`): one box per block, branches as
arrows (:mod:`rcb4hv.ui.programsvg`). Click a block to select it; its fields appear as a form
(each value as JSON text: numbers, strings, ``{"ICS": value}`` maps, lists) and "Apply"
changes them. "Add after" inserts a block of the chosen kind after the selected one (with
:data:`~rcb4hv.hth4.blocks.edit.BLOCK_TEMPLATES` fields), "Remove", "Up" / "Down" reorder,
"Connect" sends the selected jump, call or branch to the block chosen in "Branch to". Each
change is one undoable edit of the page's session (Undo / Redo and Save as for poses).
"Step" runs the motion in the emulator one instruction at a time
(:class:`~rcb4hv.project.stepper.MotionStepper`) and outlines the block being run; "Restart"
starts it again from the motion's first block. The remote buttons that start the motion are
chosen on the pad's layout (:mod:`rcb4hv.ui.bind_panel`); the project settings are
:mod:`rcb4hv.ui.settings_panel`.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass

from nicegui import ui

from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import Project
from rcb4hv.hth4.blocks import KINDS, Block, block_spans, motion_program
from rcb4hv.hth4.blocks.edit import (
    BLOCK_HINTS,
    connect_block,
    insert_block,
    move_block,
    remove_block,
    set_block,
)
from rcb4hv.hth4.blocks.fields import CONDITION_NAMES
from rcb4hv.hth4.blocks.kinds import OPS, SERVO_FIELDS, VAR_OPS
from rcb4hv.project.relocate import project_image
from rcb4hv.project.stepper import MotionStepper
from rcb4hv.ui import bind_panel, settings_panel
from rcb4hv.ui.context import UiContext, tid
from rcb4hv.ui.editor_state import Editor
from rcb4hv.ui.programsvg import block_text, program_svg

__all__ = ["ProgramView", "build"]


@dataclass
class ProgramView:
    """What the panel shows, without NiceGUI: the blocks of the editor's motion, the selected
    block and the single-stepped program's position."""

    ed: Editor
    selected: int | None = None
    current: int | None = None
    stepper: MotionStepper | None = None
    stepped: tuple[Project, int] | None = None

    def blocks(self) -> tuple[Block, ...]:
        if self.ed.session is None or self.ed.slot is None:
            return ()
        if self.ed.project.motion(self.ed.slot).is_empty:
            return ()
        return motion_program(self.ed.project, self.ed.slot).blocks

    def block_at(self, pc: int) -> int | None:
        """The index of the block whose bytes hold ROM address ``pc`` (None: not this motion)."""
        assert self.ed.slot is not None
        motion = self.ed.project.motion(self.ed.slot)
        starts = [motion.address]
        for e in motion.frames:
            starts.append(starts[-1] + len(e))
        for n, (i, count) in enumerate(block_spans(motion)):
            if starts[i] <= pc < starts[i + count]:
                return n
        return None

    def stepping_current(self) -> bool:
        """True if the stepper runs the project and motion the editor shows."""
        s = self.stepped
        return s is not None and s[0] is self.ed.project and s[1] == self.ed.slot

    def restart(self) -> str:
        if self.ed.slot is None:
            return "pick a motion"
        image, layout = project_image(self.ed.project)
        self.stepper = MotionStepper(image, motion_layout=layout)
        step = self.stepper.begin(self.ed.project.motion(self.ed.slot).address)
        self.stepped = (self.ed.project, self.ed.slot)
        self.current = self.block_at(step.pc)
        return f"at block {self.current} ({step.time:.3f} s)"

    def step(self) -> str:
        if self.stepper is None or not self.stepping_current():
            return self.restart()
        step = self.stepper.step()
        if step.error is not None:
            self.current = None
            return f"stopped: {step.error}"
        if step.done:
            self.current = None
            return f"the motion returned after {step.instructions} instructions ({step.time:.3f} s)"
        self.current = self.block_at(step.pc)
        where = f"block {self.current}" if self.current is not None else f"{step.pc:05X}h"
        return f"at {where} after {step.instructions} instructions ({step.time:.3f} s)"


def _parse(text: str) -> object:
    try:
        return json.loads(text)
    except json.JSONDecodeError:
        return text  # a bare word: a label, an operand, a condition name


def _choices(kind: str, name: str, value: object) -> list[object] | None:
    """The values a field can take when they are a short list (a select), else None."""
    if name == "if":
        options: list[object] = list(CONDITION_NAMES.values())
    elif name == "op":
        options = list(VAR_OPS if kind == "variable_arith" else OPS)
    elif name == "field":
        options = list(SERVO_FIELDS)
    else:
        return None
    return options if value in options else [*options, value]


def build(ctx: UiContext, ed: Editor, on_change: Callable[[], None]) -> Callable[[], None]:
    """The panel; returns its refresh function (call it when the project or motion changes)."""
    view = ProgramView(ed)
    fields: dict[str, ui.input | ui.select] = {}

    def fail(exc: Exception) -> None:
        ui.notify(str(exc), type="negative", multi_line=True)

    def edit(fn: object, *args: object) -> bool:
        if ed.slot is None:
            return False
        try:
            ed.apply(fn, ed.slot, *args)  # type: ignore[arg-type]
        except (Rcb4Error, ValueError) as exc:
            fail(exc)
            return False
        on_change()
        return True

    with tid(ui.expansion("Program (every block)", icon="account_tree", value=True), "flow-panel"):
        with ui.row().classes("items-center"):
            kind_sel = tid(ui.select(list(KINDS), label="Kind", with_input=True), "flow-kind")
            kind_sel.classes("w-48")
            for label, icon, name, action in (
                ("Add after", "add", "flow-add", lambda: add()),
                ("Remove", "delete", "flow-remove", lambda: remove()),
                ("Up", "arrow_upward", "flow-up", lambda: move(-1)),
                ("Down", "arrow_downward", "flow-down", lambda: move(1)),
            ):
                tid(ui.button(label, icon=icon).props("dense"), name).on_click(action)
            target_sel = tid(ui.select({}, label="Branch to", with_input=True), "flow-target")
            target_sel.classes("w-64")
            tid(ui.button("Connect", icon="call_made").props("dense"), "flow-connect").on_click(
                lambda: connect()
            )
            tid(ui.button("Step", icon="skip_next").props("dense"), "flow-step").on_click(
                lambda: stepping(view.step)
            )
            tid(ui.button("Restart", icon="replay").props("dense"), "flow-restart").on_click(
                lambda: stepping(view.restart)
            )
            step_status = tid(ui.label(""), "flow-step-status").classes("text-xs")
        with ui.row().classes("w-full no-wrap items-start"):
            chart = tid(ui.html("", sanitize=False), "flow-chart")
            chart.style("max-height: 640px; overflow-y: auto")
            chart.on(
                "click",
                lambda e: select(int(e.args)) if e.args not in (None, "") else None,
                js_handler="(e) => emit(e.target.closest('[data-block]')?.dataset.block ?? '')",
            )
            form = ui.column().classes("grow")
            bind_refresh = bind_panel.build(ed, on_change)
    settings_refresh = settings_panel.build(ctx, ed, on_change)

    def select(index: int) -> None:
        view.selected = index
        refresh()

    def add() -> None:
        kind = kind_sel.value
        if kind not in KINDS:
            fail(ValueError("choose the kind of block to add"))
            return
        at = len(view.blocks()) if view.selected is None else view.selected + 1
        if edit(insert_block, at, kind):
            view.selected = at
            refresh()

    def remove() -> None:
        if view.selected is not None and edit(remove_block, view.selected):
            view.selected = None
            refresh()

    def move(by: int) -> None:
        if view.selected is not None and edit(move_block, view.selected, view.selected + by):
            view.selected += by
            refresh()

    def connect() -> None:
        if view.selected is not None and target_sel.value is not None:
            edit(connect_block, view.selected, int(target_sel.value))

    def apply_fields() -> None:
        if view.selected is None:
            return
        values = {
            k: box.value if isinstance(box, ui.select) else _parse(box.value or "")
            for k, box in fields.items()
            if box.value not in ("", None)
        }
        if not edit(set_block, view.selected, values):
            draw_form(view.blocks())  # refused: the form shows the block's values again
        elif values.get("frames") == 0:  # the wire's range (files hold it), not the documented
            ui.notify(
                "frames 0 kept: outside the documented 1..255 (the board moves in one period "
                "or at once; `project check` warns speed-zero)",
                type="warning",
            )

    def stepping(move: Callable[[], str]) -> None:
        """Step or restart the single-stepped program and show where it is."""
        try:
            step_status.text = move()
        except (Rcb4Error, ValueError) as exc:
            fail(exc)
        refresh()

    def draw_form(blocks: tuple[Block, ...]) -> None:
        form.clear()
        fields.clear()
        if view.selected is None or not 0 <= view.selected < len(blocks):
            return
        b = blocks[view.selected]
        with form:
            ui.label(f"block {view.selected}: {b.kind}" + (f" ({b.label})" if b.label else ""))
            if b.kind in BLOCK_HINTS:
                tid(ui.label(BLOCK_HINTS[b.kind]), "flow-hint").classes("text-xs text-slate-600")
            for name, value in b.fields.items():
                choices = _choices(b.kind, name, value)
                element: ui.input | ui.select
                if choices is not None:
                    element = ui.select(choices, label=name, value=value)
                else:
                    text = (
                        value if isinstance(value, str) else json.dumps(value, ensure_ascii=False)
                    )
                    element = ui.input(name, value=text)
                fields[name] = tid(element, f"flow-field-{name}").classes("w-full")
            tid(ui.button("Apply", icon="check").props("dense"), "flow-apply").on_click(
                apply_fields
            )

    def refresh() -> None:
        blocks = view.blocks()
        if view.selected is not None and view.selected >= len(blocks):
            view.selected = None
        if ed.session is None or not view.stepping_current():
            view.current = None
        chart.set_content(program_svg(blocks, view.selected, view.current) if blocks else "")
        target_sel.options = {i: f"{i} {block_text(b)}" for i, b in enumerate(blocks)}
        target_sel.value = None
        target_sel.update()
        draw_form(blocks)
        bind_refresh()
        settings_refresh()

    return refresh
