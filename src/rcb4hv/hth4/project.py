"""Read and write HeartToHeart4 projects (``.h4p``); see :mod:`rcb4hv.hth4.model`.

Round trip: :func:`dump_project` of :func:`parse_project` reproduces an XmlSerializer-written
file byte for byte (declaration, namespace order, CRLF, two-space indent, ``<X />`` for empty
elements, no final newline). Differences only arise for input that XmlSerializer would not
write: ``<X></X>`` comes back as ``<X />``, lowercase hex frames come back uppercase,
integers lose leading zeros / ``+`` signs, comments are dropped.
"""

from __future__ import annotations

import os

from rcb4hv.errors import Hth4FormatError
from rcb4hv.files import read_bytes, write_atomic
from rcb4hv.hth4._xml import (
    PROJECT_LAYOUT,
    ExtraElement,
    XmlNode,
    XmlReader,
    parse_document,
    root_reader,
    serialize,
)
from rcb4hv.hth4._xmlbuild import Builder
from rcb4hv.hth4.model import (
    Kri3Settings,
    Motion,
    Point,
    PriorityMotion,
    PriorityMotionSlot,
    Project,
    ServoConfig,
)
from rcb4hv.rom.layout import ROM_SIZE

__all__ = [
    "dump_project",
    "load_project",
    "parse_named_project",
    "parse_project",
    "read_project_file",
    "save_project",
]

ROOT = "Rcb4"
_U16 = (0, 0xFFFF)


def load_project(path: str | os.PathLike[str]) -> Project:
    """Read a ``.h4p`` file (however it is named); errors name the file
    (:func:`read_project_file`)."""
    return read_project_file(path)[0]


def read_project_file(path: str | os.PathLike[str]) -> tuple[Project, bytes]:
    """The project in file ``path`` and the bytes it was read from. A malformed file raises
    :class:`~rcb4hv.errors.Hth4FormatError` starting with the file's name (``project diff A
    B``: which one), and a 256 KB ROM image says that it is one."""
    data = read_bytes(path)
    return parse_named_project(data, str(path)), data


def parse_named_project(data: bytes, name: str) -> Project:
    """The project in ``data``, read from the file called ``name`` (a path, an uploaded
    file's name): errors start with the name, and a 256 KB ROM image says that it is one."""
    if len(data) == ROM_SIZE:
        raise Hth4FormatError(
            name,
            "looks like a 256 KB ROM image, not a HeartToHeart4 project "
            "(`rcb4hv project image` reads images)",
        )
    if not data.strip():
        raise Hth4FormatError(name, "an empty file, not a HeartToHeart4 project")
    try:
        return parse_project(data)
    except Hth4FormatError as exc:
        raise Hth4FormatError(name, f"not a HeartToHeart4 project: {exc}") from None


def parse_project(data: bytes | str) -> Project:
    """Parse the text of a ``.h4p`` file (bytes as stored, or an already decoded str)."""
    if not isinstance(data, (bytes, bytearray, str)):
        raise TypeError(f"a project's text is bytes or str, not {type(data).__name__}")
    root, layout = parse_document(data, ROOT, PROJECT_LAYOUT)
    r = root_reader(root)
    extras: list[ExtraElement] = []
    project = Project(
        config=r.bytes_of("Config"),
        adc_reference=r.bytes_of("AdcReference"),
        kri3=_read_kri3(r.child("Kri3")),
        motions=tuple(
            _read_motion(e) for e in r.child("MotionDataCollection").items("DictionaryEntry")
        ),
        servos=tuple(_read_servo(e) for e in r.child("ServoConfigParams").items("DictionaryEntry")),
        startup_motion_address=r.int_of("StartupMotionAddress"),
        low_power_motion_address=r.int_of("LowPowerMotionAddress"),
        low_power_value=r.int_of("LowPowerValue"),
        priority_motions=tuple(
            _read_priority(e) for e in r.child("PriorityMotionCollection").items("DictionaryEntry")
        ),
        picture_file_name=r.opt_str_of("PictureFileName"),
        link_file_list=_read_raw_list(r, "LinkFileList"),
        convert_file_list=_read_raw_list(r, "ConvertFileList"),
        project_title=r.opt_str_of("ProjectTitle"),
        file_name=r.opt_str_of("FileName"),
        path=r.opt_str_of("Path"),
        name=r.opt_str_of("Name"),
        anchors=_read_raw_list(r, "Anchors"),
        sound_device_number=r.int_of("SoundDeviceNumber"),
        layout=layout,
    )
    r.close(extras)
    if extras:
        project = _replace_extra(project, tuple(extras))
    return project


def _replace_extra(project: Project, extra: tuple[ExtraElement, ...]) -> Project:
    from dataclasses import replace

    return replace(project, extra=extra)


def _entry(e: XmlReader, value_type: str, optional: bool = False) -> tuple[str, XmlReader | None]:
    key = e.child("Key")
    key.xsi_type("xsd:string")
    value = e.opt_child("Value")
    if value is None:
        if not optional:
            raise Hth4FormatError(f"{e.path}/Value", "missing element")
        return key.text(), None
    value.xsi_type(value_type)
    return key.text(), value


def _read_kri3(k: XmlReader) -> Kri3Settings:
    return Kri3Settings(
        name=k.opt_str_of("Name"),
        count=k.int_of("Count"),
        rom_address=k.int_of("RomAddress"),
        ram_address=k.int_of("RamAddress"),
        device_number=k.int_of("DeviceNumber"),
        code=k.int_of("Code"),
        id=k.int_of("ID"),
        receive_data_address=k.int_of("ReceiveDataAddress"),
        receive_data_size=k.int_of("ReceiveDataSize"),
        button_value=k.int_of("ButtonValue"),
        pa1=k.int_of("PA1"),
        pa2=k.int_of("PA2"),
        pa3=k.int_of("PA3"),
        pa4=k.int_of("PA4"),
        checksum=k.int_of("CheckSum"),
    )


def _read_motion(e: XmlReader) -> Motion:
    key, v = _entry(e, "Motion")
    assert v is not None
    return Motion(
        key=key,
        number=v.int_of("Number"),
        name=v.opt_str_of("Name"),
        date=v.str_of("Date"),
        button_data=v.int_of("ButtonData"),
        compare_type=v.str_of("CompareType"),
        frames=v.child("MotionData").hex_frames(),
        address=v.int_of("Address"),
        key_code=v.str_of("KeyCode"),
    )


def _read_servo(e: XmlReader) -> ServoConfig:
    key, v = _entry(e, "ServoItem")
    assert v is not None
    loc = v.child("Location")
    return ServoConfig(
        key=key,
        name=v.opt_str_of("Name"),
        count=v.int_of("Count"),
        rom_address=v.int_of("RomAddress"),
        ram_address=v.int_of("RamAddress"),
        mode=v.str_of("Mode"),
        port=v.str_of("Port"),
        device_number=v.int_of("DeviceNumber"),
        code=v.int_of("Code"),
        id=v.int_of("ID"),
        trim=v.int_of("Trim"),
        position=v.int_of("Position"),
        mixing1_address=v.int_of("Mixing1Address"),
        mixing1_rate=v.int_of("Mixing1Rate"),
        mixing2_address=v.int_of("Mixing2Address"),
        mixing2_rate=v.int_of("Mixing2Rate"),
        display_rate=v.decimal_of("DisplayRate"),
        location=Point(loc.int_of("X"), loc.int_of("Y")),
        group=v.str_of("Group"),
        fore_color=v.str_of("ForeColor"),
        back_color=v.str_of("BackColor"),
    )


def _read_priority(e: XmlReader) -> PriorityMotionSlot:
    key, v = _entry(e, "PriorityMotion", optional=True)
    if v is None:
        return PriorityMotionSlot(key)
    return PriorityMotionSlot(
        key,
        PriorityMotion(
            name=v.opt_str_of("Name"),
            port=v.str_of("Port"),
            compare_type=v.str_of("CompareType"),
            value=v.int_of("Value"),
            address=v.int_of("Address"),
        ),
    )


def _read_raw_list(r: XmlReader, tag: str) -> tuple[XmlNode, ...] | None:
    sub = r.opt_child(tag)
    if sub is None:
        return None
    if (sub.el.text or "").strip():
        raise sub.error("expected a list of elements, found text")
    nodes = []
    for i, kid in enumerate(sub.el, 1):
        if kid.tail and kid.tail.strip():
            raise sub.error("text between list items is not supported")
        nodes.append(XmlNode.from_element(kid, f"{sub.path}/{kid.tag}[{i}]"))
    sub._used.update(range(len(nodes)))
    return tuple(nodes)


# ---------------------------------------------------------------------------------------------
# Writing


def dump_project(project: Project) -> bytes:
    """The ``.h4p`` file contents for ``project`` (UTF-8, XmlSerializer layout)."""
    if not isinstance(project, Project):
        raise TypeError(f"project must be a Project, not {type(project).__name__}")
    b = Builder(ROOT, "")
    b.bytes_leaf("Config", project.config)
    b.bytes_leaf("AdcReference", project.adc_reference)
    _write_kri3(b.child("Kri3"), project.kri3)
    coll = b.child("MotionDataCollection")
    for m in project.motions:
        _write_motion(coll.item("DictionaryEntry"), m)
    coll = b.child("ServoConfigParams")
    for s in project.servos:
        _write_servo(coll.item("DictionaryEntry"), s)
    b.int_leaf("StartupMotionAddress", project.startup_motion_address)
    b.int_leaf("LowPowerMotionAddress", project.low_power_motion_address)
    b.int_leaf("LowPowerValue", project.low_power_value)
    coll = b.child("PriorityMotionCollection")
    for p in project.priority_motions:
        _write_priority(coll.item("DictionaryEntry"), p)
    b.opt_leaf("PictureFileName", project.picture_file_name)
    _write_raw_list(b, "LinkFileList", project.link_file_list)
    _write_raw_list(b, "ConvertFileList", project.convert_file_list)
    b.opt_leaf("ProjectTitle", project.project_title)
    b.opt_leaf("FileName", project.file_name)
    b.opt_leaf("Path", project.path)
    b.opt_leaf("Name", project.name)
    _write_raw_list(b, "Anchors", project.anchors)
    b.int_leaf("SoundDeviceNumber", project.sound_device_number)
    return serialize(b.to_node(project.extra), project.layout)


def save_project(project: Project, path: str | os.PathLike[str]) -> None:
    """Write ``project`` to ``path`` as a ``.h4p`` file, all at once, keeping the file's mode
    and owner (:func:`rcb4hv.files.write_atomic`: a read-only file, a directory or a missing
    directory raises :class:`~rcb4hv.errors.FileAccessError` naming ``path``, nothing
    written; a file with several hard links is replaced under this name only, with a
    warning)."""
    write_atomic(path, dump_project(project))


def _write_key(e: Builder, key: str, value_type: str | None) -> Builder | None:
    e.leaf("Key", key, "xsd:string")
    return None if value_type is None else e.child("Value", value_type)


def _write_kri3(k: Builder, kri: Kri3Settings) -> None:
    k.opt_leaf("Name", kri.name)
    k.int_leaf("Count", kri.count)
    k.int_leaf("RomAddress", kri.rom_address)
    k.int_leaf("RamAddress", kri.ram_address)
    k.int_leaf("DeviceNumber", kri.device_number)
    k.int_leaf("Code", kri.code)
    k.int_leaf("ID", kri.id)
    k.int_leaf("ReceiveDataAddress", kri.receive_data_address)
    k.int_leaf("ReceiveDataSize", kri.receive_data_size)
    k.int_leaf("ButtonValue", kri.button_value)
    k.int_leaf("PA1", kri.pa1)
    k.int_leaf("PA2", kri.pa2)
    k.int_leaf("PA3", kri.pa3)
    k.int_leaf("PA4", kri.pa4)
    k.int_leaf("CheckSum", kri.checksum)


def _write_motion(e: Builder, m: Motion) -> None:
    v = _write_key(e, m.key, "Motion")
    assert v is not None
    v.int_leaf("Number", m.number)
    v.opt_leaf("Name", m.name)
    v.leaf("Date", m.date)
    v.int_leaf("ButtonData", m.button_data)
    v.leaf("CompareType", m.compare_type)
    v.child("MotionData").hex_frames(m.frames)
    v.int_leaf("Address", m.address)
    v.leaf("KeyCode", m.key_code)


def _write_servo(e: Builder, s: ServoConfig) -> None:
    v = _write_key(e, s.key, "ServoItem")
    assert v is not None
    v.opt_leaf("Name", s.name)
    v.int_leaf("Count", s.count)
    v.int_leaf("RomAddress", s.rom_address)
    v.int_leaf("RamAddress", s.ram_address)
    v.leaf("Mode", s.mode)
    v.leaf("Port", s.port)
    v.int_leaf("DeviceNumber", s.device_number)
    v.int_leaf("Code", s.code)
    v.int_leaf("ID", s.id)
    v.int_leaf("Trim", s.trim)
    v.int_leaf("Position", s.position)
    v.int_leaf("Mixing1Address", s.mixing1_address)
    v.int_leaf("Mixing1Rate", s.mixing1_rate)
    v.int_leaf("Mixing2Address", s.mixing2_address)
    v.int_leaf("Mixing2Rate", s.mixing2_rate)
    v.decimal_leaf("DisplayRate", s.display_rate)
    loc = v.child("Location")
    loc.int_leaf("X", s.location.x)
    loc.int_leaf("Y", s.location.y)
    v.leaf("Group", s.group)
    v.leaf("ForeColor", s.fore_color)
    v.leaf("BackColor", s.back_color)


def _write_priority(e: Builder, p: PriorityMotionSlot) -> None:
    v = _write_key(e, p.key, None if p.motion is None else "PriorityMotion")
    if v is None or p.motion is None:
        return
    v.opt_leaf("Name", p.motion.name)
    v.leaf("Port", p.motion.port)
    v.leaf("CompareType", p.motion.compare_type)
    v.int_leaf("Value", p.motion.value)
    v.int_leaf("Address", p.motion.address)


def _write_raw_list(b: Builder, tag: str, nodes: tuple[XmlNode, ...] | None) -> None:
    if nodes is not None:
        b.child(tag).raw(nodes)
