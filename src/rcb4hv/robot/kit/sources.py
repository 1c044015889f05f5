"""The provenance of the kit builder's figures: the sources, and a figure (value, unit,
source, where it was read)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["SOURCES", "Figure", "row"]

#: source key -> (what it is, licence)
SOURCES: dict[str, tuple[str, str]] = {
    "KX": (
        "inabajsk/kxreus (kxrbody.l, kxrlinks.l, rcb4robotconfig.l, models/*.l, "
        "eusview/robots/kxr/*.json; commits 4a2094e, a1238a3, 044677e, 58d0e83)",
        "no licence file: facts and figures only, no code or mesh",
    ),
    "KP": (
        "Kondo's HeartToHeart4 sample projects (inabajsk/kxreus projects/Hello_*)",
        "no licence stated (Kondo Kagaku): facts only",
    ),
    "RC": ("iory/rcb4 ros/kxr_models URDFs (commit dc1ccf5)", "MIT (package.xml says BSD)"),
    "FACTS": ("shared/robots/FACTS.md (Kondo KRS-3304R2 catalogue figures)", "facts"),
    "CHOSEN": ("a named choice of this package where no source gives the figure", "-"),
}


@dataclass(frozen=True)
class Figure:
    value: float | tuple[float, float, float]
    unit: str
    source: str  # a SOURCES key
    where: str  # the file / section the figure was read or derived from


def row(value: float | tuple[float, float, float], unit: str, source: str, where: str) -> Figure:
    return Figure(value, unit, source, where)
