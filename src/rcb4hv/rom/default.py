"""The built-in default board: a KHR-3HV-like humanoid in the HeartToHeart4 2.2 layout.

17 servos (the ICS number is ``2 * ID + 0`` on SIO1-4, ``+ 1`` on SIO5-8):

* head: ID 0 -> ICS 0
* left arm IDs 1-3 and left leg IDs 5-9 on SIO1-4 -> ICS 2, 4, 6, 10, 12, 14, 16, 18
* right arm IDs 1-3 and right leg IDs 5-9 on SIO5-8 -> ICS 3, 5, 7, 11, 13, 15, 17, 19

Motion 1 raises both arms, waits for the pose, brings them back home and returns; motion 2
turns the head left and right. The triangle button (vector jump) calls motion 1, the circle
button motion 2. No startup motion (the stub at 3CB80h).

``default_image(LAYOUTS["2.1"])`` is the same board in an older layout (:mod:`rcb4hv.rom.older`).
"""

from __future__ import annotations

from typing import Final

from rcb4hv.protocol import Button, RunConstFrameServo, SystemRegister
from rcb4hv.rom.image import ImageDescription, Motion, ServoConfig, VectorPackage
from rcb4hv.rom.layout import HTH4_22, MotionLayout

__all__ = ["DEFAULT_ICS", "default_description", "default_image"]

HEAD: Final = (0,)
LEFT: Final = (2, 4, 6, 10, 12, 14, 16, 18)
RIGHT: Final = (3, 5, 7, 11, 13, 15, 17, 19)
DEFAULT_ICS: Final = tuple(sorted(HEAD + LEFT + RIGHT))
HOME: Final = 7500

# system register: ICS_F, ROM_F, VEC_F, 15 ms frames, COM 1,250,000 baud, ICS 1,250,000, LED
DEFAULT_SYSTEM_REGISTER: Final = SystemRegister(
    ics_output=True,
    rom_run=True,
    vector_jump=True,
    frame_code=SystemRegister.frame_code_for(15),
    baud_code=SystemRegister.baud_code_for(1_250_000),
    ics_baud_code=SystemRegister.baud_code_for(1_250_000),
    led=True,
).to_word()


def _pose(speed: int, changes: dict[int, int]) -> RunConstFrameServo:
    return RunConstFrameServo(speed, {k: changes.get(k, HOME) for k in DEFAULT_ICS})


def default_description(layout: MotionLayout = HTH4_22) -> ImageDescription:
    """The typed description of the default board (button targets in ``layout``)."""
    motion_address = layout.address
    raise_arms = {2: HOME + 2700, 3: HOME - 2700, 4: HOME + 300, 5: HOME - 300}
    motion1 = Motion(1, [_pose(20, raise_arms), _pose(20, {})])
    motion2 = Motion(2, [_pose(10, {0: HOME + 1500}), _pose(10, {0: HOME - 1500}), _pose(10, {})])
    return ImageDescription(
        system_register=DEFAULT_SYSTEM_REGISTER,
        servos=tuple(ServoConfig(ics, home=HOME) for ics in DEFAULT_ICS),
        vector_packages=(
            VectorPackage.button(Button.TRIANGLE, motion_address(1)),
            VectorPackage.button(Button.CIRCLE, motion_address(2)),
        ),
        title="rcb4hv default humanoid",
        motions=(motion1, motion2),
    )


def default_image(layout: MotionLayout = HTH4_22) -> bytes:
    """The 256 KB ROM image of the default board in ``layout`` (default HeartToHeart4 2.2)."""
    from rcb4hv.rom.older import build_image_for

    return build_image_for(default_description(layout), layout)
