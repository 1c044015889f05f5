"""The assembler's error type: :class:`rcb4hv.errors.AsmError` (kept importable here)."""

from __future__ import annotations

from rcb4hv.errors import AsmError

__all__ = ["AsmError"]
