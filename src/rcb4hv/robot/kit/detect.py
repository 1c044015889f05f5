"""A project's kit model from its own evidence: the title's kit code and the servo names.

1. The servo names give each servo's role (:mod:`~rcb4hv.robot.kit.names`); spares are left
   out. Every family whose frame takes all named servos and has its core joints is a
   candidate (:mod:`~rcb4hv.robot.kit.mapping`).
2. The title's kit code (:mod:`~rcb4hv.robot.kit.code`) picks among them; when the code names
   a family the servos do not fit, the servo names win and the evidence says so. A code
   given with ``--robot`` (``force``) whose frame the names contradict is refused, naming
   each servo and joint, whatever the family; names that say nothing take its stock build.
3. No code and several candidates: :class:`~rcb4hv.errors.AmbiguousRobotError` lists them
   (``--robot kxr:CODE`` picks one); none: :class:`~rcb4hv.errors.NoRobotModelError`.
4. Signs come from the kit's assembly convention, then the project's home pose is checked:
   left and right symmetric (a pair that is symmetric only with the left sign turned is
   turned, and the evidence says so), and for a biped the soles level with the torso.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

from rcb4hv.errors import AmbiguousRobotError, NoRobotModelError
from rcb4hv.protocol.memory import CENTER, COUNTS_PER_DEGREE
from rcb4hv.robot.geometry import geom_lowest_z
from rcb4hv.robot.kinematics import forward
from rcb4hv.robot.kit.build import (
    canonical_code,
    is_centre,
    kit_model,
    kit_signs,
    stock_joint_maps,
)
from rcb4hv.robot.kit.code import FAMILIES, Family, KitCode, parse_kit_code
from rcb4hv.robot.kit.convention import LIMBS
from rcb4hv.robot.kit.mapping import Placement, map_roles
from rcb4hv.robot.kit.names import Role, parse_servo_name
from rcb4hv.robot.model import RobotModel

__all__ = ["SYMMETRY_TOLERANCE_DEG", "Detection", "detect_kit"]

SYMMETRY_TOLERANCE_DEG = 5.0
"""A home pose is left-right symmetric when mirrored joint angles agree within this (deg):
Kondo's trims leave a few degrees between the sides (chosen)."""
_SIGNIFICANT = 100  # counts: a home value this far from centre tells a joint's direction
_LEVEL_DEG = 10.0  # a biped's soles are level within this of the torso at home (chosen)


@dataclass(frozen=True)
class Detection:
    """The chosen model and the evidence for it."""

    model: RobotModel
    title: str
    code: KitCode | None
    servos: tuple[tuple[int, str, str | None, int | None], ...]  # (index, name, joint, sign)
    notes: tuple[str, ...] = ()
    checks: tuple[tuple[str, bool, str], ...] = ()
    candidates: tuple[str, ...] = field(default=())
    conflicts: tuple[str, ...] = ()  # what the title or --robot's code says that the names do not

    def as_dict(self) -> dict[str, object]:
        return {
            "model": self.model.name,
            "title": self.model.title,
            "project_title": self.title,
            "kit_code": self.code.code if self.code else None,
            "family": self.code.family if self.code else None,
            "candidates": list(self.candidates),
            "servos": [
                {"index": i, "name": n, "joint": j, "sign": s} for i, n, j, s in self.servos
            ],
            "notes": list(self.notes),
            "conflicts": list(self.conflicts),
            "checks": [{"check": c, "ok": ok, "detail": d} for c, ok, d in self.checks],
        }


def _roles(names: Mapping[int, str]) -> tuple[dict[int, tuple[str, Role]], list[int]]:
    roles: dict[int, tuple[str, Role]] = {}
    spare: list[int] = []
    for index, name in names.items():
        role = parse_servo_name(name)
        if role is None:
            spare.append(index)
        else:
            roles[index] = (name, role)
    return roles, spare


def _humanoid_code(base: KitCode | None, p: Placement) -> KitCode:
    bases = p.bases
    probe = KitCode("humanoid", "", width=base.width if base else "standard")
    text = canonical_code(probe, sorted(bases))
    parsed = parse_kit_code("kxr:" + text)
    assert parsed is not None
    return replace(parsed, width=probe.width)


def _conflicts(code: KitCode, names: KitCode, said_by: str) -> list[str]:
    """What ``code`` (from the title, or ``--robot``) claims that the servo names contradict."""
    out = []
    for what in ("legs", "arms", "head"):
        said, found = getattr(code, what), getattr(names, what)
        if said is not None and said != found:
            named = f"the servo names {found}" if found is not None else "the servo names none"
            out.append(f"{said_by} says {what} {said}, {named}: names win")
    for what in ("gripper", "wheels"):
        if getattr(code, what) and not getattr(names, what):
            out.append(f"{said_by} says {what}, the servo names have none: names win")
    return out


def _candidates(
    roles: Mapping[int, tuple[str, Role]], code: KitCode | None
) -> dict[Family, Placement]:
    out: dict[Family, Placement] = {}
    for family in FAMILIES:
        p = map_roles(family, roles, wheel_tips=code is not None and code.family == family)
        if p.fits:
            out[family] = p
    return out


def _joint_map(code: KitCode, p: Placement) -> dict[str, tuple[int, int]]:
    signs = kit_signs(code)
    out: dict[str, tuple[int, int]] = {}
    for joint, index in p.joints.items():
        base = joint[2:] if joint[:2] in ("l_", "r_") else joint
        right, left = signs[base]
        out[joint] = (
            index,
            left if joint.startswith("l_") and not is_centre(code, base) else right,
        )
    return out


def _symmetry(
    code: KitCode, jm: dict[str, tuple[int, int]], home: Mapping[int, int]
) -> tuple[list[str], list[tuple[str, bool, str]]]:
    """Turn left signs the home pose shows reversed; the notes and the check rows."""
    notes: list[str] = []
    bad: list[str] = []
    probe = kit_model(code, jm)
    for joint, (index, sign) in sorted(jm.items()):
        if not joint.startswith("l_") or "r_" + joint[2:] not in jm:
            continue
        other, osign = jm["r_" + joint[2:]]
        if index not in home or other not in home or joint.endswith("wheel"):
            continue
        cl, cr = home[index] - CENTER, home[other] - CENTER
        if min(abs(cl), abs(cr)) < _SIGNIFICANT:
            continue
        kind = probe.joint(joint).kind
        mirror = -1 if kind in ("roll", "yaw") else 1
        left, right = sign * cl / COUNTS_PER_DEGREE, osign * cr / COUNTS_PER_DEGREE
        if abs(mirror * left - right) <= SYMMETRY_TOLERANCE_DEG:
            continue
        if abs(-mirror * left - right) <= SYMMETRY_TOLERANCE_DEG:
            jm[joint] = (index, -sign)
            notes.append(f"{joint}: sign turned to {-sign:+d}: the home pose is symmetric so")
        else:
            bad.append(f"{joint[2:]} ({left:+.0f}° / {right:+.0f}°)")
    row = ("home pose left-right symmetric", not bad, ", ".join(bad) or "all pairs agree")
    return notes, [row]


def _within_limits(
    code: KitCode, jm: dict[str, tuple[int, int]], extremes: Mapping[int, tuple[int, int]]
) -> tuple[list[str], list[tuple[str, bool, str]]]:
    """Turn a pair of signs the project's own motions show reversed. Kondo's motions are
    physically valid, so where the kit's convention sends a left-right pair past its
    mechanical limits and the other sign keeps every value inside them, both sides turn (a
    pair turned together keeps the home pose symmetric, so :func:`_symmetry` cannot tell).
    ``extremes``: the smallest and largest motion value of each ICS number within the
    servo's travel (values beyond it only push a joint to its end)."""
    notes: list[str] = []
    bad: list[str] = []
    probe = kit_model(code, jm)

    def past(pair: tuple[str, str], flip: int) -> float:
        """Degrees past the hard limits, the worst value of the pair with its signs times
        ``flip`` (<= 0: inside)."""
        worst = -math.inf
        for name in pair:
            j, index = probe.joint(name), jm[name][0]
            lo, hi = math.degrees(j.lower), math.degrees(j.upper)
            for v in extremes.get(index, ()):
                a = flip * math.degrees(probe.motion_angle(index, v))  # the one conversion
                worst = max(worst, lo - a, a - hi)
        return worst

    for joint in sorted(jm):
        other = "r_" + joint[2:]
        if not joint.startswith("l_") or other not in jm or joint.endswith("wheel"):
            continue
        pair = (joint, other)
        now = past(pair, 1)
        if now <= 0:
            continue
        if past(pair, -1) <= 0:
            for name in pair:
                index, sign = jm[name]
                jm[name] = (index, -sign)
            notes.append(
                f"{joint[2:]}: both signs turned: the project's motions go {now:.0f}° past its "
                "mechanical limits with the kit's convention and stay inside them so"
            )
        else:
            bad.append(f"{joint[2:]} ({now:.0f}° past)")
    row = ("motions within the mechanical limits", not bad, ", ".join(bad) or "every joint")
    return notes, [row]


def _level(model: RobotModel) -> list[tuple[str, bool, str]]:
    """A biped's soles level with its torso at home (feet flat, upright)."""
    feet = [f"{s}_ankle_roll_link" for s in ("l", "r")]
    if not all(any(link.name == f for link in model.links) for f in feet):
        return []
    frames = forward(model, dict(model.home))
    worst = 0.0
    for f in feet:
        zz = frames[f][2][2]  # the sole's z axis against the torso's (root frame)
        worst = max(worst, math.degrees(math.acos(max(-1.0, min(1.0, zz)))))
    ok = worst <= _LEVEL_DEG
    return [("home pose feet flat", ok, f"soles tilt {worst:.1f}° from the torso")]


def _feet_down(model: RobotModel, family: Family) -> list[tuple[str, bool, str]]:
    """A legged robot stands at home: every limb's last part reaches below the torso."""
    if family == "humanoid" or not model.home:
        return []
    frames = forward(model, dict(model.home))
    torso_bottom = min(g.pos[2] - g.size[2] / 2 for g in model.link("torso").geoms)
    high = []
    for limb in LIMBS[family].values():
        for side in ("l_", "r_"):
            link = next(
                (
                    side + s + "_link"
                    for s in reversed(limb)
                    if any(k.name == side + s + "_link" for k in model.links)
                ),
                None,
            )
            if link is None:
                continue
            low = min(geom_lowest_z(g, frames[link]) for g in model.link(link).geoms)
            if low > torso_bottom:
                high.append(link.removesuffix("_link"))
    detail = (
        "every limb reaches below the torso" if not high else "above the torso: " + ", ".join(high)
    )
    return [("home pose stands on its limbs", not high, detail)]


def _limb_ics(stock: Mapping[str, tuple[int, int]]) -> set[int]:
    """The ICS numbers of a stock joint map's limbs (left and right joints; not the head)."""
    return {i for j, (i, _) in stock.items() if j[:2] in ("l_", "r_")}


STOCK_SOURCE = "the kit's stock ICS numbers (KXR-KITS.md §1.4)"
"""Where a joint map taken from a stock build came from (the report's evidence)."""


def _escape(code: KitCode) -> str:
    """How to play on a KXR-``code`` all the same (docs/robots.md): a joint map of your own."""
    return (
        f" (to use a KXR-{code.code} all the same, export it: rcb4hv robot export "
        f"kxr:{code.code} -o X.urdf --joint-map X.toml, map the servos in X.toml, then "
        "--robot X.urdf)"
    )


def _forced_stock(
    force: KitCode, roles: Mapping[int, tuple[str, Role]], used: set[int], notes: list[str]
) -> tuple[KitCode, dict[str, tuple[int, int]], str]:
    """``--robot kxr:CODE`` on a project whose servo names do not give that family's frame:
    the joints of the family's first stock build whose every limb the project uses, provided
    no servo name contradicts it. A named servo that has no joint in the family (a shoulder
    on a hexapod), or whose name gives another joint than the stock one at its ICS number,
    refuses the code, naming the servo and the joint, whichever family it is; names that say
    nothing (blank, spares) never do. The servos a stock build lacks are left out."""
    stocks = stock_joint_maps(force)
    fitting = [st for st in stocks if _limb_ics(st) <= used]
    fitting.sort(key=lambda st: len(used - {i for i, _ in st.values()}))  # fewest left out
    at = {i: j for j, (i, _) in (fitting or stocks)[0].items()}
    placed = map_roles(force.family, roles, wheel_tips=True)
    clash = [
        why + (f" (ICS {i} is the stock {at[i]})" if i in at else "") for i, why in placed.unplaced
    ]
    clash += [
        f"{roles[i][0]}: {joint} by its name, "
        + (f"ICS {i} is the stock {at[i]}" if i in at else f"no stock joint at ICS {i}")
        for joint, i in sorted(placed.joints.items(), key=lambda item: item[1])
        if at.get(i) != joint
    ]
    if clash:
        raise NoRobotModelError(
            f"the servo names do not fit a KXR-{force.code}: " + "; ".join(clash) + _escape(force)
        )
    if not fitting:
        lacking = ", ".join(f"{i} ({j})" for i, j in sorted(at.items()) if i not in used)
        raise NoRobotModelError(
            f"the servo names do not give a KXR-{force.code}'s joints and the project has no "
            f"servo at its stock ICS number(s) {lacking}; it uses {sorted(used)}" + _escape(force)
        )
    stock = {j: (i, s) for j, (i, s) in fitting[0].items() if i in used}
    why = "no joint named" if not roles else "some joints named, each at its stock ICS number"
    notes.append(
        f"the servo names do not fit a KXR-{force.code} ({why}), but the ICS numbers are a "
        "stock build's: joints from its stock map"
    )
    left = sorted(used - {i for i, _ in stock.values()})
    if left:
        notes.append(f"servo(s) {left}: no joint of the stock KXR-{force.code}: left out")
    return force, stock, STOCK_SOURCE


def _choose(
    code: KitCode | None,
    force: KitCode | None,
    roles: Mapping[int, tuple[str, Role]],
    cands: Mapping[Family, Placement],
    used: set[int],
    notes: list[str],
) -> tuple[KitCode, dict[str, tuple[int, int]], str]:
    """The build (its code), its joint map and where the map came from (steps 1-3)."""
    by_names = "the project's servo names (右/左, part, axis, limb)"
    if force is not None and force.family not in cands:
        return _forced_stock(force, roles, used, notes)
    if code is not None and code.family not in cands:
        for stock in stock_joint_maps(code):
            if not _limb_ics(stock) <= used <= {i for i, _ in stock.values()}:  # head optional
                continue
            stock = {j: (i, s) for j, (i, s) in stock.items() if i in used}
            why = "; ".join(w for _, w in map_roles(code.family, roles).unplaced)
            notes.append(
                f"the servo names do not fit a KXR-{code.code} ({why or 'no joint named'}), "
                "but the ICS numbers are a stock build's: joints from its stock map"
            )
            return code, stock, STOCK_SOURCE
    family: Family
    if code is not None and code.family in cands:
        family = code.family
    elif len(cands) == 1:
        family = next(iter(cands))
        if code is not None:
            notes.append(f"the title says {code.family}, the servo names a {family}: names win")
    elif cands:
        names_ = tuple(f"kxr:{f}" for f in cands)
        raise AmbiguousRobotError(
            f"the servo names fit {', '.join(names_)}: pick one with --robot", names_
        )
    else:
        raise NoRobotModelError("the servo names describe no KXR kit")
    placement = cands[family]
    if placement.side_conflicts:
        notes.append(
            f"servo(s) {sorted(placement.side_conflicts)} are named for the other side: "
            "the kit's wiring puts the right side on even ICS numbers, so they are taken "
            "as wired (KXR-KITS.md §1.2)"
        )
    if family == "humanoid":
        effective = _humanoid_code(code, placement)
    else:
        effective = code if code is not None and code.family == family else KitCode(family, family)
    return effective, _joint_map(effective, placement), by_names


def detect_kit(
    title: str | None,
    names: Mapping[int, str],
    home: Mapping[int, int] | None = None,
    *,
    force: KitCode | None = None,
    extremes: Mapping[int, tuple[int, int]] | None = None,
) -> Detection:
    """The kit model of a project (see the module docstring). ``names``: ICS number -> servo
    name of the slots in use; ``home``: the home pose's motion values by ICS number; ``force``:
    the kit code ``--robot kxr:CODE`` gives (its family wins over the names); ``extremes``:
    the smallest and largest value the project's motions give each ICS number within the
    servo's travel (:func:`_within_limits`)."""
    roles, spare = _roles(names)
    code = force or parse_kit_code(title)
    notes: list[str] = []
    if spare:
        notes.append(f"no joint in the name of servo(s) {sorted(spare)}: left out")
    cands = _candidates(roles, code)
    effective, jm, source = _choose(code, force, roles, cands, set(names), notes)
    conflicts: list[str] = []
    if code is not None and code.family == effective.family == "humanoid":
        said_by = f"--robot kxr:{code.code}" if force is not None else "the title"
        conflicts = _conflicts(code, effective, said_by)
        notes += conflicts
    checks: list[tuple[str, bool, str]] = []
    if home:
        sym_notes, rows = _symmetry(effective, jm, home)
        notes += sym_notes
        checks += rows
    if extremes:
        lim_notes, rows = _within_limits(effective, jm, extremes)
        notes += lim_notes
        checks += rows
    counts = {j: home[i] - CENTER for j, (i, _) in jm.items() if home and i in home}
    model = kit_model(
        effective,
        jm,
        home_counts=counts,
        sources={"joint map": source},
    )
    checks += _level(model) + _feet_down(model, effective.family)
    servos = tuple(
        (i, names[i], model.servo(i).joint if i in model.indices else None,
         model.servo(i).sign if i in model.indices else None)
        for i in sorted(names)
    )  # fmt: skip
    return Detection(
        model, title or "", code, servos, tuple(notes), tuple(checks), conflicts=tuple(conflicts)
    )
