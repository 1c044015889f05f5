"""The assembler's error type."""

from __future__ import annotations

__all__ = ["AsmError"]


class AsmError(ValueError):
    """A source line that does not assemble; carries the 1-based ``line`` and ``column``."""

    def __init__(self, message: str, line: int, column: int = 1, source: str | None = None):
        self.message = message
        self.line = line
        self.column = column
        self.source = source
        super().__init__(f"line {line}, column {column}: {message}")
