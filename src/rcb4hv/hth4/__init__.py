"""HeartToHeart4 files (Kondo's Windows motion editor): read, model, write.

=========  ==========================  ==================================================
file       root / format               functions
=========  ==========================  ==================================================
``.h4p``   ``Rcb4`` (XmlSerializer)    :func:`load_project`, :func:`parse_project`,
                                       :func:`dump_project`, :func:`save_project`
``.xml``   ``CanvasData``              :func:`load_motion_xml`, :func:`parse_motion_xml`,
                                       :func:`dump_motion_xml`, :func:`save_motion_xml`
``.h4t``   ``ArrayOfDictionaryEntry``  :func:`load_trim`, :func:`parse_trim`, :func:`dump_trim`,
                                       :func:`save_trim`
``.h4l``   unknown schema, generic     :func:`load_link`, :func:`parse_link`, :func:`dump_link`,
                                       :func:`save_link`
``.csv``   Shift-JIS CSV               :func:`load_motion_list`, :func:`parse_motion_list`,
                                       :func:`dump_motion_list`, :func:`save_motion_list`
=========  ==========================  ==================================================

``load_*`` take a path, ``parse_*`` the file's bytes (or decoded text), ``dump_*`` return the
bytes to store and ``save_*`` write them. Malformed or foreign input raises
:class:`Hth4FormatError` (a ``ValueError`` and an ``Rcb4Error``) naming the element or cell.
Motion frames stay raw ``bytes`` here; decode them with :mod:`rcb4hv.protocol`.
"""

from rcb4hv.hth4._xml import (
    PROJECT_LAYOUT,
    XSI_FIRST_LAYOUT,
    ExtraElement,
    XmlLayout,
    XmlNode,
)
from rcb4hv.hth4.flowchart import (
    dump_motion_xml,
    load_motion_xml,
    parse_motion_xml,
    save_motion_xml,
)
from rcb4hv.hth4.flowchart_model import Flowchart, FlowchartActivity, FlowchartLine, Size
from rcb4hv.hth4.link import (
    XmlDocument,
    dump_link,
    dump_xml_document,
    load_link,
    parse_link,
    parse_xml_document,
    save_link,
)
from rcb4hv.hth4.model import (
    HTH4_22_MOTION_BASE,
    MAX_MOTIONS,
    MOTION_SLOT_SIZE,
    Kri3Settings,
    Motion,
    Point,
    PriorityMotion,
    PriorityMotionSlot,
    Project,
    ServoConfig,
    motion_key,
    motion_rom_address,
    slot_from_key,
)
from rcb4hv.hth4.motionlist import (
    BUTTON_SYMBOLS,
    MotionList,
    MotionListEntry,
    button_label,
    dump_motion_list,
    load_motion_list,
    parse_motion_list,
    save_motion_list,
)
from rcb4hv.hth4.project import dump_project, load_project, parse_project, save_project
from rcb4hv.hth4.trim import TrimEntry, TrimFile, dump_trim, load_trim, parse_trim, save_trim

__all__ = [
    "BUTTON_SYMBOLS",
    "HTH4_22_MOTION_BASE",
    "MAX_MOTIONS",
    "MOTION_SLOT_SIZE",
    "PROJECT_LAYOUT",
    "XSI_FIRST_LAYOUT",
    "ExtraElement",
    "Flowchart",
    "FlowchartActivity",
    "FlowchartLine",
    "Kri3Settings",
    "Motion",
    "MotionList",
    "MotionListEntry",
    "Point",
    "PriorityMotion",
    "PriorityMotionSlot",
    "Project",
    "ServoConfig",
    "Size",
    "TrimEntry",
    "TrimFile",
    "XmlDocument",
    "XmlLayout",
    "XmlNode",
    "button_label",
    "dump_link",
    "dump_motion_list",
    "dump_motion_xml",
    "dump_project",
    "dump_trim",
    "dump_xml_document",
    "load_link",
    "load_motion_list",
    "load_motion_xml",
    "load_project",
    "load_trim",
    "motion_key",
    "motion_rom_address",
    "parse_link",
    "parse_motion_list",
    "parse_motion_xml",
    "parse_project",
    "parse_trim",
    "parse_xml_document",
    "save_link",
    "save_motion_list",
    "save_motion_xml",
    "save_project",
    "save_trim",
    "slot_from_key",
]
