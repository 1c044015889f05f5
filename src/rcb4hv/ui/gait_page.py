"""Walk page: generate a walk for the dashboard's robot model (``rcb4hv gait``), store it in
the open project (a new project for the model when none is open) and play it once in
physics, with the outcome shown; the Project page's 3D preview then plays it too."""

from __future__ import annotations

import asyncio
from dataclasses import dataclass
from typing import get_args

from nicegui import ui

from rcb4hv.gait.pattern import Direction
from rcb4hv.hth4 import Project
from rcb4hv.project.physics_sim import PhysicsOutcome
from rcb4hv.robot.model import RobotModel
from rcb4hv.ui.context import UiContext, tid

__all__ = ["GeneratedWalk", "build", "generate_walk"]


@dataclass(frozen=True)
class GeneratedWalk:
    project: Project
    slot: int
    commanded: float
    outcome: PhysicsOutcome | None


def generate_walk(
    project: Project | None, model: RobotModel, direction: Direction, steps: int,
    stride: float | None = None, turn: float | None = None,
) -> GeneratedWalk:  # fmt: skip
    """The walk in the first free slot of ``project`` (or of a new project for ``model``),
    played once in physics on ``model``."""
    from rcb4hv.gait.generate import default_params, walk
    from rcb4hv.gait.motion import period_ms, walk_motion
    from rcb4hv.hth4.keyframes import add_motion, free_slots
    from rcb4hv.hth4.newproject import new_project
    from rcb4hv.project.relocate import project_image, project_layout
    from rcb4hv.project.run import run_motions

    base = project if project is not None else new_project(model)
    free = free_slots(base)
    if not free:
        raise ValueError("the project has no free motion slot")
    params = default_params(model, direction, steps=steps, stride=stride, turn=turn)
    period = period_ms(base)
    motion = walk_motion(
        model, walk(model, params, period / 1000.0), slot=free[0], name=f"gait {direction}",
        period=period, layout=project_layout(base),
    ).motion  # fmt: skip
    out = add_motion(base, motion)
    image, layout = project_image(out)
    run = run_motions(image, [free[0]], motion_layout=layout, robot=model)
    return GeneratedWalk(out, free[0], params.commanded, run.motions[0].outcome)


def build(ctx: UiContext) -> None:
    ui.label("Generate a walk (ZMP preview control, docs/gait.md)").classes("text-h6")
    with ui.row().classes("items-center"):
        direction = tid(
            ui.select(list(get_args(Direction)), value="forward", label="Direction")
            .classes("w-40"), "gait-direction",
        )  # fmt: skip
        steps = tid(ui.number("Steps", value=4, min=1, max=40, step=1), "gait-steps")
        stride = tid(ui.number("Stride m (blank: default)", value=None, step=0.005), "gait-stride")
        go = tid(ui.button("Generate and simulate", icon="directions_walk"), "gait-go")
    status = tid(ui.label(""), "gait-status")

    async def generate() -> None:
        model = ctx.robot
        if model is None:
            ui.notify("no robot model: start the dashboard with --robot", type="warning")
            return
        go.disable()
        status.text = "generating and simulating..."
        try:
            made = await asyncio.to_thread(
                generate_walk, ctx.project, model, direction.value, int(steps.value or 1),
                float(stride.value) if stride.value else None,
            )  # fmt: skip
        except ValueError as exc:
            status.text = f"not generated: {exc}"
            ui.notify(f"not generated: {exc}", type="negative", multi_line=True)
            return
        finally:
            go.enable()
        ctx.set_project(made.project, ctx.project_name or f"{model.name}-walks.h4p")
        o = made.outcome
        unit = "°" if str(direction.value).startswith("turn") else " m"
        how = (
            "no physics outcome" if o is None else
            f"travelled {o.dx_m:+.3f} m forward, {o.dy_m:+.3f} m left, turned "
            f"{o.dyaw_deg:+.1f}°, {'fell' if o.fell else 'stayed up'} ({o.end_pose})"
        )  # fmt: skip
        status.text = f"motion {made.slot}: {made.commanded:.3g}{unit} commanded; {how}"

    go.on_click(generate)
