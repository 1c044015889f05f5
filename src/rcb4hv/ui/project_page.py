"""Project page: open a HeartToHeart4 project (.h4p) and look inside it: motions, servo
table, button bindings, `project check` findings, and one motion's disassembly and
flowchart. Simulation, build, upload and downloads are in :mod:`rcb4hv.ui.project_actions`,
the 3D preview of a motion in :mod:`rcb4hv.ui.preview`."""

from __future__ import annotations

from nicegui import events, ui

from rcb4hv.asm import disassemble_frames
from rcb4hv.errors import Rcb4Error
from rcb4hv.hth4 import Project, button_label, parse_motion_xml
from rcb4hv.hth4.flowchart_model import Flowchart
from rcb4hv.hth4.project import parse_named_project
from rcb4hv.ui import preview, project_actions
from rcb4hv.ui.checks import check_rows
from rcb4hv.ui.context import UiContext, tid
from rcb4hv.ui.flowsvg import canvas_svg, motion_svg

__all__ = ["build", "flowchart_title", "load_upload", "motion_table", "servo_table"]


def motion_table(project: Project) -> list[dict[str, object]]:
    return [
        {
            "slot": m.slot,
            "address": f"{m.address:05X}",
            "name": m.name or "",
            "frames": len(m.frames),
            "bytes": m.code_size,
            "button": button_label(m.button_data) if m.button_data else "",
        }
        for m in project.used_motions
    ]


def servo_table(project: Project) -> list[dict[str, object]]:
    return [
        {
            "ics": s.device_number,
            "name": s.name or s.key,
            "id": s.id,
            "port": s.port,
            "trim": s.trim,
            "home": s.position,
        }
        for s in project.servos
        if s.in_use
    ]


def load_upload(ctx: UiContext, name: str, data: bytes) -> Project:
    """Parse an uploaded file (size-checked) and make it the open project."""
    if len(data) > ctx.max_upload:
        raise ValueError(f"{name}: {len(data):,} bytes; the limit is {ctx.max_upload:,}")
    project = parse_named_project(data, name)
    ctx.set_project(project, name)
    return project


DISASM_MIN_PX = 420
_DISASM_STYLE = f"flex: 1 1 {DISASM_MIN_PX}px; min-width: min({DISASM_MIN_PX}px, 100%)"
_DISASM_CSS = ".rcb4hv-disasm pre, .rcb4hv-disasm code { white-space: pre-wrap; }"


def flowchart_title(name: str, chart: Flowchart) -> str:
    """The title over an uploaded flowchart ``.xml``."""
    return f"{name}: flowchart, {len(chart.activities)} boxes, {len(chart.lines)} lines"


def _columns(*names: str) -> list[dict[str, str]]:
    return [{"name": n, "label": n, "field": n, "align": "left"} for n in names]


def build(ctx: UiContext) -> None:
    ui.add_css(_DISASM_CSS)

    # a refused file leaves its upload box empty: the box listed it with a tick as if it
    # were open (the summary names the project that is)
    async def uploaded(e: events.UploadEventArguments) -> None:
        if e.file.size() > ctx.max_upload:
            ui.notify(f"{e.file.name}: over the {ctx.max_upload:,}-byte limit", type="negative")
            project_box.reset()
            return
        try:
            load_upload(ctx, e.file.name, await e.file.read())
        except (Rcb4Error, ValueError) as exc:  # the message starts with the file's name
            ui.notify(f"cannot open {exc}", type="negative", multi_line=True)
            project_box.reset()
            return
        ui.notify(f"opened {e.file.name}")

    async def flowchart_uploaded(e: events.UploadEventArguments) -> None:
        try:
            chart = parse_motion_xml(await e.file.read())
        except (Rcb4Error, ValueError) as exc:
            ui.notify(f"cannot open {e.file.name}: {exc}", type="negative", multi_line=True)
            flowchart_box.reset()
            return
        motions.selected = []  # the chart shown is the file's, not a motion's
        detail_title.text = flowchart_title(e.file.name, chart)
        detail_asm.content = ""
        detail_svg.set_content(canvas_svg(chart))

    with ui.row().classes("items-start"):
        project_box = tid(
            ui.upload(
                label="Open .h4p project",
                auto_upload=True,
                max_file_size=ctx.max_upload,
                on_upload=uploaded,
                on_rejected=lambda: ui.notify(
                    f"not opened: a project is a .h4p file of at most {ctx.max_upload // 2**20} MB "
                    "(a flowchart .xml goes to the next box)",
                    type="warning",
                ),
            ).props('accept=".h4p"'),
            "project-upload",
        )
        flowchart_box = tid(
            ui.upload(
                label="Show a flowchart .xml",
                auto_upload=True,
                max_file_size=ctx.max_upload,
                on_upload=flowchart_uploaded,
                on_rejected=lambda: ui.notify(
                    "not shown: a flowchart is an .xml file of at most "
                    f"{ctx.max_upload // 2**20} MB",
                    type="warning",
                ),
            ).props('accept=".xml"'),
            "flowchart-upload",
        )
        with ui.column():
            summary = tid(ui.label("no project open"), "project-summary")
            findings_summary = tid(ui.label(""), "project-check-summary")
    with ui.tabs() as tabs:
        t_motions = ui.tab("Motions")
        t_servos = ui.tab("Servos")
        t_bind = ui.tab("Bindings")
        t_check = ui.tab("Check")
        t_actions = ui.tab("Simulate / upload")
        t_preview = tid(ui.tab("3D preview"), "project-tab-preview")
    with ui.tab_panels(tabs, value=t_motions).classes("w-full"):
        with ui.tab_panel(t_motions), ui.row().classes("w-full no-wrap items-start"):
            motions = tid(
                ui.table(
                    columns=_columns("slot", "address", "name", "frames", "bytes", "button"),
                    rows=[],
                    row_key="slot",
                    selection="single",
                    pagination=0,
                )
                .props("dense flat virtual-scroll")
                .style("max-height: 600px"),
                "project-motions",
            )
            with ui.column().classes("grow"):
                detail_title = tid(ui.label("select a motion"), "project-motion-title")
                # the flowchart and the disassembly side by side when there is room, else
                # one above the other; long lines (a pose of 18 servos) wrap, never cut
                with ui.row().classes("w-full items-start"):
                    detail_svg = tid(ui.html("", sanitize=False), "project-flowchart")
                    detail_asm = tid(ui.code("", language="text"), "project-disasm")
                    detail_asm.classes("rcb4hv-disasm").style(_DISASM_STYLE)
        with ui.tab_panel(t_servos):
            servos = tid(
                ui.table(
                    columns=_columns("ics", "name", "id", "port", "trim", "home"),
                    rows=[],
                    row_key="ics",
                ).props("dense flat"),
                "project-servos",
            )
        with ui.tab_panel(t_bind):
            bindings = tid(
                ui.table(
                    columns=_columns("button", "slot", "name", "compare"), rows=[], row_key="slot"
                ).props("dense flat"),
                "project-bindings",
            )
        with ui.tab_panel(t_check):
            checks = tid(
                ui.table(
                    columns=_columns("#", "severity", "code", "slot", "name", "address", "reason"),
                    rows=[],
                    row_key="#",
                ).props("dense flat"),
                "project-checks",
            )
        with ui.tab_panel(t_actions):
            project_actions.build(ctx, motions)
        with ui.tab_panel(t_preview):
            preview.build(ctx, motions)

    def show_motion(slot: int) -> None:
        project = ctx.project
        if project is None:
            return
        m = project.motion(slot)
        detail_title.text = f"M{slot:03d} {m.name} - {len(m.frames)} frames at {m.address:05X}h"
        detail_asm.content = disassemble_frames(m.frames, m.address)
        detail_svg.set_content(motion_svg(m.frames, m.address))

    motions.on_select(lambda e: show_motion(int(e.selection[0]["slot"])) if e.selection else None)

    def redraw() -> None:
        project = ctx.project
        if project is None:
            return
        used = project.used_motions
        summary.text = (
            f"{ctx.project_name}: {project.project_title or project.name or ''} - "
            f"{len(used)} motions, {len(servo_table(project))} servos, "
            f"system register {project.system_register:04X}h"
        )
        motions.rows = motion_table(project)
        servos.rows = servo_table(project)
        bindings.rows = [
            {
                "button": button_label(m.button_data),
                "slot": m.slot,
                "name": m.name or "",
                "compare": m.compare_type,
            }
            for m in used
            if m.button_data
        ]
        try:
            rows, text = check_rows(project)
        except Exception as exc:  # a lint crash must not hide the project
            rows, text = [], f"project check failed: {exc}"
        checks.rows = rows
        findings_summary.text = f"project check: {text}"
        for t in (motions, servos, bindings, checks):
            t.update()

    ctx.on_project(redraw)
    redraw()
