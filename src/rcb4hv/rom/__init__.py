"""HeartToHeart4 2.2 ROM images: layout constants, a typed description, builder and parser.

:class:`ImageServo`, :class:`ImageMotion` and :class:`ImagePriorityMotion` are what an image
holds; ``ServoConfig``, ``Motion`` and ``PriorityMotion`` are their old names here (the
project file's entries of those names are in :mod:`rcb4hv.hth4`)."""

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
    Motion,
    PriorityMotion,
    ServoConfig,
    VectorPackage,
    build_image,
    parse_image,
)

__all__ = [
    "DEFAULT_ICS",
    "Compare",
    "ImageDescription",
    "ImageMotion",
    "ImagePriorityMotion",
    "ImageServo",
    "Kri3Config",
    "Motion",
    "PriorityMotion",
    "ServoConfig",
    "VectorPackage",
    "build_image",
    "default_description",
    "default_image",
    "layout",
    "parse_image",
]
