"""The accelerometer reaches its AD channels as the fixture's direction-detect motion
expects: lying on the back it plays "get up from the back", on the front "get up from the
front", standing it just returns."""

from __future__ import annotations

from pathlib import Path

import pytest

from rcb4hv.cli.project_common import load_image
from rcb4hv.emulator import EmulatorConfig
from rcb4hv.physics import DEFAULT_SENSORS
from rcb4hv.project.physics_sim import PhysicsSimulator, StartPose
from rcb4hv.robot.builtin import load_builtin
from tests.physics.conftest import PROJECT

IMAGE, LAYOUT, NAMES = load_image(Path(PROJECT))
KXR = load_builtin("kxr-l2-gripper")
DETECT, FROM_BACK, FROM_FRONT = 17, 15, 16  # XL2G_117, XL2G_115, XL2G_116


def ad(sim: PhysicsSimulator, channel: int) -> int:
    return sim.board.ad_input(channel)


@pytest.mark.parametrize(
    ("start", "ad5"),
    [("upright", (315, 335)), ("on_back", (520, 540)), ("on_front", (110, 130))],
)
def test_the_accelerometer_reads_gravity_on_ad5(start: StartPose, ad5: tuple[int, int]) -> None:
    sim = PhysicsSimulator(IMAGE, KXR, motion_layout=LAYOUT, start=start)
    sim.boot()
    assert ad5[0] <= ad(sim, DEFAULT_SENSORS.accel_x or 0) <= ad5[1]
    # lying flat on the back or front, nothing along the left axis
    assert abs(ad(sim, 3) - DEFAULT_SENSORS.accel_zero) < 15


@pytest.mark.parametrize(
    ("start", "plays"), [("on_back", FROM_BACK), ("on_front", FROM_FRONT), ("upright", None)]
)
def test_the_direction_detect_motion_sees_how_the_robot_lies(
    start: StartPose, plays: int | None
) -> None:
    # the fixture's comparisons branch when either enabled flag matches (docs/physics.md)
    config = EmulatorConfig(virtual_servos=KXR.indices, branch_condition="or")
    sim = PhysicsSimulator(IMAGE, KXR, motion_layout=LAYOUT, start=start, config=config)
    sim.boot()
    jumped: set[int] = set()
    targets = {LAYOUT.address(FROM_BACK): FROM_BACK, LAYOUT.address(FROM_FRONT): FROM_FRONT}

    def watch(_: object) -> None:
        for address, slot in targets.items():
            if address <= sim.board.pc < address + 0x800:
                jumped.add(slot)

    assert sim.backend is not None
    sim.backend.observers.append(watch)
    res = sim.play(LAYOUT.address(DETECT), limit=20)
    assert res.status == "completed"
    assert jumped == ({plays} if plays else set())
