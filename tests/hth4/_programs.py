"""A project holding one motion (slot 1) for the program tests."""

from __future__ import annotations

from rcb4hv.hth4 import Motion, Project
from rcb4hv.hth4.model import motion_rom_address


def one_motion_project(frames: tuple[bytes, ...], slots: int = 3) -> Project:
    """A project with ``slots`` slots at the 2.2 addresses; slot 1 holds ``frames``."""
    motions = tuple(
        Motion(
            key=f"M{n:03d}",
            number=n - 1,
            name=f"m{n}",
            date="2020-01-01T00:00:00",
            frames=frames if n == 1 else (),
            address=motion_rom_address(n),
        )
        for n in range(1, slots + 1)
    )
    return Project(motions=motions)
