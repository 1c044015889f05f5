"""``rcb4hv project robust``: fall probability of motions over many physics trials."""

from __future__ import annotations

import json
from pathlib import Path

import click

from rcb4hv.cli._util import MOTION_SLOT, handle_errors
from rcb4hv.cli.gait_cmd import RAY


def register(cli: click.Group) -> None:
    group = cli.commands.get("project")
    if not isinstance(group, click.Group):
        raise RuntimeError("rcb4hv.cli.project_cmd must be registered before project_robust_cmd")
    group.add_command(robust_command)


@click.command("robust")
@click.argument("file", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--motion", "motions", type=MOTION_SLOT, multiple=True, help="Slot (repeatable).")
@click.option("--trials", type=click.IntRange(min=1), default=20, show_default=True)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True)
@click.option("--robot", default=None, help="Robot model (default: detected from FILE).")
@click.option("--workers", type=click.IntRange(min=1), default=None, help="Processes (cores).")
@RAY
@click.option("--json", "as_json", is_flag=True, help="Print the figures as JSON.")
@handle_errors
def robust_command(
    file: Path, motions: tuple[int, ...], trials: int, seed: int, robot: str | None,
    workers: int | None, ray_address: str | None, as_json: bool,
) -> None:  # fmt: skip
    """Play motions of FILE in TRIALS physics runs, each with the unmeasured constants drawn
    from their documented ranges (docs/gait.md), and report the fall probability (Wilson 95 %
    interval) and the quartiles of displacement and turn per motion."""
    from tqdm import tqdm

    from rcb4hv.cli.project_common import image_slots, load_file
    from rcb4hv.cli.project_physics import physics_robot
    from rcb4hv.project.robust import robust

    loaded = load_file(file)
    image, layout = loaded.image, loaded.layout
    loaded.check_slots(motions)
    slots = list(motions) or image_slots(image, layout)
    model = physics_robot(loaded.project, image, robot)
    # no bar for --json, nor on a stderr that is no terminal (tqdm's disable=None)
    with tqdm(total=trials, unit="trial", disable=True if as_json else None, leave=False) as bar:
        rows = robust(
            image, slots, layout=layout, robot=model, trials=trials, seed=seed, workers=workers,
            use_ray=ray_address is not None, ray_address=ray_address or None, progress=bar.update,
        )  # fmt: skip
    if as_json:
        click.echo(json.dumps({"robot": model.name, "seed": seed, "motions": rows}, indent=2))
        return
    for r in rows:
        lo, hi = r["ci"]
        dx, dy, dyaw = r["dx_m"], r["dy_m"], r["dyaw_deg"]
        click.echo(
            f"motion {r['slot']}: falls {r['falls']}/{r['trials']} "
            f"p={r['fall_probability']:.2f} [{lo:.2f}, {hi:.2f}]; "
            f"dx {dx['median']:+.3f} m [{dx['q1']:+.3f}, {dx['q3']:+.3f}], "
            f"dy {dy['median']:+.3f} m, turn {dyaw['median']:+.1f}°"
        )
