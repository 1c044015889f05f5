"""`project check` findings (:func:`rcb4hv.project.check.check_project`) as table rows."""

from __future__ import annotations

from rcb4hv.errors import RobotModelError
from rcb4hv.hth4 import Project
from rcb4hv.hth4.robotpick import project_model
from rcb4hv.project.check import check_project

__all__ = ["check_rows"]


def check_rows(project: Project) -> tuple[list[dict[str, object]], str]:
    """(finding rows, a one-line summary such as ``0 errors, 3 warnings``); joint limits are
    checked when the project's robot is detected (as ``project check`` does)."""
    try:
        model = project_model(project)
    except RobotModelError:
        model = None
    findings = check_project(project, model)
    rows: list[dict[str, object]] = []
    for i, f in enumerate(findings):
        row: dict[str, object] = {"#": i + 1}
        row.update({k: ("" if v is None else str(v)) for k, v in f.to_dict().items()})
        rows.append(row)
    errors = sum(1 for f in findings if f.severity == "error")
    return rows, f"{errors} errors, {len(findings) - errors} warnings"
