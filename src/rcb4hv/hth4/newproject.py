"""A new HeartToHeart4 project for a robot model, and the project-wide settings as edits.

:func:`new_project` writes what HeartToHeart4's "new project" gives, for any
:class:`~rcb4hv.robot.RobotModel`: the 35-slot servo table (the model's servos in use, named
after their joints, trims 0, home positions from the model's home pose; a multi-legged kit
model without one takes its kit's stock home pose, :mod:`rcb4hv.robot.kit.stockhome`, as its
zero pose lies on the torso), 120 empty motion slots at the HeartToHeart4 2.2 addresses, slot
1 a "home position" motion (the home pose, then HeartToHeart4's closing ``03 0D 10 FF``) and
the start-up program calling it.

Settings (pure functions from a project to a new one, as :mod:`rcb4hv.hth4.edit`):
:func:`set_startup`, :func:`set_low_power`, :func:`set_priority`, :func:`set_mixing`,
:func:`set_ad_reference` (:func:`set_ad_references`), :func:`set_output_period`;
:func:`mixing_source` reads a mixing source as a user writes it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from typing import Final

from rcb4hv.errors import EditError
from rcb4hv.hth4.blocks.kinds import Block
from rcb4hv.hth4.blocks.program import Program, put_program
from rcb4hv.hth4.edit import used_motion
from rcb4hv.hth4.keyframes import now_text
from rcb4hv.hth4.model import (
    COMPARE as COMPARE,
)
from rcb4hv.hth4.model import (
    MAX_MOTIONS,
    Motion,
    PriorityMotion,
    PriorityMotionSlot,
    Project,
    ServoConfig,
    motion_key,
    motion_rom_address,
)
from rcb4hv.protocol.memory import ADDR, CENTER, FRAME_PERIODS_MS, SystemRegister
from rcb4hv.robot.kit.stockhome import with_stock_home
from rcb4hv.robot.model import RobotModel
from rcb4hv.values import parse_address

__all__ = [
    "HOME_FRAMES",
    "HOME_NAME",
    "mixing_source",
    "new_project",
    "set_ad_reference",
    "set_ad_references",
    "set_low_power",
    "set_mixing",
    "set_output_period",
    "set_priority",
    "set_startup",
]

HOME_NAME: Final = "home position"
HOME_FRAMES: Final = 30
"""Output periods of slot 1's move to the home pose (0.45 s at 15 ms): a documented choice,
slow enough that no servo jumps at power-on."""
SYSTEM_REGISTER: Final = bytes((0x1B, 0x82))
"""Config: ICS output, ROM program, vector jump on, 15 ms frame, 115200 baud (the word the
fixture project holds, spec 10.2)."""
SERVO_SLOTS: Final = 35
SERVO_BLOCK_IMAGE: Final = 0x0626
"""ROM image of the servo blocks (spec 11.2): slot n at 0626h + 20n."""
PRIORITY_KEYS: Final = (*map(str, range(13)), "-1")
"""The ``PriorityMotionCollection`` keys HeartToHeart4 writes: the 13 checks, then ``-1``."""
NO_MIXING: Final = 0xFFFF


def _servo(model: RobotModel, ics: int) -> ServoConfig:
    in_use = ics in model.indices
    joint = model.servo(ics).joint if in_use else f"ICS{ics}"
    home = model.motion_value(ics, model.home[joint]) if joint in model.home else CENTER
    return ServoConfig(
        key=joint,
        name=joint,
        device_number=ics,
        id=ics // 2,
        port="SIO1" if ics % 2 == 0 else "SIO2",
        mode="Normal" if in_use else "None",
        rom_address=SERVO_BLOCK_IMAGE + ADDR.SERVO_BLOCK_SIZE * ics,
        ram_address=ADDR.servo_block(ics),
        position=home,
        group="Body" if in_use else "Ext",
    )


def new_project(model: RobotModel, *, title: str | None = None, date: str | None = None) -> Project:
    """A project for ``model`` (module docstring); ``date`` (HeartToHeart4 text) for every
    motion slot, default now."""
    model = with_stock_home(model)
    when = date or now_text()
    servos = tuple(_servo(model, n) for n in range(SERVO_SLOTS))
    motions = tuple(
        Motion(
            key=motion_key(n),
            number=n - 1,
            name=motion_key(n),
            date=when,
            address=motion_rom_address(n),
        )
        for n in range(1, MAX_MOTIONS + 1)
    )
    project = Project(
        config=SYSTEM_REGISTER,
        motions=motions,
        servos=servos,
        priority_motions=tuple(PriorityMotionSlot(k) for k in PRIORITY_KEYS),
        project_title=title or model.name,
        name=title or model.name,
    )
    home = {str(s.device_number): s.position for s in servos if s.in_use}
    program = Program(
        blocks=(Block("pose", {"frames": HOME_FRAMES, "positions": home}), Block("end")),
        name=HOME_NAME,
        date=when,
    )
    return set_startup(put_program(project, 1, program), 1)


def _used(project: Project, slot: int, what: str) -> Motion:
    try:
        return used_motion(project, slot)
    except EditError as exc:
        raise EditError(f"{what}: {exc}") from None


def set_startup(project: Project, slot: int | None) -> Project:
    """The motion the start-up program calls (None: none, the image's RETURN stub)."""
    address = -1 if slot is None else _used(project, slot, "start-up motion").address
    return replace(project, startup_motion_address=address)


def set_low_power(project: Project, slot: int | None, value: int | None = None) -> Project:
    """The low-battery motion (None: none), called when AD0 (the supply, 25/1024 V a count)
    is at or below ``value`` (default: the project's)."""
    if value is not None and not 0 <= value <= 1023:
        raise EditError(f"low-power value {value} outside the AD range 0..1023")
    address = -1 if slot is None else _used(project, slot, "low-power motion").address
    threshold = project.low_power_value if value is None else value
    if slot is not None and threshold == 0:
        raise EditError(
            "the low-power motion runs when AD0 <= its value, and the value is 0, so it "
            "would never run: give the value too (--low-power-value; Kondo's samples check "
            "the battery with a priority check, Battery < 224)"
        )
    return replace(project, low_power_motion_address=address, low_power_value=threshold)


def priority_port_source(port: str) -> tuple[int, int]:
    """(RAM address, size) compared by a priority check of input ``port`` (Battery, AD0-AD10,
    PA1-PA4, any case); ValueError for another name."""
    p = port.strip()
    if p.lower() == "battery":
        return ADDR.ad(0), 2
    up = p.upper()
    if up.startswith("AD") and up[2:].isdigit() and 0 <= int(up[2:]) <= 10:
        return ADDR.ad(int(up[2:])), 2
    if up.startswith("PA") and up[2:].isdigit() and 1 <= int(up[2:]) <= 4:
        return ADDR.PA[int(up[2:]) - 1], 1
    raise ValueError(f"unknown priority-motion port {port!r} (known: Battery, AD0-AD10, PA1-PA4)")


def set_priority(
    project: Project,
    index: int,
    slot: int | None,
    port: str = "Battery",
    compare_type: str = "LessThanOrEqualTo",
    value: int = 0,
) -> Project:
    """Priority check ``index`` (0-12): call motion ``slot`` when input ``port`` (Battery,
    AD0-AD10, PA1-PA4) compares ``compare_type`` to ``value``; None clears the check."""
    key = str(index)
    if key not in PRIORITY_KEYS[:-1]:
        raise EditError(f"priority check {index} outside 0..12")
    try:
        priority_port_source(port)
    except ValueError as exc:
        raise EditError(f"priority check {index}: {exc}") from None
    if compare_type not in COMPARE:
        raise EditError(
            f"priority check {index}: unknown comparison {compare_type!r} "
            f"(known: {', '.join(COMPARE)})"
        )
    if slot is None:
        entry = PriorityMotionSlot(key)
    else:
        m = _used(project, slot, f"priority check {index}")
        entry = PriorityMotionSlot(
            key, PriorityMotion(m.name, port, compare_type, value, m.address)
        )
    slots = list(project.priority_motions)
    keys = [s.key for s in slots]
    if key in keys:
        slots[keys.index(key)] = entry
    else:
        slots.append(entry)
    return replace(project, priority_motions=tuple(slots))


def set_mixing(
    project: Project, ics: int, which: int, source: int | None, rate: int = 1
) -> Project:
    """Mixing input ``which`` (1 or 2) of servo ``ics``: RAM word ``source`` (e.g. AD1 at 0024h;
    None: off) times ``rate``, -127..127 (the block's method byte: a sign bit and a multiplier
    of 0-127; a negative rate turns a reversed sensor round)."""
    if which not in (1, 2):
        raise EditError(f"a servo has mixing inputs 1 and 2, not {which}")
    if source is not None and not 0 <= source < NO_MIXING:
        raise EditError(f"mixing source {source} is not a RAM address")
    if not -127 <= rate <= 127:
        raise EditError(f"mixing rate {rate} outside -127..127 (a sign and a multiplier 0-127)")
    try:
        servo = project.servo(ics)
    except KeyError:
        raise EditError(f"the project configures no servo ICS {ics}") from None
    address = NO_MIXING if source is None else source
    if which == 1:
        servo = replace(servo, mixing1_address=address, mixing1_rate=rate)
    else:
        servo = replace(servo, mixing2_address=address, mixing2_rate=rate)
    servos = tuple(servo if s.device_number == ics else s for s in project.servos)
    return replace(project, servos=servos)


def mixing_source(text: str) -> int | None:
    """A mixing source written ``AD1`` (its measured word), a RAM address (``0024h``, ``0x24``,
    ``$24``, ``36``: :func:`rcb4hv.values.parse_address`) or ``none`` (None)."""
    t = text.strip().upper()
    if t in ("", "NONE"):
        return None
    if t.startswith("AD") and t[2:].isdigit():
        if int(t[2:]) >= ADDR.AD_COUNT:
            raise EditError(f"mixing source {text!r}: the board has AD0-AD{ADDR.AD_COUNT - 1}")
        return int(ADDR.AD_VALUES + 2 * int(t[2:]))
    try:
        return parse_address(t)
    except ValueError:
        raise EditError(f"mixing source {text!r}: ADn, a RAM address or none") from None


def set_ad_references(project: Project, values: Mapping[int, int]) -> Project:
    """The analog calibration of several channels at once (channel -> value)."""
    for channel, value in values.items():
        project = set_ad_reference(project, channel, value)
    return project


def set_ad_reference(project: Project, channel: int, value: int) -> Project:
    """The analog calibration of AD ``channel`` (0-10): its value at rest (spec 10.4)."""
    if not 0 <= channel < ADDR.AD_COUNT:
        raise EditError(f"AD channel {channel} outside 0..{ADDR.AD_COUNT - 1}")
    if not -0x8000 <= value <= 0xFFFF:
        raise EditError(f"AD reference {value} is not a 16-bit value")
    data = bytearray(project.adc_reference.ljust(2 * ADDR.AD_COUNT, b"\0"))
    data[2 * channel : 2 * channel + 2] = (value & 0xFFFF).to_bytes(2, "little")
    return replace(project, adc_reference=bytes(data))


def set_output_period(project: Project, ms: int) -> Project:
    """The board's servo output period (10, 15, 20 or 25 ms; system register bits 5-4, spec
    10.2). A pose's frame count is in output periods, so every motion plays at another speed:
    a move of 20 frames lasts 0.2 s at 10 ms and 0.3 s at 15 ms."""
    if ms not in FRAME_PERIODS_MS:
        raise EditError(
            f"output period {ms} ms: the board has {', '.join(map(str, FRAME_PERIODS_MS))} ms"
        )
    try:
        reg = SystemRegister.from_word(project.system_register)
    except ValueError as exc:
        raise EditError(str(exc)) from None
    word = replace(reg, frame_code=FRAME_PERIODS_MS.index(ms)).to_word()
    return replace(project, config=word.to_bytes(2, "little"))
