"""How sensitive the physics verdicts are to the model's chosen constants (``make sensitivity``).

For each chosen figure (:class:`rcb4hv.physics.PhysicsOptions`: stretch -> stiffness, the
servos' stall torque, speed cap,
free-servo damping, armature, the controller's braking, foot friction, gyro and accelerometer
scales) and each factor (default x0.5, x0.75, x1.33, x2) it plays every motion of each project
with physics, as ``rcb4hv project simulate --physics`` does (a fresh boot, standing, per
motion), and lists the motions whose verdict differs from the run with the documented figures. A
verdict is what a user reads off a motion: fell (and how it lies), or the end pose, the way it
went (the larger of dx, dy when at least 5 cm) and the way it turned (when at least 5°).

Usage::

    python -m bench.sensitivity [PROJECT.h4p ...] [--extra DIR] [--factors 0.5,0.75,1.33,2]
                                [--figure NAME ...] [--motion SLOT ...] [--out FILE]

Without projects: the fixture (``../shared/fixtures/hth4/kxr-l2-hac``). ``--extra DIR`` adds
every ``.h4p`` below DIR (e.g. local copies of Kondo's sample projects, never committed). The
table (markdown) goes to stdout, and to FILE with ``--out``. About 10 CPU-minutes for the
fixture: run it under ``nice``.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from dataclasses import fields
from pathlib import Path

from rcb4hv.cli.project_common import load_file
from rcb4hv.cli.project_physics import physics_robot
from rcb4hv.physics import DEFAULT_SENSORS, PhysicsOptions
from rcb4hv.physics.options import NOT_FACTORS
from rcb4hv.project.physicsresult import PhysicsOutcome
from rcb4hv.project.run import run_motions
from rcb4hv.robot.mjcf import FLOOR_FRICTION, TORSIONAL_FRICTION
from rcb4hv.robot.servos import FREE_DAMPING_FRACTION, FULL_TORQUE_ERROR_DEG, MOTOR_TIME_CONSTANT

REPO = Path(__file__).resolve().parents[1]
FIXTURE = REPO.parent / "shared/fixtures/hth4/kxr-l2-hac/HAC_KXR_HTH4_project.h4p"
MOVED_M = 0.05  # a displacement below this is "in place"
TURNED_DEG = 5.0  # a turn below this is "no turn"
FIGURES = {
    "stiffness": f"stretch -> stiffness ({FULL_TORQUE_ERROR_DEG:g}° error at stall, stretch 127)",
    "torque": "servo stall torque (13.9 kgf·cm, the KRS-3304R2's catalogue figure)",
    "speed_cap": "speed cap (ICS speed / 127 x no-load speed)",
    "free_damping": f"free-servo damping ({FREE_DAMPING_FRACTION:g} x back-EMF)",
    "armature": f"armature ({MOTOR_TIME_CONSTANT * 1000:g} ms motor time constant)",
    "servo_damping": "servo controller's braking (critically damped bare servo at stretch 127)",
    "friction": f"foot friction ({FLOOR_FRICTION:g})",
    "torsional_friction": f"foot spin friction ({TORSIONAL_FRICTION:g} m, MuJoCo's default)",
    "gyro_scale": f"gyro scale ({DEFAULT_SENSORS.gyro_counts_per_dps:g} counts per °/s)",
    "mass": "link masses and inertias (the models' estimates)",
    "accel_scale": f"accelerometer scale ({DEFAULT_SENSORS.accel_counts_per_g:.0f} counts per g)",
}


def verdict(o: PhysicsOutcome) -> str:
    """What a user reads off one motion's outcome (see the module docstring)."""
    if o.fell:
        return f"fell {o.end_pose}"
    parts = [o.end_pose]
    if max(abs(o.dx_m), abs(o.dy_m)) >= MOVED_M:
        if abs(o.dx_m) >= abs(o.dy_m):
            parts.append("forward" if o.dx_m > 0 else "back")
        else:
            parts.append("left" if o.dy_m > 0 else "right")
    if abs(o.dyaw_deg) >= TURNED_DEG:
        parts.append("turns left" if o.dyaw_deg > 0 else "turns right")
    return ", ".join(parts)


def verdicts(
    path: Path, options: PhysicsOptions, slots: Sequence[int] = ()
) -> dict[int, tuple[str, str]]:
    """``{slot: (name, verdict)}`` of every motion of the project at ``path`` (of ``slots``
    when given)."""
    f = load_file(path)
    model = physics_robot(f.project, f.image, None)
    slots = sorted(slots or f.names)
    run = run_motions(
        f.image, slots, names=f.names, motion_layout=f.layout, robot=model, options=options
    )
    return {r.result.slot or 0: (r.result.name, verdict(r.outcome)) for r in run.motions}


def flips(base: dict[int, tuple[str, str]], other: dict[int, tuple[str, str]]) -> list[str]:
    return [f"{slot}: {other[slot][1]}" for slot in sorted(base) if other[slot][1] != base[slot][1]]


def study(
    path: Path, factors: list[float], figures: Sequence[str] = (), slots: Sequence[int] = ()
) -> list[str]:
    """The markdown section of one project: every figure of :data:`FIGURES` (or ``figures``),
    every motion (or ``slots``)."""
    t0 = time.process_time()
    base = verdicts(path, PhysicsOptions(), slots)
    lines = [
        f"### {path.name}",
        "",
        "With the documented figures:",
        "",
        "| slot | motion | verdict |",
        "|---|---|---|",
    ]
    lines += [f"| {slot} | {name} | {v} |" for slot, (name, v) in sorted(base.items())]
    lines += [
        "",
        "Motions whose verdict flips (their slots; the new verdicts below):",
        "",
        "| constant | " + " | ".join(f"x{f:g}" for f in factors) + " |",
        "|---|" + "---|" * len(factors),
    ]
    details: list[str] = []
    for f in fields(PhysicsOptions):
        if f.name in NOT_FACTORS or f.name not in FIGURES or (figures and f.name not in figures):
            continue
        cells = []
        for factor in factors:
            changed = flips(base, verdicts(path, PhysicsOptions(**{f.name: factor}), slots))
            cells.append(", ".join(c.split(":")[0] for c in changed) if changed else "none")
            if changed:
                details.append(f"- {f.name} x{factor:g}: " + "; ".join(changed))
            print(f"  {f.name} x{factor:g}: {len(changed)} flip(s)", file=sys.stderr)
        lines.append(f"| {FIGURES[f.name]} | " + " | ".join(cells) + " |")
    lines += ["", *details]
    cpu = time.process_time() - t0
    lines += ["", f"({len(base)} motions, {cpu / 60:.1f} CPU-minutes)", ""]
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("projects", nargs="*", type=Path)
    ap.add_argument("--extra", type=Path, help="also every .h4p below this directory")
    ap.add_argument("--factors", default="0.5,0.75,1.33,2")
    ap.add_argument("--out", type=Path)
    ap.add_argument(
        "--figure", action="append", choices=sorted(FIGURES), help="only this figure (repeatable)"
    )
    ap.add_argument("--motion", action="append", type=int, help="only this slot (repeatable)")
    args = ap.parse_args(argv)
    factors = [float(v) for v in args.factors.split(",")]
    projects = list(args.projects) or [FIXTURE]
    if args.extra is not None:
        projects += sorted(args.extra.rglob("*.h4p"))
    lines: list[str] = []
    for path in projects:
        print(f"{path}:", file=sys.stderr)
        lines += study(path, factors, args.figure or (), args.motion or ())
    text = "\n".join(lines)
    print(text)
    if args.out is not None:
        args.out.write_text(text + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
