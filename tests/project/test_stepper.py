"""Single-stepping a motion in the emulator: one instruction per step, the program counter
at each instruction of the path the motion takes."""

from __future__ import annotations

from pathlib import Path

from rcb4hv.hth4 import load_project
from rcb4hv.hth4.blocks import block_spans
from rcb4hv.project.relocate import project_image
from rcb4hv.project.stepper import MotionStepper

TURN_LEFT = 69


def test_turn_left_steps_through_its_blocks(kxr_project_path: Path) -> None:
    project = load_project(kxr_project_path)
    image, layout = project_image(project)
    motion = project.motion(TURN_LEFT)
    starts = [motion.address]
    for e in motion.frames:
        starts.append(starts[-1] + len(e))
    stepper = MotionStepper(image, motion_layout=layout)
    first = stepper.begin(motion.address)
    pcs = [first.pc]
    while True:
        step = stepper.step()
        if step.done or step.error:
            break
        pcs.append(step.pc)
    assert step.error is None and step.instructions == len(pcs)
    # three poses, the button compare and its branch (no button: not taken), the home pose,
    # the RETURN; every step one entry further
    assert pcs == starts[:7]
    assert [n for _, n in block_spans(motion)][:4] == [1, 1, 1, 2]
    assert step.time > first.time + 0.4  # the poses took their frames
