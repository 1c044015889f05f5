"""MkDocs hook: the docstrings use Sphinx cross-reference roles (``:class:`~rcb4hv.x.Y```),
which mkdocstrings renders as text. Turn them into links to the API reference when
mkdocs-autorefs knows the object (``optional``: plain code otherwise), showing the short name
for ``~`` references as Sphinx does."""

from __future__ import annotations

import re
from typing import Any

ROLE = re.compile(r":(?:class|meth|func|mod|data|attr|exc|obj):<code>(~?)([\w.]+)(\(\))?</code>")


def _replace(m: re.Match[str]) -> str:
    tilde, target, call = m.group(1), m.group(2), m.group(3) or ""
    shown = target.rsplit(".", 1)[-1] if tilde else target
    if "." not in target:
        return f"<code>{shown}{call}</code>"
    return f'<autoref identifier="{target}" optional><code>{shown}{call}</code></autoref>'


def on_page_content(html: str, **kwargs: Any) -> str:
    return ROLE.sub(_replace, html)
