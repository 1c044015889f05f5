"""`project check` findings for the Project page, when :mod:`rcb4hv.project.check` exists.

The lint lives in its own module (``check_project(project) -> list[Finding]``); this adapter
turns findings into table rows and says plainly when the lint is not installed.
"""

from __future__ import annotations

import importlib
import logging
from typing import Any

from rcb4hv.hth4 import Project

__all__ = ["check_rows"]

log = logging.getLogger(__name__)


def check_rows(project: Project) -> tuple[list[dict[str, object]], str]:
    """(finding rows, a one-line summary)."""
    try:
        module: Any = importlib.import_module("rcb4hv.project.check")
    except ImportError:
        return [], "project check is not available in this version"
    findings = module.check_project(project)
    rows: list[dict[str, object]] = []
    for f in findings:
        d = f.to_dict()
        rows.append({k: ("" if v is None else str(v)) for k, v in d.items()})
    errors = sum(1 for f in findings if f.severity == "error")
    return rows, f"{errors} errors, {len(findings) - errors} warnings"
