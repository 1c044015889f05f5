"""rcb4hv: host library, CLI and firmware emulator for the Kondo RCB-4HV robot controller."""

from __future__ import annotations

__version__ = "0.1.0"

__all__ = ["__version__"]
