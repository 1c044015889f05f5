"""Physics: CPU time of the emulator driving a robot in MuJoCo, against the virtual time.

For the 17-axis KHR-3HV, the 22-axis KHR-3HV Ver.2 (built-in models) and the KXR build
with the most servos among Kondo's sample projects, the 30-axis KXR-L2L6A7H2G (kit builder:
6-axis legs, 7-axis arms, grippers, 2-axis head): an emulated board
set up for the robot's servos (``rcb4hv.physics.standalone.robot_board``) with a
``PhysicsBackend``; the robot stands on the floor and crouches and rises every 0.5 s
(RunConstFrameServo through ``Board.feed``, as a host sends them) for 10 virtual seconds,
output period 10 ms (the board's default), physics step ``rcb4hv.robot.mjcf.TIMESTEP``
(2 ms). ``ours_us`` is the CPU time of this process (``time.process_time``: the machine is
shared, and wall time measures the other jobs too), ``wire_us`` the virtual (real robot)
time; the target is 30x faster than real time on one core (ratio <= 1/30). Best of 3 runs.
Skipped without MuJoCo (the ``sim`` extra).
"""

from __future__ import annotations

import time
from typing import Any

from bench.bench_project import FIXTURE

VIRTUAL_S = 10.0
MOVE_S = 0.5
TARGET = 1 / 30


def _crouch(model: Any, depth: float) -> dict[int, int]:
    """Servo values of a crouch ``depth`` rad deep: knees bent 2x, hips and ankles back."""
    angles = {}
    for j in model.joints:
        if "knee" in j.name:
            angles[j.name] = 2 * depth
        elif "hip_pitch" in j.name or "ankle_pitch" in j.name:
            angles[j.name] = -depth
    values: dict[int, int] = model.motion_values(angles)
    return values


def _one(name: str, virtual_s: float = VIRTUAL_S) -> tuple[float, float, bool]:
    from rcb4hv.physics import PhysicsBackend, PhysicsWorld
    from rcb4hv.physics.standalone import robot_board
    from rcb4hv.protocol import RunConstFrameServo
    from rcb4hv.robot.builtin import load_robot

    model = load_robot(name)
    board = robot_board(model)
    world = PhysicsWorld(model)
    world.place({})
    backend = PhysicsBackend(board, world)
    poses = [_crouch(model, 0.3), _crouch(model, 0.0)]
    frames = round(MOVE_S / board.output_period)
    t0 = time.process_time()
    k = 0
    while board.now < virtual_s - 1e-9:
        board.feed(RunConstFrameServo(frames, sorted(poses[k % 2].items())).encode())
        board.run_for(MOVE_S)
        k += 1
    backend.sync()
    wall = time.process_time() - t0
    upright = world.base().tilt < 0.5
    return wall, backend.time, upright


def run(quick: bool = False) -> list[dict[str, Any]]:
    try:
        import mujoco  # noqa: F401
    except ImportError:
        print("(skipping bench_physics: MuJoCo is not installed; pip install 'rcb4hv[sim]')")
        return []
    from rcb4hv.robot.mjcf import TIMESTEP

    step_ms = TIMESTEP * 1000
    rows = []
    robots = (("khr3hv", 17), ("khr3hv-22", 22), ("kxr:L2L6A7H2G", 30))
    for name, axes in robots[:1] if quick else robots:
        best, virtual, upright = float("inf"), 0.0, True
        for _ in range(1 if quick else 3):
            wall, v, up = _one(name, MOVE_S if quick else VIRTUAL_S)
            if wall < best:
                best, virtual, upright = wall, v, up
        rows.append(
            {
                "name": f"physics: {name} ({axes} axes) crouching, {step_ms:g} ms step",
                "ours_us": best * 1e6,
                "wire_us": virtual * 1e6,
                "ratio": best / virtual,
                "target": TARGET,
                "note": f"{virtual / best:.1f}x real time ({virtual:.1f} s virtual in "
                f"{best:.3f} s CPU); {'upright' if upright else 'FELL'} at the end",
            }
        )
    if FIXTURE.is_file():
        rows.append(_fixture_row(quick))
    return rows


def _fixture_row(quick: bool) -> dict[str, Any]:
    """The fixture project's motions played as ``project simulate --physics`` plays them
    (``run_motions``: each motion on a copy of the robot booted and settled once, held on
    its button for 3 s): CPU time against the virtual time the report covers, each motion's
    boot and settling included (they are its start state, computed once)."""
    from rcb4hv.cli.project_common import load_image
    from rcb4hv.project.run import run_motions
    from rcb4hv.robot.builtin import load_robot

    image, layout, names = load_image(FIXTURE)
    robot = load_robot("kxr-l2-gripper")
    slots = sorted(names)[:3] if quick else sorted(names)
    best, virtual = float("inf"), 0.0
    for _ in range(1 if quick else 2):
        t0 = time.process_time()
        run = run_motions(image, slots, names=names, robot=robot, motion_layout=layout)
        cpu = time.process_time() - t0
        if cpu < best:
            best, virtual = cpu, run.virtual_s
    return {
        "name": f"physics: the fixture's {len(slots)} motions (project simulate --physics)",
        "ours_us": best * 1e6,
        "wire_us": virtual * 1e6,
        "ratio": best / virtual,
        "target": TARGET,
        "note": f"{virtual / best:.1f}x real time ({virtual:.1f} s virtual in {best:.2f} s CPU)",
    }


if __name__ == "__main__":
    for r in run():
        print(r)
