"""HeartToHeart4 2.2 ROM images: layout constants, a typed description, builder and parser."""

from __future__ import annotations

from rcb4hv.rom import layout
from rcb4hv.rom.default import DEFAULT_ICS, default_description, default_image
from rcb4hv.rom.image import (
    Compare,
    ImageDescription,
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
