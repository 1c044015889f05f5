"""HeartToHeart4 2.2 ROM images: layout constants, a typed description, builder and parser.

:class:`ImageServo`, :class:`ImageMotion` and :class:`ImagePriorityMotion` are what an image
holds (the project file's entries, ``Motion``, ``ServoConfig`` and ``PriorityMotion``, are in
:mod:`rcb4hv.hth4`)."""

from __future__ import annotations

from rcb4hv.rom import layout
from rcb4hv.rom.default import DEFAULT_ICS, default_description, default_image
from rcb4hv.rom.image import (
    Compare,
    ImageDescription,
    ImageMotion,
    ImagePriorityMotion,
    ImageServo,
    Kri3Config,
    VectorPackage,
    build_image,
    parse_image,
)
from rcb4hv.rom.slots import UndecodedSlot, undecoded_slots

__all__ = [
    "DEFAULT_ICS",
    "Compare",
    "ImageDescription",
    "ImageMotion",
    "ImagePriorityMotion",
    "ImageServo",
    "Kri3Config",
    "UndecodedSlot",
    "VectorPackage",
    "build_image",
    "default_description",
    "default_image",
    "layout",
    "parse_image",
    "undecoded_slots",
]
