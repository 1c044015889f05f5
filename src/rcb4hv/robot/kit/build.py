"""A kit model from a kit code, and the canonical code of a build.

:func:`kit_model` assembles the frame of a :class:`~rcb4hv.robot.kit.code.KitCode` with the
joints a project uses (its joint map), or, given only the code, with the joints the code
implies at Kondo's stock ICS numbers and signs (``rcb4hv robot show kxr:L2W2L6A4H2``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from rcb4hv.protocol.memory import COUNTS_PER_DEGREE
from rcb4hv.robot.kit.assembly import assemble
from rcb4hv.robot.kit.code import KitCode
from rcb4hv.robot.kit.convention import SHORT_LEG_ROLL, SIGNS, STOCK, STOCK_VARIANTS, arm_signs
from rcb4hv.robot.kit.figures import (
    FIGURES,
    SOURCES,
    LinkFigure,
    fig,
    link_figures,
    torso_contents,
    weighed_arms,
    weighed_legs,
)
from rcb4hv.robot.kit.templates import template
from rcb4hv.robot.model import RobotModel

__all__ = [
    "canonical_code",
    "code_joints",
    "kit_model",
    "kit_signs",
    "stock_joint_map",
    "stock_joint_maps",
]

_ARM = ("shoulder_pitch", "shoulder_roll", "elbow_pitch", "shoulder_yaw", "wrist_roll",
        "wrist_pitch", "wrist_yaw")  # fmt: skip
_LEG = {
    2: ("hip_yaw", "hip_roll"),
    4: ("hip_roll", "hip_pitch", "knee_pitch", "ankle_pitch"),
    5: ("hip_roll", "hip_pitch", "knee_pitch", "ankle_pitch", "ankle_roll"),
    6: ("hip_yaw", "hip_roll", "hip_pitch", "knee_pitch", "ankle_pitch", "ankle_roll"),
}
_CENTRE = frozenset(
    {"neck_yaw", "neck_pitch", "neck_pitch2", "neck_pitch3", "waist_yaw", "jaw"}
)  # the L4N's hand ("gripper") is centre too, see code_joints


def code_joints(code: KitCode) -> list[str]:
    """The base joint names the code implies (its stock build)."""
    if code.family == "L4R" and code.arms:  # L4R2A3(G): arms in front, wheels behind
        out = ["front_yaw", "arm_roll", "arm_elbow", "rear_yaw", "rear_wheel", "neck_yaw"]
        return out + (["gripper"] if code.gripper else [])
    if code.family != "humanoid":
        out = [
            s.name
            for s in template(code).slots
            if not s.centre and not s.passive and (not s.optional or s.kind == "wheel")
        ]
        extra = {
            "L4T": ["neck_yaw"],
            "L4R": ["neck_yaw", "neck_pitch"],
            "L4N": ["neck_yaw", "neck_pitch", "gripper"],
            "L4D": ["neck_pitch", "jaw"],
        }
        return out + extra.get(code.family, [])
    arms = code.arms or 3
    out = list(_ARM[: 3 + max(0, min(arms, 7) - 3)])
    out += _LEG.get(code.legs or 5, _LEG[5])
    out += ["neck_yaw", "neck_pitch"][: code.head or 0]
    if code.gripper:
        out.append("gripper")
    if code.wheels:
        out.append("ankle_wheel")
    if code.legs == 2:  # the short legs stand on a wheeled base (kxra6g family)
        out += ["front_wheel", "rear_wheel"]
    if code.waist:
        out.append("waist_yaw")
    return out


def is_centre(code: KitCode, base: str) -> bool:
    return base in _CENTRE or (code.family == "L4N" and base == "gripper")


def kit_signs(code: KitCode) -> dict[str, tuple[int, int]]:
    """Base joint -> (right sign, left sign) of the kit's assembly convention."""
    signs = dict(SIGNS[code.family])
    if code.family == "humanoid":
        signs.update(arm_signs(code.arms or 3))
        if (code.legs or 5) <= 2:
            signs["hip_roll"] = SHORT_LEG_ROLL
    return signs


def stock_joint_maps(code: KitCode) -> list[dict[str, tuple[int, int]]]:
    """The joint maps of the code's stock build and of the family's other stock builds
    (:data:`~rcb4hv.robot.kit.convention.STOCK_VARIANTS`), in that order."""
    return [stock_joint_map(code)] + [
        stock_joint_map(code, variant) for variant in STOCK_VARIANTS.get(code.family, ())
    ]


def stock_joint_map(
    code: KitCode, numbers: Mapping[str, int] | None = None
) -> dict[str, tuple[int, int]]:
    """Full joint name -> (ICS number, sign) of the code's stock build (``numbers``: another
    stock build's ICS numbers, right side)."""
    stock = dict(STOCK[code.family] if numbers is None else numbers)
    if code.family == "humanoid" and (code.arms or 3) >= 7:
        stock["neck_yaw"], stock["neck_pitch"] = 32, 33  # wrist yaw takes 30/31
    if code.family == "humanoid" and code.legs == 2:
        stock["hip_roll"] = 16  # kxra6g: crotch-r 16/17, crotch-y 24/25
    signs = kit_signs(code)
    out: dict[str, tuple[int, int]] = {}
    for base in code_joints(code):
        right, left = signs[base]
        if is_centre(code, base):
            out[base] = (stock[base], right)
        else:
            out["r_" + base] = (stock[base], right)
            out["l_" + base] = (stock[base] + 1, left)
    return out


def _legs(joints: list[str]) -> int:
    """Axes a humanoid's leg has, from its base joint names."""
    if "knee_pitch" not in joints:
        return 2
    return 6 if "hip_yaw" in joints else 5 if "ankle_roll" in joints else 4


def canonical_code(code: KitCode, joints: list[str]) -> str:
    """The code of the build whose base joints are ``joints`` (``L2W2L6A4H2G``, ``L6``)."""
    if code.family == "L4R" and "arm_roll" in joints:
        return "L4R2A3" + ("G" if "gripper" in joints else "")
    if code.family != "humanoid":
        return code.family + ("H4" if code.family == "L4N" and "neck_pitch3" in joints else "")
    have = set(joints)
    legs = _legs(joints)
    arms = sum(1 for j in _ARM if j in have) + (1 if "elbow_yaw" in have else 0)
    head = sum(1 for j in ("neck_yaw", "neck_pitch") if j in have)
    text = "L2" + ("W2" if "ankle_wheel" in have else "")
    text += f"L{legs}" + (f"A{arms}" if arms else "") + (f"H{head}" if head else "")
    text += ("G" if "gripper" in have else "") + ("T1" if "waist_yaw" in have else "")
    text += {"wide": "W", "narrow": "N"}.get(code.width, "")
    return text


def kit_model(
    code: KitCode,
    joint_map: Mapping[str, tuple[int, int]] | None = None,
    *,
    home_counts: Mapping[str, int] | None = None,
    sources: Mapping[str, str] | None = None,
) -> RobotModel:
    """The model of ``code``'s frame with ``joint_map`` (full joint name -> (ICS number,
    sign); default: the code's stock build); ``home_counts``: the home pose's motion values
    minus 7500 by full joint name (wheels are left out)."""
    jm = dict(joint_map) if joint_map is not None else stock_joint_map(code)
    bases = sorted({j[2:] if j[:2] in ("l_", "r_") else j for j in jm})
    text = canonical_code(code, bases)
    home = {
        j: math.radians(jm[j][1] * counts / COUNTS_PER_DEGREE)
        for j, counts in (home_counts or {}).items()
        if j in jm and not j.endswith("wheel")
    }
    used = sorted({FIGURES[k].source for k in FIGURES})
    per_link = link_figures(text)
    borrowed = {} if per_link or code.family != "humanoid" else _borrowed(bases)
    src = {
        "dimensions": "rcb4hv.robot.kit.figures (one row per figure, with its source); "
        + "; ".join(f"{k}: {SOURCES[k][0]} ({SOURCES[k][1]})" for k in used),
        "joint map": "Kondo's stock ICS numbers for this kit code (KXR-KITS.md §1.4)",
        "signs": "the kit's assembly convention (kxreus joint maps of the stock builds)",
        "mass": (
            f"kxreus's per-link masses and centres of mass of this build (figures "
            f"lmass.{text}.*, lcom.{text}.*)"
            if per_link
            else f"the build's whole-robot mass (figures {', less '.join(_total_rows(text))})"
            if f"mass.{text}" in FIGURES
            else f"{code.family} whole-robot mass (figures mass.{code.family}) ± one "
            "KRS-3304R2 per servo more or fewer"
        )
        + ("" if per_link else ", shared over the links by servo and shape volume")
        + (
            "; the torso's contents and the leg links from the weighed build with the same "
            "legs, the arm links from the one with the same arm (figures.torso_contents, "
            "figures.weighed_legs, figures.weighed_arms)"
            if borrowed
            else ""
        ),
    }
    src.update(sources or {})
    return assemble(
        template(code, arms="arm_roll" in bases),
        bases,
        jm,
        name="kxr:" + text,
        title=f"Kondo KXR-{text} ({len(jm) - _shared(jm)} servos)",
        sources=src,
        home=home,
        total_mass=_total_mass(text),
        link_masses=per_link,
        borrowed=borrowed,
    )


def _borrowed(bases: list[str]) -> dict[str, LinkFigure]:
    """The weighed builds' torso contents, leg and arm links for a humanoid build no source
    weighs link by link (``figures.torso_contents``, ``figures.weighed_legs``,
    ``figures.weighed_arms``)."""
    legs = _legs(bases)
    out = weighed_legs(legs, "ankle_wheel" in bases) | weighed_arms(bases)
    torso = torso_contents(legs)
    if torso is not None:
        out["torso"] = torso
    return out


def _shared(jm: Mapping[str, tuple[int, int]]) -> int:
    return len(jm) - len({i for i, _ in jm.values()})


def _total_rows(text: str) -> list[str]:
    """The figures of the build ``text``'s whole-robot mass: kxreus's total, then the parts of
    kxreus's build that Kondo's lacks (``leftout.<code>``) where there are any."""
    return [k for k in (f"mass.{text}", f"leftout.{text}") if k in FIGURES]


def _total_mass(text: str) -> float | None:
    """kxreus's whole-robot mass (kg) of the build ``text`` less what Kondo's build lacks
    (:func:`_total_rows`), or None where kxreus gives none."""
    if f"mass.{text}" not in FIGURES:
        return None
    total, *left_out = (fig(k) for k in _total_rows(text))
    return (total - sum(left_out)) / 1000
