"""Board page: link, version, system register, battery, ROM program state, reconnect."""

from __future__ import annotations

from nicegui import ui

from rcb4hv.session import BoardState
from rcb4hv.ui.context import UiContext, tid

__all__ = ["STALE_MARK", "build", "stale", "state_rows"]


def state_rows(state: BoardState) -> list[dict[str, str]]:
    """The Board page's table: one (field, value) row each."""
    sysreg = state.system
    rows = [
        ("link", state.url),
        ("connected", "yes" if state.connected else "no"),
        ("baud", f"{state.baudrate:,}" if state.baudrate else "-"),
        ("version", state.version or "-"),
        ("battery", f"{state.battery:.2f} V"),
        ("ROM program", "running" if state.rom_running else "stopped"),
        ("PC", f"{state.pc:06X}h"),
        ("call depth", str(state.call_depth)),
        ("current motion", "-" if state.motion is None else str(state.motion)),
        ("update flags", state.update_flags.hex(" ")),
        ("button word", f"{state.buttons:04X}h"),
        ("polls", str(state.polls)),
    ]
    if state.ad is not None:
        ad = state.ad
        rows += [
            (f"AD{ch}", f"input {i}, measured {m} (reference {r})")
            for ch, (i, m, r) in enumerate(zip(ad.inputs, ad.measured, ad.references, strict=True))
            if ch
        ]
    if sysreg is not None:
        d = sysreg.describe()
        rows.append(("system register", f"{d['word']}h"))
        rows += [(f"  {k}", str(v)) for k, v in d.items() if k != "word"]
    if stale(state):  # the last values read, not the board's now
        rows = [(k, v if k in _LIVE else f"{v} {STALE_MARK}") for k, v in rows]
    return [{"field": k, "value": v} for k, v in rows]


STALE_MARK = "(stale: link down)"
_LIVE = ("link", "connected", "polls")
"""The rows that are the dashboard's own, true while the link is down."""


def stale(state: BoardState) -> bool:
    """Whether the board's values shown are left over from before the link went down."""
    return not state.connected and state.polls > 0


def build(ctx: UiContext) -> None:
    session = ctx.session
    with ui.row().classes("items-center"):
        url = tid(ui.input("Port URL", value=session.url).classes("w-96"), "board-url")
        tid(ui.button("Reconnect", icon="refresh"), "board-reconnect").on_click(
            lambda: _reconnect(ctx, url.value)
        )
    note = tid(ui.label("").classes("text-orange-800"), "board-stale")
    table = tid(
        ui.table(
            columns=[
                {"name": "field", "label": "Field", "field": "field", "align": "left"},
                {"name": "value", "label": "Value", "field": "value", "align": "left"},
            ],
            rows=state_rows(session.state),
            row_key="field",
        ).props("dense flat"),
        "board-table",
    )

    def refresh() -> None:
        st = session.state
        note.text = (
            "The link is down: the values below are the last ones read, not the board's now."
            if stale(st)
            else ""
        )
        note.set_visibility(bool(note.text))
        table.classes(
            add="opacity-60" if stale(st) else "", remove="" if stale(st) else "opacity-60"
        )
        table.rows = state_rows(st)
        table.update()

    refresh()

    ui.timer(0.5, refresh)


def _reconnect(ctx: UiContext, url: str) -> None:
    url = (url or "").strip()
    if not url:
        ui.notify("give a port URL", type="warning")
        return
    ctx.session.reconnect(url)
    ui.notify(f"reconnecting to {url}")
