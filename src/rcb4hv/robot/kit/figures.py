"""Every figure the kit builder uses, with its source and licence: the one provenance table.

Like MuJoCo Menagerie's model cards, each number names where it came from. ``docs/robots.md``
renders this table (``rcb4hv robot show kxr:CODE`` prints the sources a model used). Lengths
are millimetres, masses grams, in the robot frame (x forward, y left, z up), for the LEFT
side (the right is the mirror image). Nothing here is copied code or mesh: the figures were
read or derived from the sources (derivations in ``shared/robots/KXR-KITS.md``, the section
named in each row).
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import NamedTuple

from rcb4hv.robot.kit.linkrows import LINK_ROWS
from rcb4hv.robot.kit.sources import SOURCES, Figure
from rcb4hv.robot.kit.sources import row as _f

__all__ = [
    "FIGURES",
    "MASS_SERVOS",
    "SOURCES",
    "Figure",
    "LinkFigure",
    "case_shortfall",
    "fig",
    "link_figures",
    "provenance_markdown",
    "vec",
]


_KRS_3304R2_G = 35.03
"""A KRS-3304R2 with its horn (g): ``servo.mass`` and ``mass.per_servo``."""
_KXREUS_CASE_G = 27.73
"""The mass kxreus gives every servo case it weighs (g): ``servo.mass_kxreus``."""
_L5A3H2G_TOTAL = 1421.74
"""kxreus's KXR-L2L5A3H2G (``kxrl2l5a3h2g.json``) total, g: 22 servo cases, two of them the
eye servos of its ``:head :h2s``."""
_L5A3H2G_EYES = 2 * _KXREUS_CASE_G + 2 * 43.241
"""Its eye servos' cases (in head-neck-p, physics.links[22]) and eye links ([23], [24]), g."""

FIGURES: dict[str, Figure] = {
    # ---------------------------------------------------------------- servo and parts
    "servo.case": _f((32.5, 26.0, 26.0), "mm", "KX", "kxrbody.l kxr-servo-s3300 (§2.1)"),
    "servo.mass": _f(_KRS_3304R2_G, "g", "KX", "kxrbody.l s3304R2 33.7 + horn 1.33 (§3.1)"),
    "servo.mass_kxreus": _f(
        _KXREUS_CASE_G,
        "g",
        "KX",
        "kxrbody.l s3301 26.4 + horn 1.33: every servo case of kxreus's models",
    ),
    "wheel.radius": _f(30.5, "mm", "KX", "kxrbody.l kxr-wheel r 20 + 10.5 (§2.6)"),
    "wheel.width": _f(13.0, "mm", "KX", "kxrbody.l kxr-wheel tyre half-width 6.5 (§2.6)"),
    "wheel.axle_offset": _f(14.0, "mm", "KX", "kxrlinks.l kxr-wheel-link offset 3.5 + 10.5"),
    # ---------------------------------------------------------------- biped body (L2)
    "l2.shoulder": _f((-7.25, 46.5, 69.0), "mm", "KX", "models/kxrl2g.l (§2.2)"),
    "l2.neck_yaw": _f((-7.25, 0.0, 82.5), "mm", "KX", "kxrl2l6a6h2.json head-neck-y (§2.3)"),
    "l2.neck_pitch": _f((0.0, 0.0, 36.0), "mm", "KX", "kxrl2l6a6h2.json head-neck-p (§2.3)"),
    "l2.hip_l5": _f((0.0, 23.5, -28.0), "mm", "KX", "models/kxrl2g.l crotch-r (§2.2)"),
    "l2.hip_l6": _f((0.0, 23.5, -34.5), "mm", "KX", "kxrl2l6a6h2.json crotch-y (§2.3)"),
    "l2.hip_l6_wide": _f((0.0, 44.5, -34.5), "mm", "KX", "kxrl2l6a7h2w.json crotch-y (§2.4)"),
    "l2.hip_yaw_to_roll": _f(31.0, "mm", "KX", "kxrl2l6a6h2.json check (§2.3)"),
    "l2.hip_l2": _f((0.0, 34.0, -31.0), "mm", "KX", "models/kxra6g.l crotch-y (§2.5)"),
    "l2.short_leg": _f(33.0, "mm", "KX", "models/kxra6g.l crotch-y to crotch-r (§2.5)"),
    "l2.thigh": _f(58.0, "mm", "KX", "models/kxrl2g.l knee (§2.2)"),
    "l2.shin": _f(57.98, "mm", "KX", "models/kxrl2g.l ankle (§2.2)"),
    "l2.sole": _f(31.0, "mm", "KX", "models/kxrl2g.l leg end-coords (§2.2)"),
    "l2.sole_top": _f(
        21.0, "mm", "KX", "models/kxrl2g.l foot link RLEG_LINK4: its plate's top below the ankle"
    ),
    **{
        f"l2.sole_step{k}": _f(
            step,
            "mm",
            "KX",
            "models/kxrl2g.l foot link RLEG_LINK4 (mirrored): the plate, 105 mm long, reaches 21 "
            "mm inward and 46.2 mm outward of the ankle; its rounded outer side is three boxes "
            "inside that outline (x half-length, inner y, outer y)",
        )
        for k, step in enumerate(((52.5, -21.0, 18.9), (42.0, 18.9, 33.6), (21.0, 33.6, 44.1)), 1)
    },
    "l2.base_wheel": _f(
        (54.0, 14.0, -34.0),
        "mm",
        "RC",
        "kxrmw4a6h2m.urdf wheels at x ±54 (§2.5); y, z chosen: axle on the "
        "short leg's foot, wheel below its sole",
    ),
    "l2.foot_wheel": _f(
        (54.0, 14.0, -3.5),
        "mm",
        "CHOSEN",
        "base wheels under a long-legged biped's foot (the kxra6g projects "
        "list them with full legs): the kxrmw4a6h2m wheel spacing (x ±54, RC), "
        "tyre 3 mm below the sole",
    ),
    "l2.ankle_wheel": _f(
        (-78.03, 0.0, 0.0),
        "mm",
        "KX",
        "kxrl2w2l6a4h2.json lleg-ankle-w pos from the ankle pitch axis (kxr-document.txt: "
        "足首の後ろに車輪); with the 31 mm sole the tyre clears the floor by 0.5 mm at zero pose",
    ),
    "l2.ankle_tyre": _f(
        (0.0, 23.5, 0.0),
        "mm",
        "KX",
        "kxrl2w2l6a4h2.json physics: the ankle wheel's tyre cylinder 23.5 mm outboard of its "
        "axle's origin",
    ),
    # arm chains: offsets from the previous joint (A3: kxrl2g.l; A4: kxrl2w2l6a4h2.json;
    # A5-A6: kxrl2l6a6h2.json; A7: kxrl2l6a7h2w.json)
    "arm3.roll": _f((0.0, 29.0, 0.0), "mm", "KX", "models/kxrl2g.l shoulder-r (§2.2)"),
    "arm3.elbow": _f((0.0, 0.0, -53.0), "mm", "KX", "models/kxrl2g.l elbow-p (§2.2)"),
    "arm3.gripper": _f((0.0, 0.0, -65.5), "mm", "KX", "models/kxrl2g.l gripper2-r (§2.2)"),
    "arm3.basic_forearm": _f(
        (27.4, 31.0, 41.9),
        "mm",
        "KX",
        "eusview/robots/kxr/kxrl2l5a3.json (the basic kit) forearm link shapes: the elbow "
        "servo's case and the joint base screwed to its end with its side plates, from 9.3 mm "
        "above the elbow axis to arm3.basic_hand below it (an A3 arm without a gripper)",
    ),
    "arm3.basic_hand": _f(
        32.6, "mm", "KX", "kxrl2l5a3.json: the basic kit's forearm ends this far below the elbow"
    ),
    "arm4.roll": _f((0.0, 29.0, 0.0), "mm", "KX", "kxrl2w2l6a4h2.json larm-shoulder-r pos"),
    "arm4.yaw": _f((0.0, 0.0, -67.0), "mm", "KX", "kxrl2w2l6a4h2.json larm-shoulder-y pos"),
    "arm4.elbow": _f((0.0, 0.0, -29.0), "mm", "KX", "kxrl2w2l6a4h2.json larm-elbow-p pos"),
    "arm4.gripper": _f(
        (0.0, 0.0, -65.5), "mm", "KX", "kxrl2w2l6a4h2.json larm-gripper2-r pos (from the elbow)"
    ),
    "arm6.shoulder": _f(
        (7.25, 46.5, 67.5), "mm", "KX", "kxrl2l6a6h2.json larm-shoulder-p link header (§2.3)"
    ),
    "arm6.roll": _f((0.0, 31.0, 0.0), "mm", "KX", "kxrl2l6a6h2.json shoulder-r (§2.3)"),
    "arm6.yaw": _f((0.0, 0.0, -15.0), "mm", "KX", "kxrl2l6a6h2.json shoulder-y (§2.3)"),
    "arm6.elbow": _f((0.0, 0.0, -41.0), "mm", "KX", "kxrl2l6a6h2.json elbow-p (§2.3)"),
    # the A6 forearm is bent (`:elbow :angle`): the wrist sits behind the elbow and the
    # hand points forward at zero pose. The same numbers in kxreus's kxrl2l6a6h2.json check,
    # models/kxra6g.l, models/kxrl2inaba.l and eusmodels/kxrl2l2a6h2.l (its link frames)
    "arm6.wrist": _f(
        (-23.5, 0.0, -43.0), "mm", "KX", "kxrl2l6a6h2.json wrist-p from the elbow (§2.3)"
    ),
    "arm6.wrist_roll": _f(
        (15.0, 0.0, 0.0), "mm", "KX", "kxrl2l6a6h2.json wrist-r 15 forward (§2.3)"
    ),
    "arm6.gripper": _f(
        (31.5, 0.0, 0.0), "mm", "KX", "kxrl2l6a6h2.json gripper 31.5 forward (§2.3)"
    ),
    "arm7.yaw": _f((0.0, 31.0, 0.0), "mm", "KX", "kxrl2l6a7h2w.json shoulder-y (§2.4)"),
    "arm7.elbow": _f((0.0, 0.0, -58.0), "mm", "KX", "kxrl2l6a7h2w.json elbow-p (§2.4)"),
    "arm7.wrist_yaw": _f((0.0, 0.0, -67.0), "mm", "KX", "kxrl2l6a7h2w.json wrist-y (§2.4)"),
    "arm7.wrist": _f((0.0, 0.0, -41.0), "mm", "KX", "kxrl2l6a7h2w.json wrist-p (§2.4)"),
    "arm7.gripper": _f((0.0, 0.0, -61.0), "mm", "KX", "kxrl2l6a7h2w.json gripper2-r (§2.4)"),
    # ---------------------------------------------------------------- four and six legs
    "l4d.hip": _f((64.5, 48.0, 0.0), "mm", "KX", "models/kxrl4d.l (§2.7)"),
    "l4d.roll": _f((0.0, 29.0, 0.0), "mm", "KX", "models/kxrl4d.l (§2.7)"),
    "l4d.knee": _f((0.0, 0.0, -53.0), "mm", "KX", "models/kxrl4d.l (§2.7)"),
    "l4d.ankle": _f((0.0, 0.0, -57.98), "mm", "KX", "models/kxrl4d.l (§2.7)"),
    "l4d.foot": _f((10.5, 0.0, -33.0), "mm", "KX", "models/kxrl4d.l foot end-coords (§2.7)"),
    "l4d.neck": _f((43.5, 0.0, 58.5), "mm", "KX", "models/kxrl4d.l head-neck-p (§2.7)"),
    "l4d.jaw": _f((38.89, 0.0, 114.89), "mm", "KX", "models/kxrl4d.l head-gripper-p (§2.7)"),
    "l4t.hip": _f((43.5, 64.5, -3.0), "mm", "KX", "models/kxrl4t.l crotch-y (§2.8)"),
    "l4t.roll": _f((0.0, 40.0, 0.0), "mm", "KX", "models/kxrl4t.l (§2.8)"),
    "l4t.foot": _f((0.0, 32.5, 0.0), "mm", "KX", "models/kxrl4t.l end-coords (§2.8)"),
    "l4t.neck": _f((64.5, 0.0, 53.47), "mm", "KX", "models/kxrl4t.l head-neck-y (§2.8)"),
    "l4t.neck_pitch": _f((0.0, 0.0, 36.0), "mm", "KX", "models/kxrl4t.l head-neck-p (§2.8)"),
    "l4n.hand": _f(
        (40.0, 0.0, 0.0),
        "mm",
        "CHOSEN",
        "L4N hand ahead of the neck pitch; KX gives no L4N neck offsets (§2.8)",
    ),
    "l4r.wheel": _f(
        (0.0, 54.5, -21.0),
        "mm",
        "KX",
        "eusview kxrl4r2a3.json rleg-crotch-w from rleg-crotch-y: the wheel joint of the "
        "`:leg :j1w` rear leg the L4R shares (KXR-KITS.md §2.8); the L4R's front `:arm :j1w` "
        "is taken to match. The disc sits wheel.axle_offset further out, 3 mm past the json's "
        "mesh centre",
    ),
    "l4r.shoulder": _f(
        (0.0, 52.0, 0.0),
        "mm",
        "KX",
        "eusview kxrl4r2a3.json rarm-shoulder-r from rarm-shoulder-y (the L4R2A3 arm: yaw to roll)",
    ),
    "l4r.upper_arm": _f(
        (0.0, 69.0, 0.0),
        "mm",
        "KX",
        "eusview kxrl4r2a3.json rarm-elbow-r from rarm-shoulder-r (the L4R2A3 arm: roll to elbow)",
    ),
    "l4r.forearm": _f(
        (0.0, 78.0, 0.0),
        "mm",
        "KX",
        "eusview kxrl4r2a3.json rarm-elbow-r link's shapes: the arm ends 78 mm beyond the elbow",
    ),
    "l4r.arm_wheel": _f(
        (25.5, 0.0, 0.0),
        "mm",
        "KX",
        "eusview kxrl4r2a3g.json larm-shoulder-w: the L4R2A3G's passive wheel (kxreus's "
        "`:passive-wheel :shoulder`), its joint at the arm's roll joint, turning about x (at "
        "the zero pose), its disc (wheel.radius, wheel.width) centred this far out along x; "
        "no servo drives it (the project's servo table has none)",
    ),
    "r4ll.hip": _f(
        (64.5, 48.0, 0.0),
        "mm",
        "CHOSEN",
        "R4LL: the L4D body's hips (no R4LL dimensions published, §2.10)",
    ),
    "r4ll.pitch": _f((0.0, 29.0, 0.0), "mm", "CHOSEN", "R4LL: the L4D's hip-to-roll offset"),
    "r4ll.leg": _f(
        (0.0, 0.0, -110.98),
        "mm",
        "CHOSEN",
        "R4LL: the L4D's knee + ankle lengths (53 + 57.98) from pitch joint to wheel axle",
    ),
    "l6.front": _f((64.5, 43.5, -3.0), "mm", "KX", "models/kxrl6.l (§2.9)"),
    "l6.middle": _f((0.0, 75.0, -3.0), "mm", "KX", "models/kxrl6.l (§2.9)"),
    "l6.coxa": _f(52.0, "mm", "KX", "models/kxrl6.l yaw to pitch/roll (§2.9)"),
    "l6.femur": _f(69.0, "mm", "KX", "models/kxrl6.l pitch/roll to knee (§2.9)"),
    "l6.tibia": _f((78.0, 0.0, 14.0), "mm", "KX", "models/kxrl6.l foot end in knee link"),
    # ---------------------------------------------------------------- whole-robot masses
    "mass.humanoid": _f(
        _L5A3H2G_TOTAL - _L5A3H2G_EYES,
        "g",
        "KX",
        "kxrl2l5a3h2g.json total (§3.3) less its head's eye servos and eye links "
        "(leftout.L2L5A3H2G): the 20-servo reference build",
    ),
    "mass.L4D": _f(1153.07, "g", "KX", "kxrl4d.json total (§3.3)"),
    "mass.L4T": _f(616.2, "g", "KX", "kxrl4t.json total (§3.3)"),
    "mass.L4R": _f(929.82, "g", "KX", "kxrl4r.json total (§3.3)"),
    "mass.L4N": _f(717.44, "g", "KX", "kxrl4nh4.json total (§3.3)"),
    "mass.L6": _f(1028.62, "g", "KX", "kxrl6.json total (§3.3)"),
    "mass.R4LL": _f(929.82, "g", "CHOSEN", "R4LL: the L4R's total (no R4LL figure, §3.3)"),
    # whole-robot masses of the builds kxreus exports, by this package's canonical code
    "mass.L2L5A3": _f(1135.68, "g", "KX", "kxrl2l5a3.json total (§3.3)"),
    "mass.L2L5A3H2G": _f(_L5A3H2G_TOTAL, "g", "KX", "kxrl2l5a3h2g.json total (§3.3)"),
    "leftout.L2L5A3H2G": _f(
        _L5A3H2G_EYES,
        "g",
        "KX",
        "kxrl2l5a3h2g.json physics.links[22]-[24]: its `:head :h2s` has two eye servos (27.73 g "
        "cases in head-neck-p) and two eye links (43.241 g each); Kondo's KXR-L2GH has no eye "
        "servo (its project's servo table), so the model's total leaves them out",
    ),
    "mass.L2L5A4H2G": _f(1483.21, "g", "KX", "kxrl2l5a4h2g.json total (§3.3)"),
    "mass.L2L6A5H2G": _f(1700.81, "g", "KX", "kxrl2l6a5h2.json total (§3.3)"),
    "mass.L2L6A6H2G": _f(1708.46, "g", "KX", "kxrl2l6a6h2.json total (§3.3)"),
    "mass.L2L6A7H2G": _f(1824.9, "g", "KX", "kxrl2l6a7h2.json total (§3.3)"),
    "mass.L2L6A7H2GW": _f(1909.38, "g", "KX", "kxrl2l6a7h2w.json total (§3.3)"),
    "mass.L2W2L5A3H2G": _f(1690.68, "g", "KX", "kxrl2w2l5a3h2.json physics.total_mass"),
    "mass.L2W2L5A4H2G": _f(1676.41, "g", "KX", "kxrl2w2l5a4h2.json total (§3.3)"),
    "mass.L2W2L6A4H2G": _f(1878.05, "g", "KX", "kxrl2w2l6a4h2.json total (§3.3)"),
    "mass.L4R2A3G": _f(1174.47, "g", "KX", "kxrl4r2a3g.json total (§3.3)"),
    "mass.per_servo": _f(
        _KRS_3304R2_G,
        "g",
        "KX",
        "a servo more or less than the reference build: "
        "one KRS-3304R2 with horn (§3.1); its bracket is not counted",
    ),
    **LINK_ROWS,
}

#: servo count of the build each family's ``mass.*`` total was computed for
MASS_SERVOS: dict[str, int] = {
    "humanoid": 20, "L4D": 18, "L4T": 9, "L4R": 10, "L4N": 12, "L6": 18, "R4LL": 12,
}  # fmt: skip


def fig(key: str) -> float:
    v = FIGURES[key].value
    if isinstance(v, tuple):
        raise TypeError(f"{key} is a vector")
    return v


def case_shortfall() -> float:
    """Grams kxreus leaves out of every servo case it weighs: it counts each at 27.73 g, a
    KRS-3301's (``servo.mass_kxreus``), where the kits' KRS-3304R2 weighs ``servo.mass``
    (KXR-KITS.md §3.1). One place for the correction of its per-link figures and totals."""
    return fig("servo.mass") - fig("servo.mass_kxreus")


def vec(key: str) -> tuple[float, float, float]:
    v = FIGURES[key].value
    if not isinstance(v, tuple):
        raise TypeError(f"{key} is a scalar")
    return v


class LinkFigure(NamedTuple):
    """What a source gives of one link: mass (g), centre of mass (mm) and moments of inertia
    about it (g·cm²), in the link frame, left side; None where it gives none."""

    mass: float
    com: tuple[float, float, float] | None
    inertia: tuple[float, float, float] | None


def link_figures(code: str) -> dict[str, LinkFigure]:
    """Slot (``torso``, ``ankle_pitch``, ...) -> the figures of that link of the build whose
    canonical code is ``code``, where the source weighs each link (the ``lmass.CODE.*``,
    ``lcom.CODE.*`` and ``linert.CODE.*`` rows); empty for other builds.

    kxreus weighs every servo case 27.73 g (a KRS-3301's, ``servo.mass_kxreus``); each case a
    link carries (``lcases.CODE.*``) is brought to the KRS-3304R2's ``servo.mass`` at the
    link's centre of mass, so the link's centre and moments stay the source's."""
    head = f"lmass.{code}."
    extra = case_shortfall()
    out: dict[str, LinkFigure] = {}
    for key in FIGURES:
        if key.startswith(head):
            slot = key[len(head) :]
            com, inertia = f"lcom.{code}.{slot}", f"linert.{code}.{slot}"
            cases = f"lcases.{code}.{slot}"
            out[slot] = LinkFigure(
                fig(key) + (fig(cases) * extra if cases in FIGURES else 0.0),
                vec(com) if com in FIGURES else None,
                vec(inertia) if inertia in FIGURES else None,
            )
    return out


# the weighed humanoid builds whose torso stands for every build with the same legs: the KXR
# humanoid torso is one set of parts (board, battery box, back pack, frames) whatever the arms
WEIGHED_TORSO = {5: "L2W2L5A3H2G", 6: "L2L6A6H2G"}


def torso_contents(legs: int) -> LinkFigure | None:
    """What a KXR humanoid's torso weighs without the servo cases on it, from the weighed
    build with ``legs``-axis legs (:data:`WEIGHED_TORSO`), for a build no source weighs link
    by link: its board, battery box, back pack and frames. The servos on the torso (hip,
    shoulder and neck servos, by build) are counted with their own joints' links, as every
    servo of such a build is; the centre and moments stay the weighed torso's. None for legs
    no weighed build has (the two-axis legs of the kxra6g bases)."""
    code = WEIGHED_TORSO.get(legs)
    if code is None:
        return None
    torso = link_figures(code)["torso"]
    cases = fig(f"lcases.{code}.torso")
    return LinkFigure(torso.mass - cases * fig("servo.mass"), torso.com, torso.inertia)


# the leg links a build no source weighs takes from the weighed build with the same legs:
# (leg axes, ankle wheels) -> build. The five-axis leg is the six-axis one below its hip yaw
# (kxrl2l6a6h2.json's hip-roll to foot links are kxrl2g.l's five-axis leg links, their servo
# cases at 27.73 g: 78.374, 22.434, 54.3, 78.374, 38.432 g)
WEIGHED_LEGS = {
    (6, False): "L2L6A6H2G",
    (5, False): "L2L6A6H2G",
    (6, True): "L2W2L6A4H2G",
    (5, True): "L2W2L5A3H2G",
}
LEG_SLOTS = ("hip_yaw", "hip_roll", "hip_pitch", "knee_pitch", "ankle_pitch", "ankle_roll")


def weighed_legs(legs: int, wheels: bool) -> dict[str, LinkFigure]:
    """Slot -> the figures of the leg links of the weighed build with the same legs
    (:data:`WEIGHED_LEGS`), for a humanoid build no source weighs link by link: the same
    parts weigh the same in every build. A six-axis hip yaw link takes the case of its servo,
    which the weighed build counts in its torso (:func:`torso_contents` lends the torso
    without it). Empty for legs no weighed build has."""
    code = WEIGHED_LEGS.get((legs, wheels))
    if code is None:
        return {}
    have = link_figures(code)
    slots = LEG_SLOTS[1 if legs == 5 else 0 :] + (("ankle_wheel",) if wheels else ())
    out = {s: have[s] for s in slots if s in have}
    if "hip_yaw" in out:
        yaw = out["hip_yaw"]
        out["hip_yaw"] = LinkFigure(yaw.mass + fig("servo.mass"), yaw.com, yaw.inertia)
    return out


# the arm links a humanoid build no source weighs takes from the weighed build whose arm has
# the same joints: its links are the same parts (frozenset of the arm's slots -> build)
WEIGHED_ARMS: dict[frozenset[str], str] = {
    frozenset(("shoulder_pitch", "shoulder_roll", "elbow_pitch", "gripper")): "L2W2L5A3H2G",
    frozenset(
        ("shoulder_pitch", "shoulder_roll", "shoulder_yaw", "elbow_pitch", "gripper")
    ): "L2W2L6A4H2G",
    frozenset(
        (
            "shoulder_pitch",
            "shoulder_roll",
            "shoulder_yaw",
            "elbow_pitch",
            "wrist_pitch",
            "wrist_roll",
            "gripper",
        )
    ): "L2L6A6H2G",
}
ARM_SLOTS = frozenset(s for arm in WEIGHED_ARMS for s in arm) | {"wrist_yaw"}


def weighed_arms(slots: Iterable[str]) -> dict[str, LinkFigure]:
    """Slot -> the figures of the arm links of the weighed build whose arm has exactly the
    arm joints among ``slots`` (:data:`WEIGHED_ARMS`), for a humanoid build no source weighs
    link by link; empty for an arm no weighed build has (A5, A7, an arm without its gripper,
    whose elbow link would carry one case fewer). The shoulder pitch link takes the case of
    its servo, which the weighed build counts in its torso (as the six-axis hip yaw's)."""
    arm = frozenset(s for s in slots if s in ARM_SLOTS)
    code = WEIGHED_ARMS.get(arm)
    if code is None:
        return {}
    have = link_figures(code)
    out = {s: have[s] for s in sorted(arm) if s in have}
    if "shoulder_pitch" in out:
        sp = out["shoulder_pitch"]
        out["shoulder_pitch"] = LinkFigure(sp.mass + fig("servo.mass"), sp.com, sp.inertia)
    return out


def provenance_markdown() -> str:
    """The provenance table as Markdown (docs/robots.md carries it; a test keeps them equal)."""
    rows = ["| source | what | licence |", "|---|---|---|"]
    rows += [f"| {k} | {what} | {lic} |" for k, (what, lic) in SOURCES.items()]
    rows += ["", "| figure | value | unit | source | where |", "|---|---|---|---|---|"]
    for key, f in FIGURES.items():
        v = f.value
        text = ", ".join(f"{x:g}" for x in v) if isinstance(v, tuple) else f"{v:g}"
        rows.append(f"| `{key}` | {text} | {f.unit} | {f.source} | {f.where} |")
    return "\n".join(rows) + "\n"
