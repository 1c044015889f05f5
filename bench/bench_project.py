"""Project simulation: wall time to play every motion of the fixture project in virtual time.

Boots the fixture project's image in the emulator (virtual clock) and plays each of its 65
motions the way a host does (``rcb4hv.project.run.run_motions``, the one run API). ``ours_us``
is the wall time of the run, ``wire_us`` the virtual time it covers (both with the boot, which
is short); the target is 1000x faster
than real time (ratio <= 0.001). Best of 3 runs. Skipped when ../shared is absent.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

FIXTURE = (
    Path(__file__).resolve().parent.parent.parent
    / "shared/fixtures/hth4/kxr-l2-hac/HAC_KXR_HTH4_project.h4p"
)
TARGET = 0.001


def run(quick: bool = False) -> list[dict[str, Any]]:
    if not FIXTURE.is_file():
        print(f"(skipping bench_project: {FIXTURE} not found)")
        return []
    from rcb4hv import hth4
    from rcb4hv.project.image import build_project_image
    from rcb4hv.project.run import run_motions

    project = hth4.load_project(FIXTURE)
    image = build_project_image(project)
    motions = [m.slot for m in project.used_motions][: 3 if quick else None]
    best_wall, virtual, statuses = float("inf"), 0.0, ""
    for _ in range(1 if quick else 3):
        t0 = time.perf_counter()
        run = run_motions(image, motions)  # the boot included
        wall = time.perf_counter() - t0
        if wall < best_wall:
            best_wall = wall
            virtual = run.virtual_s
            statuses = ", ".join(f"{n} {s}" for s, n in sorted(run.summary().items()))
    return [
        {
            "name": f"project: simulate {len(motions)} fixture motions (virtual time)",
            "ours_us": best_wall * 1e6,
            "wire_us": virtual * 1e6,
            "ratio": best_wall / virtual,
            "target": TARGET,
            "note": f"{virtual:.1f} s virtual in {best_wall:.3f} s wall ({statuses})",
        }
    ]


if __name__ == "__main__":
    for r in run():
        print(r)
