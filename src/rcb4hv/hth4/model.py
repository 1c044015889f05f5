"""Typed model of a HeartToHeart4 project (``.h4p``) and the ROM-layout helpers.

A project file is the XmlSerializer image of HeartToHeart4's ``Rcb4`` class. Element by
element (names in the file → fields here; "inferred" = read from the fixture and the
RCB-4HV spec, not from Kondo documentation):

``Config`` → :attr:`Project.config`
    Two ``unsignedByte``: the system register (spec 10.2) little-endian. ``27, 130`` is
    0x821B. :attr:`Project.system_register` gives the word (ROM image 05DC).
``AdcReference`` → :attr:`Project.adc_reference`
    22 bytes: AD0–AD10 reference values, 11 little-endian words (RAM 000C, ROM image 08F6).
``Kri3`` → :class:`Kri3Settings`
    The KRI-3 remote receiver: ``Name``; ``Count`` (11, bytes of its RAM block — inferred);
    ``RomAddress``; ``RamAddress`` (844 = 034C, its block in the user area); ``DeviceNumber``
    (35 = its ICS slot); ``Code`` (1, the block type); ``ID`` (31); ``ReceiveDataAddress``,
    ``ReceiveDataSize`` (7 bytes received: button word, PA1–PA4, checksum — inferred);
    ``ButtonValue``, ``PA1``–``PA4``, ``CheckSum`` (initial values of that data).
``MotionDataCollection`` → :attr:`Project.motions` (:class:`Motion`)
    120 ``DictionaryEntry`` with keys ``M001``…``M120``. ``Number`` is **0-based**
    (``M001`` has ``Number`` 0) and ``Address`` is the ROM address HeartToHeart4 2.2 uses,
    0x0B80 + 2048 · Number (checked for all 120 slots of the fixture), so slot n (1–120) =
    Number + 1 = the digits of the key. An unused slot has an empty ``MotionData``.
    ``MotionData`` lists complete command frames as hex strings ``"13 12 00 FF …"``; jump
    targets inside them are absolute ROM addresses. HeartToHeart4 writes the final RETURN as
    ``03 0D 10 FF``: a valid RETURN frame followed by one 0xFF byte, which is part of the
    stored bytes (the ``.csv`` motion list counts it in the size) but is never executed.
    ``ButtonData`` is the remote button word that starts the motion (spec 10.1 bit values,
    0 = none), ``CompareType`` how the button word is compared (``Equals`` in every fixture
    entry; other .NET enum names seen: ``LessThanOrEqualTo`` in priority motions).
    ``Date`` is an ``xs:dateTime`` with 7 fraction digits (kept as text). ``KeyCode`` is a
    keyboard shortcut in the editor (``None``; meaning of other values not inferred).
``ServoConfigParams`` → :attr:`Project.servos` (:class:`ServoConfig`)
    One entry per ICS slot 0–34, keyed by the servo's display name. ``DeviceNumber`` is the
    ICS number (ID·2 + 0 for SIO1–4, 1 for SIO5–8 — but this file says ``Port`` ``SIO1`` for
    even, ``SIO2`` for odd numbers, so ``Port`` names the connector group, not SIO1–8
    literally); ``ID`` the servo ID; ``Count`` 20 = bytes of the servo block; ``RomAddress``
    (0x0626 + 20·n) and ``RamAddress`` (0x0090 + 20·n) the block image and RAM copy (spec
    11.2); ``Mode`` ``None`` (slot unused) or ``Normal``; ``Trim`` signed offset added to
    positions; ``Position`` the home position (7500 = centre); ``Mixing1Address``/
    ``Mixing2Address`` RAM source of a mixing input (65535 = none) and ``Mixing1Rate``/
    ``Mixing2Rate`` its rate (units not inferred); ``Code`` (0, block type — inferred).
    ``DisplayRate``, ``Location``, ``Group``, ``ForeColor``, ``BackColor`` only drive the
    editor's window.
``StartupMotionAddress``
    ROM address of the motion CALLed at startup (80768 = M039 in the fixture); ``-1`` is
    assumed to mean none (the image then CALLs the stub at 3CB80).
``LowPowerMotionAddress``, ``LowPowerValue``
    An older low-battery hook (``-1``/``0`` in the fixture, which uses a priority motion
    with ``Port`` ``Battery`` instead).
``PriorityMotionCollection`` → :attr:`Project.priority_motions`
    Keys ``"0"``–``"12"`` (the 13 priority checks of the 2.2 image) and ``"-1"`` (meaning
    not inferred); an entry without ``Value`` is an unused check. A value names the motion,
    the input (``Port``: ``Battery``; other names not seen), ``CompareType``, the compared
    ``Value`` (223 for the battery) and the ROM ``Address`` of the motion to call.
``PictureFileName``, ``LinkFileList``, ``ConvertFileList``, ``Anchors``
    Editor data. The three lists are empty in the fixture, so their item format is unknown:
    their children are kept as raw :class:`~rcb4hv.hth4._xml.XmlNode` values.
``ProjectTitle`` (32-byte title area at ROM 0A1B), ``FileName``, ``Path``, ``Name``,
``SoundDeviceNumber`` (``-1``).

.NET ``string`` members may be ``null``, which XmlSerializer writes by omitting the element;
those fields are ``str | None`` here (``None`` = absent). Elements the model does not know are
kept in ``extra`` and written back in place.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from decimal import Decimal
from typing import Final

from rcb4hv.errors import NotFoundError
from rcb4hv.hth4._xml import PROJECT_LAYOUT, ExtraElement, XmlLayout, XmlNode
from rcb4hv.protocol.frame import split_frames
from rcb4hv.protocol.memory import ADDR, read_system, read_u16
from rcb4hv.rom.image import Compare
from rcb4hv.rom.layout import LAYOUTS

COMPARE: Final[dict[str, Compare]] = {
    "Equals": "eq",
    "NotEquals": "ne",
    "LessThan": "lt",
    "LessThanOrEqualTo": "le",
    "GreaterThan": "gt",
    "GreaterThanOrEqualTo": "ge",
}
"""HeartToHeart4's ``CompareType`` names -> comparisons."""

__all__ = [
    "HTH4_22_MOTION_BASE",
    "MAX_MOTIONS",
    "MOTION_SLOT_SIZE",
    "Kri3Settings",
    "Motion",
    "Point",
    "PriorityMotion",
    "PriorityMotionSlot",
    "Project",
    "ServoConfig",
    "motion_key",
    "motion_rom_address",
    "slot_from_key",
]

HTH4_22_MOTION_BASE = LAYOUTS["2.2"].motion_base
"""ROM address of motion 1 in a HeartToHeart4 2.2 image (spec 11.2)."""

MOTION_SLOT_SIZE = LAYOUTS["2.2"].motion_stride
"""Bytes reserved for each motion in the 2.x layouts."""

MAX_MOTIONS = LAYOUTS["2.2"].motion_count
"""Motion slots in a HeartToHeart4 2.x project."""


def motion_rom_address(slot: int, version: str = "2.2") -> int:
    """ROM address of motion ``slot`` (1-based) in the image of HeartToHeart4 ``version``.

    2.2: 0x0B80 + 2048·(n − 1); 2.0/2.1: 0x0BB8 + 2048·(n − 1); 1.3: 0x0BB8 + 0x1300·(n − 1)
    with 50 slots (spec 11.2).
    """
    try:
        layout = LAYOUTS[version]
    except KeyError:
        raise ValueError(
            f"unknown HeartToHeart4 layout {version!r} (known: {', '.join(LAYOUTS)})"
        ) from None
    return layout.address(slot)


def motion_key(slot: int) -> str:
    """Dictionary key HeartToHeart4 uses for a slot: 1 → ``"M001"``."""
    if isinstance(slot, bool) or not isinstance(slot, int) or not 1 <= slot <= 999:
        raise ValueError(f"motion slot must be an int in 1..999, got {slot!r}")
    return f"M{slot:03d}"


def slot_from_key(key: str) -> int:
    """``"M001"`` → 1. Raises ValueError for anything else."""
    if len(key) == 4 and key[0] == "M" and key[1:].isdigit() and key[1:].isascii():
        slot = int(key[1:])
        if slot >= 1:
            return slot
    raise ValueError(f"not a motion key like 'M001': {key!r}")


@dataclass(frozen=True)
class Point:
    """A ``System.Drawing.Point`` (editor coordinates)."""

    x: int = 0
    y: int = 0


@dataclass(frozen=True)
class Kri3Settings:
    """The ``Kri3`` element: KRI-3 remote-control receiver block (see the module docstring)."""

    name: str | None = "KRI-3"
    count: int = 11
    rom_address: int = 0
    ram_address: int = ADDR.KRI3_BLOCK
    device_number: int = 35
    code: int = 1
    id: int = 31
    receive_data_address: int = 0
    receive_data_size: int = 7
    button_value: int = 0
    pa1: int = 0
    pa2: int = 0
    pa3: int = 0
    pa4: int = 0
    checksum: int = 0


@dataclass(frozen=True)
class Motion:
    """One ``MotionDataCollection`` entry: a motion slot and its command frames."""

    key: str
    number: int
    name: str | None
    date: str
    button_data: int = 0
    compare_type: str = "Equals"
    frames: tuple[bytes, ...] = ()
    address: int = 0
    key_code: str = "None"

    @property
    def slot(self) -> int:
        """1-based motion slot (``Number`` + 1; ``M001`` is slot 1)."""
        return self.number + 1

    @property
    def is_empty(self) -> bool:
        """True for an unused slot (no frames)."""
        return not self.frames

    @property
    def frame_list(self) -> list[bytes]:
        """The command frames as a new list (each a complete frame, as stored)."""
        return list(self.frames)

    @property
    def button(self) -> tuple[int, str]:
        """The remote-button binding: (button word, compare type); (0, …) = none."""
        return self.button_data, self.compare_type

    def rom_bytes(self) -> bytes:
        """The motion's bytes as they go into ROM (frames concatenated)."""
        return b"".join(self.frames)

    @property
    def code_size(self) -> int:
        """The bytes of the motion's frames, without what follows the last one (HeartToHeart4's
        FF end marker, which is not a frame): what ``project image`` reads back from ROM."""
        return sum(map(len, split_frames(self.rom_bytes())[0]))

    def expected_address(self, version: str = "2.2") -> int:
        """Where HeartToHeart4 ``version`` puts this slot (compare with :attr:`address`)."""
        return motion_rom_address(self.slot, version)


@dataclass(frozen=True)
class ServoConfig:
    """One ``ServoConfigParams`` entry: the configuration of one ICS slot."""

    key: str
    name: str | None
    device_number: int
    id: int
    port: str = "SIO1"
    mode: str = "Normal"
    count: int = 20
    rom_address: int = 0
    ram_address: int = 0
    code: int = 0
    trim: int = 0
    position: int = 7500
    mixing1_address: int = 0xFFFF
    mixing1_rate: int = 1
    mixing2_address: int = 0xFFFF
    mixing2_rate: int = 1
    display_rate: Decimal = Decimal("1.0")
    location: Point = Point()
    group: str = "Body"
    fore_color: str = "Black"
    back_color: str = "buttonface"

    @property
    def ics_number(self) -> int:
        """The ICS number (0–35) of this slot (``DeviceNumber``)."""
        return self.device_number

    @property
    def home_position(self) -> int:
        """Home position (``Position``; 7500 = centre)."""
        return self.position

    @property
    def in_use(self) -> bool:
        """False when ``Mode`` is ``None`` (no servo configured in this slot)."""
        return self.mode != "None"


@dataclass(frozen=True)
class PriorityMotion:
    """The value of a ``PriorityMotionCollection`` entry."""

    name: str | None
    port: str
    compare_type: str
    value: int
    address: int


@dataclass(frozen=True)
class PriorityMotionSlot:
    """A ``PriorityMotionCollection`` entry; ``motion`` is None for an unused check."""

    key: str
    motion: PriorityMotion | None = None


@dataclass(frozen=True)
class Project:
    """A HeartToHeart4 project (``.h4p``). See the module docstring for every field."""

    config: bytes = bytes((0x1B, 0x82))
    adc_reference: bytes = bytes(22)
    kri3: Kri3Settings = Kri3Settings()
    motions: tuple[Motion, ...] = ()
    servos: tuple[ServoConfig, ...] = ()
    startup_motion_address: int = -1
    low_power_motion_address: int = -1
    low_power_value: int = 0
    priority_motions: tuple[PriorityMotionSlot, ...] = ()
    picture_file_name: str | None = ""
    link_file_list: tuple[XmlNode, ...] | None = ()
    convert_file_list: tuple[XmlNode, ...] | None = ()
    project_title: str | None = ""
    file_name: str | None = None
    path: str | None = None
    name: str | None = None
    anchors: tuple[XmlNode, ...] | None = ()
    sound_device_number: int = -1
    extra: tuple[ExtraElement, ...] = ()
    layout: XmlLayout = field(default=PROJECT_LAYOUT)

    # -- values the ROM builder needs ----------------------------------------------------

    @property
    def system_register(self) -> int:
        """``Config`` as the 16-bit system-register value (little-endian)."""
        if len(self.config) != 2:
            raise ValueError(f"Config holds {len(self.config)} bytes, expected 2")
        return read_system(self.config, 0)

    @property
    def adc_reference_words(self) -> tuple[int, ...]:
        """``AdcReference`` as little-endian 16-bit words (AD0, AD1, …)."""
        data = self.adc_reference
        return tuple(read_u16(data, i) for i in range(0, len(data) - 1, 2))

    @property
    def used_motions(self) -> tuple[Motion, ...]:
        """Motions with at least one frame."""
        return tuple(m for m in self.motions if not m.is_empty)

    def motion(self, slot: int) -> Motion:
        """The motion in 1-based ``slot``; :class:`~rcb4hv.errors.NotFoundError` (also a
        KeyError) if the project has no such slot."""
        for m in self.motions:
            if m.slot == slot:
                return m
        slots = sorted(m.slot for m in self.motions)
        have = f"{slots[0]}..{slots[-1]}" if slots else "none"
        raise NotFoundError(f"the project has no motion slot {slot!r} (its slots: {have})")

    def motion_at(self, address: int) -> Motion | None:
        """The motion stored at ROM ``address`` (by its ``Address``), or None."""
        for m in self.motions:
            if m.address == address:
                return m
        return None

    @property
    def startup_motion(self) -> Motion | None:
        """The motion at :attr:`startup_motion_address`, or None (``-1`` or no match)."""
        if self.startup_motion_address < 0:
            return None
        return self.motion_at(self.startup_motion_address)

    @property
    def active_priority_motions(self) -> tuple[tuple[int, PriorityMotion], ...]:
        """(check index, value) of each used priority check with a numeric key ≥ 0."""
        out = []
        for slot in self.priority_motions:
            if slot.motion is not None and slot.key.isdigit():
                out.append((int(slot.key), slot.motion))
        return tuple(out)

    def servo(self, ics: int) -> ServoConfig:
        """The servo configuration of ICS number ``ics``; :class:`~rcb4hv.errors.NotFoundError`
        (also a KeyError) if absent."""
        for s in self.servos:
            if s.device_number == ics:
                return s
        have = ", ".join(str(n) for n in sorted(s.device_number for s in self.servos))
        raise NotFoundError(
            f"no servo configuration for ICS {ics!r} (configured: {have or 'none'})"
        )

    @property
    def servos_by_ics(self) -> dict[int, ServoConfig]:
        """Servo configurations keyed by ICS number."""
        return {s.device_number: s for s in self.servos}
