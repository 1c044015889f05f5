"""Remote bindings on the KRC pad's layout (part of the Editor page's program panel).

The pad's buttons, laid out as on the Remote page (:data:`rcb4hv.ui.remote_page.PAD`), toggle
the combination that starts the chosen motion; "Bind" stores it (an undoable edit, refused if
another motion has it unless the page's override is ticked; no button: unbind). The list
under the pad shows which motion every bound combination starts.
"""

from __future__ import annotations

from collections.abc import Callable

from nicegui import ui

from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import button_label
from rcb4hv.hth4.edit import bind_button
from rcb4hv.ui.context import tid
from rcb4hv.ui.editor_state import Editor
from rcb4hv.ui.remote_page import PAD

__all__ = ["bindings", "build"]

ON, OFF = "primary", "grey-5"


def bindings(ed: Editor) -> list[str]:
    """One line per bound motion: its buttons and the motion."""
    if ed.session is None:
        return []
    return [
        f"{button_label(m.button_data)} → M{m.slot:03d} {m.name or ''}"
        for m in ed.project.used_motions
        if m.button_data
    ]


def build(ed: Editor, on_change: Callable[[], None]) -> Callable[[], None]:
    """The pad; returns its refresh function."""
    chosen = [0]
    pads: dict[int, ui.button] = {}

    def toggle(bit: int) -> None:
        chosen[0] ^= bit
        paint()

    def bind() -> None:
        if ed.slot is None:
            return
        try:
            ed.apply(bind_button, ed.slot, chosen[0], force=ed.force)
        except (Rcb4Error, ValueError) as exc:
            ui.notify(str(exc), type="negative", multi_line=True)
        on_change()

    with ui.column().classes("gap-1"):
        ui.label("Remote buttons of this motion").classes("text-sm")
        for group in (PAD[0:4], PAD[4:8], PAD[8:12]):
            with ui.row().classes("gap-1"):
                for text, button, name in group:
                    b = tid(ui.button(text).props("dense"), f"bind-pad-{name}").classes("w-12")
                    b.on_click(lambda _e, bit=int(button): toggle(bit))
                    pads[int(button)] = b
        with ui.row().classes("items-center"):
            tid(ui.button("Bind", icon="gamepad").props("dense"), "bind-apply").on_click(bind)
            word = tid(ui.label(""), "bind-word").classes("text-xs")
        listing = tid(ui.label("").style("white-space: pre-line"), "bind-list").classes("text-xs")

    def paint() -> None:
        for bit, b in pads.items():
            b.props(f"color={ON if chosen[0] & bit else OFF}")
        word.text = f"{button_label(chosen[0]) or 'none'} ({chosen[0]:04X}h)"

    def refresh() -> None:
        chosen[0] = (
            0 if ed.session is None or ed.slot is None else (ed.project.motion(ed.slot).button_data)
        )
        paint()
        listing.text = "\n".join(bindings(ed))

    return refresh
