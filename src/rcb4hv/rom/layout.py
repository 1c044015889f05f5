"""Addresses of the HeartToHeart4 2.2 ROM image layout (spec section 11.2).

The fixed instruction slots at the start of the image copy the project's data images (further
up the ROM) into RAM, then fall into the main loop at :data:`MAIN_LOOP`. Motion ``n`` (1-120)
lives at :func:`motion_address`.

Where the spec gives only a region (the PIO direction switches at 0454h and the 25-byte
priority-motion checks), this module fixes the project's own choice:

* ``0454h`` holds an unconditional JUMP over 24 bytes reserved for PIO direction switches
  (no source shows their bytes, so none are generated; the reserved bytes stay erased),
* the 13 priority checks follow at :data:`PRIORITY_CHECKS` (25 bytes each:
  ``SUB NW <source> - value`` (9), ``CALL <motion> if <cond>`` (7), ``MOVE sysreg <- value`` (9)
  re-arming the system register after the motion), and an unused slot is a JUMP to the next
  slot followed by erased bytes,
* the JUMP back to :data:`MAIN_LOOP` sits at :data:`MAIN_LOOP_JUMP` (= 05B1h).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

from rcb4hv.protocol import ROM_SIZE as ROM_SIZE  # the board fact (rcb4hv.protocol.operands)
from rcb4hv.protocol.memory import ADDR

ERASED: Final = 0xFF

CONFIG_WRITE: Final = 0x00000
PIO_DIRECTION_WRITE: Final = 0x00009
PIO_DATA_WRITE: Final = 0x00012
AD_REFERENCE_COPY: Final = 0x0001B
SERVO_BLOCK_COPIES: Final = 0x00026
SERVO_BLOCK_COPY_COUNT: Final = 35
ALLOC_COPY: Final = 0x001A7
KRI3_ALLOC_COPY: Final = 0x001B2
KRI3_BLOCK_COPY: Final = 0x001BD
VECTOR_PACKAGE_COPIES: Final = 0x001C8
VECTOR_PACKAGE_COUNT: Final = 32
VECTOR_ADDRESS_COPY: Final = 0x00328
SYSTEM_REGISTER_COPY: Final = 0x00333
ALL_FREE: Final = 0x0033E
TIMER_WAIT: Final = 0x0038D
ALL_HOLD: Final = 0x003A6
ALL_HOME: Final = 0x003F5
STARTUP_CALL: Final = 0x00444
MAIN_LOOP: Final = 0x0044B
PIO_SWITCHES: Final = 0x00454
PIO_SWITCHES_SIZE: Final = 24
PRIORITY_CHECKS: Final = 0x0046C
PRIORITY_COUNT: Final = 13
PRIORITY_SIZE: Final = 25
MAIN_LOOP_JUMP: Final = 0x005B1

SYSTEM_REGISTER_IMAGE: Final = 0x005DC
ALLOC_IMAGE: Final = 0x005DE
SERVO_BLOCK_IMAGES: Final = 0x00626
SERVO_BLOCK_IMAGE_COUNT: Final = 36
AD_REFERENCE_IMAGE: Final = 0x008F6
KRI3_ALLOC_IMAGE: Final = 0x0090C
KRI3_BLOCK_IMAGE: Final = 0x0090E
KRI3_BLOCK_SIZE: Final = ADDR.KRI3_BLOCK_SIZE
VECTOR_ADDRESS_IMAGE: Final = 0x00919
VECTOR_PACKAGE_IMAGES: Final = 0x0091B
TITLE: Final = 0x00A1B
TITLE_SIZE: Final = 32
PRIORITY_IMAGES: Final = 0x00A3B


@dataclass(frozen=True, slots=True)
class MotionLayout:
    """Where a HeartToHeart4 image keeps its motions and main loop (spec 11.2)."""

    name: str
    motion_base: int
    motion_stride: int
    main_loop: int
    motion_count: int
    main_loop_end: int
    """First address after the main loop's instructions (its closing JUMP included)."""

    @property
    def version(self) -> str:
        """The HeartToHeart4 version named by :data:`LAYOUTS` (``2.2``, ``2.1``, ``1.3``)."""
        return self.name.removeprefix("hth4-")

    @property
    def motion_end(self) -> int:
        """First address after the last motion slot."""
        return self.motion_base + self.motion_stride * self.motion_count

    @property
    def startup_stub(self) -> int:
        """The RETURN the startup CALL targets when the project has no startup motion."""
        return self.motion_end

    @property
    def older(self) -> bool:
        """True for the layouts whose main loop is at 003FDh (:mod:`rcb4hv.rom.older`)."""
        return self.main_loop == OLDER_MAIN_LOOP

    def address(self, motion: int) -> int:
        """ROM address of ``motion`` (1-based)."""
        if isinstance(motion, bool) or not isinstance(motion, int):
            raise ValueError(f"motion numbers are ints, not {motion!r}")
        if not 1 <= motion <= self.motion_count:
            raise ValueError(f"motion {motion} out of range 1..{self.motion_count}")
        return self.motion_base + self.motion_stride * (motion - 1)

    def motion_at(self, pc: int) -> int | None:
        """The motion whose slot holds ROM address ``pc``, or None."""
        if pc < self.motion_base:
            return None
        n = (pc - self.motion_base) // self.motion_stride + 1
        return n if n <= self.motion_count else None


OLDER_MAIN_LOOP: Final = 0x003FD
OLDER_MAIN_LOOP_END: Final = 0x0056A

LAYOUTS: Final[dict[str, MotionLayout]] = {
    "2.2": MotionLayout("hth4-2.2", 0x0B80, 2048, 0x044B, 120, MAIN_LOOP_JUMP + 7),
    # 2.0/2.1: motion n at 0BB8h + 800h (n - 1) and the main loop at 003FDh. Both are what
    # the host libraries of that era use (libkondo4: RCB4_ADDR_MOT_BASE 3000, RCB4_MOT_SIZE
    # 2048, RCB4_ADDR_MAIN 03FDh; python-khr3hv: CALL 0BB8h + 800h n, PC <- 0003FDh) and
    # where a real project of that era stores its motions (Address 3000 + 2048 k). The boot
    # region around the main loop is this project's choice (rcb4hv.rom.older).
    "2.1": MotionLayout("hth4-2.1", 0x0BB8, 2048, OLDER_MAIN_LOOP, 120, OLDER_MAIN_LOOP_END),
    "2.0": MotionLayout("hth4-2.0", 0x0BB8, 2048, OLDER_MAIN_LOOP, 120, OLDER_MAIN_LOOP_END),
    "1.3": MotionLayout("hth4-1.3", 0x0BB8, 0x1300, OLDER_MAIN_LOOP, 50, OLDER_MAIN_LOOP_END),
}
"""Motion layouts of the HeartToHeart4 versions (spec 11.2), by version. 2.0 and 2.1 are the
same layout (no source tells them apart); detection names it ``2.1``."""

HTH4_22: Final = LAYOUTS["2.2"]
MOTIONS: Final = HTH4_22.motion_base
MOTION_SIZE: Final = HTH4_22.motion_stride
MOTION_COUNT: Final = HTH4_22.motion_count
STARTUP_STUB: Final = 0x3CB80
assert HTH4_22.startup_stub == STARTUP_STUB

TIMER_WAIT_COUNT: Final = 0x0010

assert MAIN_LOOP_JUMP == PRIORITY_CHECKS + PRIORITY_COUNT * PRIORITY_SIZE
assert PRIORITY_CHECKS == PIO_SWITCHES + PIO_SWITCHES_SIZE


def motion_address(n: int) -> int:
    """ROM address of motion ``n`` (1-120) in the HeartToHeart4 2.2 layout."""
    return HTH4_22.address(n)


def motion_number(address: int) -> int | None:
    """The motion slot (1-120) whose region holds ``address``, or None."""
    return HTH4_22.motion_at(address)
