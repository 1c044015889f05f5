"""Lint a HeartToHeart4 project before it goes on a robot (``rcb4hv project check``).

:func:`check_project` returns :class:`Finding` records. The wire, ROM and emulator layers take
every frame the board takes, so values outside the documented ranges build, upload and play;
this is where they are reported. Severity ``error``: the board would stop (ROMERR or a
command error) or the project does not build. ``warning``: it runs, but probably not as meant.

Codes:

``build-error`` (error)
    :func:`rcb4hv.project.image.project_description` refuses the project.
``invalid-instruction`` (error)
    A motion entry that is not a command frame the board runs (bad checksum, reserved bits).
``target-empty-slot`` (error), ``target-outside-rom`` (error), ``target-mid-instruction``
(error), ``target-past-motion`` (error), ``target-not-motion-start`` (warning),
``target-outside-motions`` (warning)
    Where the startup motion, a priority check, the low-power motion or a JUMP/CALL lands:
    a slot that holds no motion, past the 256 KB ROM (``FFFFFF`` is an unresolved flowchart
    target), inside an instruction, after the motion's last byte (erased ROM), on an
    instruction that is not the start of a motion, or in the system area. The RETURN stub at
    3CB80h (HeartToHeart4's "no startup motion") is a valid target.
``priority-without-motion`` (warning)
    A priority check configured with ``Address`` ``-1`` (see :mod:`rcb4hv.project.options`).
``position-out-of-range``, ``stretch-out-of-range``, ``speed-zero`` (warnings)
    Documented ranges (:mod:`rcb4hv.protocol.ranges`): positions 3500-11500 (besides hold and
    free), 12h values 1-127, servo speeds 1-255.
``no-final-return`` (error when a path runs off the motion's end into erased ROM, else warning)
``unknown-ics`` (warning for servo commands, which skip the servo; error for an ICS operand of a
data command, which stops the program)
``unreachable-code`` (warning)
    Instructions no path reaches. HeartToHeart4's own closing ``RETURN`` (``03 0D 10 FF``)
    after the flowchart's RETURN is not reported.
``button-bound-twice`` (warning)
    The same button word and comparison start two motions: the first package (lowest slot)
    wins and the other never plays from the remote.
``button-on-empty-slot`` (warning)
    A slot with no motion keeps a button binding.
``joint-limit`` (warning), ``joint-advisory`` (warning)
    Given the robot model: a servo position beyond its joint's hard (mechanical) limits, where
    the brackets collide or the servo's travel ends; or inside them but outside the joint's
    narrower advisory range (e.g. a library's software limits, which the robot maker's own
    motions may exceed). One finding per motion and joint, at its first instruction
    (:meth:`rcb4hv.robot.model.RobotModel.limit_check`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Final, Literal

from rcb4hv.asm import format_command
from rcb4hv.hth4 import Motion, Project
from rcb4hv.project.image import project_description
from rcb4hv.project.motionflow import MotionCode, motion_code
from rcb4hv.project.relocate import project_layout
from rcb4hv.protocol import (
    ALWAYS,
    Call,
    Ics,
    Jump,
    Return,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
)
from rcb4hv.protocol.ranges import (
    documented_position,
    documented_servo_speed,
    documented_stretch,
)
from rcb4hv.robot.model import RobotModel
from rcb4hv.rom import layout

__all__ = ["Finding", "Severity", "check_project", "unlisted_servos"]

Severity = Literal["error", "warning"]
KRI3_ICS: Final = 35


@dataclass(frozen=True)
class Finding:
    """One lint result: where (slot, motion name, ROM address, instruction) and why."""

    severity: Severity
    code: str
    slot: int | None
    name: str
    address: int | None
    instruction: str
    reason: str

    def to_dict(self) -> dict[str, object]:
        return {
            "severity": self.severity,
            "code": self.code,
            "slot": self.slot,
            "name": self.name,
            "address": None if self.address is None else f"{self.address:05X}",
            "instruction": self.instruction,
            "reason": self.reason,
        }


class _Map:
    """Which motion slot holds a ROM address, and where its instructions start."""

    def __init__(
        self, project: Project, codes: dict[int, MotionCode], stub: int = layout.STARTUP_STUB
    ) -> None:
        self.stub = stub
        entries = sorted(project.motions, key=lambda m: m.address)
        self.regions: list[tuple[int, int, Motion]] = []
        for i, m in enumerate(entries):
            if i + 1 < len(entries):
                end = entries[i + 1].address
            elif i:
                end = m.address + (m.address - entries[i - 1].address)
            else:
                end = m.address + layout.MOTION_SIZE
            self.regions.append((m.address, end, m))
        self.codes = codes

    def motion_at(self, address: int) -> Motion | None:
        for lo, hi, m in self.regions:
            if lo <= address < hi:
                return m
        return None

    def problem(
        self, address: int, *, entry: bool, origin: Motion | None = None
    ) -> tuple[Severity, str, str] | None:
        """(severity, code, words) of what is wrong with a branch to ``address``, or None.

        ``entry``: the target should be the start of a motion (startup, priority, low power);
        ``origin``: the motion a JUMP/CALL comes from (branches inside it are fine).
        """
        if address >= layout.ROM_SIZE:
            why = "an unresolved flowchart target" if address == 0xFFFFFF else "past the ROM"
            return "error", "target-outside-rom", f"{why} (the board wraps it into erased ROM)"
        m = self.motion_at(address)
        if m is None:
            if address == self.stub:
                return None
            return "warning", "target-outside-motions", "lands outside the motion slots"
        code = self.codes.get(m.slot)
        if code is None:
            return "error", "target-empty-slot", f"slot {m.slot} holds no motion"
        if address >= m.address + code.size:
            return "error", "target-past-motion", f"lands after the end of slot {m.slot}"
        if address not in code.at:
            why = f"lands inside an instruction of slot {m.slot}"
            return "error", "target-mid-instruction", why
        if address == m.address or (not entry and origin is m):
            return None
        return "warning", "target-not-motion-start", f"lands inside slot {m.slot}, not at its start"


def _call_text(address: int) -> str:
    """The CALL a setting makes, as text; an address past 24 bits cannot be one."""
    if 0 <= address <= 0xFFFFFF:
        return format_command(Call(address, ALWAYS))
    return f"CALL {address} (does not fit a 24-bit address)"


def _name(m: Motion | None) -> str:
    return (m.name or "") if m is not None else ""


def _ics_list(items: Iterable[int]) -> str:
    return ", ".join(str(k) for k in items)


def _allocated(project: Project) -> set[int]:
    """The ICS numbers a servo instruction may select: the servo table's, and the KRI-3's."""
    return {s.device_number for s in project.servos if s.in_use} | {KRI3_ICS}


def _selected(cmd: object) -> list[int]:
    """The ICS numbers a servo instruction moves, stretches or speeds (none for others)."""
    if isinstance(cmd, (SetStretch, SetSpeed)):
        return [k for k, _ in cmd.values]
    return [k for k, _ in _moves(cmd)]


def _value_findings(cmd: object, allocated: set[int]) -> list[tuple[Severity, str, str]]:
    """Documented-range and servo-table problems of one decoded instruction."""
    out: list[tuple[Severity, str, str]] = []
    moves: list[tuple[int, int, int]] = []
    if isinstance(cmd, RunSingleServo):
        moves = [(cmd.ics, cmd.speed, cmd.position)]
    elif isinstance(cmd, RunConstFrameServo):
        moves = [(k, cmd.speed, p) for k, p in cmd.positions]
    elif isinstance(cmd, RunSeriesServo):
        moves = list(cmd.moves)
    if moves:
        bad = [(k, p) for k, _, p in moves if not documented_position(p)]
        if bad:
            text = ", ".join(f"ICS {k}: {p}" for k, p in bad[:6]) + (" ..." if len(bad) > 6 else "")
            why = f"position outside 3500-11500 ({text})"
            out.append(("warning", "position-out-of-range", why))
        zero = sorted({k for k, s, _ in moves if not documented_servo_speed(s)})
        if zero:
            out.append(
                (
                    "warning",
                    "speed-zero",
                    f"speed 0 for ICS {_ics_list(zero)} (documented 1-255; "
                    "the emulator moves at speed 1)",
                )
            )
    if isinstance(cmd, (SetStretch, SetSpeed)):
        what = "stretch" if isinstance(cmd, SetStretch) else "speed"
        bad = [(k, v) for k, v in cmd.values if not documented_stretch(v)]
        if bad:
            text = ", ".join(f"ICS {k}: {v}" for k, v in bad[:6]) + (" ..." if len(bad) > 6 else "")
            out.append(("warning", "stretch-out-of-range", f"{what} outside 1-127 ({text})"))
    missing = sorted(k for k in _selected(cmd) if k not in allocated)
    if missing:
        out.append(("warning", "unknown-ics", _ics_list(missing)))
    for attr in ("dst", "src"):
        op = getattr(cmd, attr, None)
        if isinstance(op, Ics) and op.ics not in allocated:
            out.append(
                (
                    "error",
                    "unknown-ics",
                    f"ICS {op.ics} not in the servo table: the program stops (command error)",
                )
            )
    return out


def _moves(cmd: object) -> list[tuple[int, int]]:
    """(ICS, position) of every servo a servo-moving instruction sets."""
    if isinstance(cmd, RunSingleServo):
        return [(cmd.ics, cmd.position)]
    if isinstance(cmd, RunConstFrameServo):
        return list(cmd.positions)
    if isinstance(cmd, RunSeriesServo):
        return [(k, p) for k, _, p in cmd.moves]
    return []


def unlisted_servos(project: Project, slot: int) -> list[int]:
    """The ICS numbers motion ``slot`` moves, stretches or speeds that the project's servo
    table lacks: the board skips them (``unknown-ics``), as in a motion of another robot."""
    found = {k for _, cmd in motion_code(project.motion(slot)).instructions for k in _selected(cmd)}
    return sorted(found - _allocated(project))


def _limit_findings(
    m: Motion, code: MotionCode, model: RobotModel, add: Callable[..., None]
) -> None:
    """``joint-limit`` / ``joint-advisory``: one per motion and joint, at the first
    instruction, with the extreme value and how many instructions go there."""
    mapped = set(model.indices)
    seen: dict[tuple[str, str], tuple[int, str, int, int, float]] = {}
    for addr, cmd in code.instructions:
        for ics, value in _moves(cmd):
            if ics not in mapped or not documented_position(value) or value in (0x7FFF, 0x8000):
                continue
            joint = model.servo(ics).joint
            angle = model.motion_angle(ics, value)
            verdict = model.limit_check(joint, angle)
            if verdict == "ok":
                continue
            first = seen.get((verdict, joint))
            if first is None:
                seen[(verdict, joint)] = (addr, format_command(cmd), 1, value, angle)
            else:
                far = abs(angle) > abs(first[4])
                seen[(verdict, joint)] = (
                    first[0], first[1], first[2] + 1,
                    value if far else first[3], angle if far else first[4],
                )  # fmt: skip
    for (kind, joint), (addr, text, count, value, angle) in seen.items():
        j = model.joint(joint)
        hard = kind == "hard"
        lo, hi = (j.lower, j.upper) if hard else j.advisory_range
        what = "hard (mechanical) limits" if hard else "advisory range"
        add(
            "warning",
            "joint-limit" if hard else "joint-advisory",
            f"{joint} at {math.degrees(angle):.1f} deg (value {value}), outside the joint's "
            f"{what} {math.degrees(lo):.1f}..{math.degrees(hi):.1f} deg, in {count} "
            f"instruction{'s' if count > 1 else ''} (the first here)",
            address=addr,
            instruction=text,
            slot=m.slot,
            name=_name(m),
        )


def check_project(project: Project, model: RobotModel | None = None) -> list[Finding]:
    """Every finding for ``project``, errors first, then by slot and address. With the
    robot ``model``, joint angles are checked against its hard limits and advisory ranges."""
    findings: list[Finding] = []

    def add(
        severity: Severity,
        code: str,
        reason: str,
        *,
        slot: int | None = None,
        name: str = "",
        address: int | None = None,
        instruction: str = "",
    ) -> None:
        findings.append(Finding(severity, code, slot, name, address, instruction, reason))

    lay = layout.HTH4_22
    try:
        lay = project_layout(project)
        project_description(project, lay)
    except ValueError as exc:
        add("error", "build-error", str(exc))
    codes = {m.slot: motion_code(m) for m in project.used_motions}
    rom = _Map(project, codes, lay.startup_stub)
    allocated = _allocated(project)

    def setting(what: str, address: int) -> None:
        p = rom.problem(address, entry=True)
        if p is not None:
            m = rom.motion_at(address)
            add(
                p[0],
                p[1],
                f"{what} {address:05X}h: {p[2]}",
                slot=None if m is None else m.slot,
                name=_name(m),
                address=address,
                instruction=_call_text(address),
            )

    if project.startup_motion_address >= 0:
        setting("startup motion", project.startup_motion_address)
    for index, pm in project.active_priority_motions:
        if pm.address < 0:
            add(
                "warning",
                "priority-without-motion",
                f"priority check {index} ({pm.port} {pm.compare_type} {pm.value}) has no "
                "motion (Address -1): nothing runs when it holds",
                name=pm.name or "",
            )
        else:
            setting(f"priority check {index} motion", pm.address)
    if project.low_power_motion_address >= 0:
        setting("low-power motion", project.low_power_motion_address)

    bound: dict[tuple[int, str], Motion] = {}
    for m in sorted(project.motions, key=lambda m: m.slot):
        if not m.button_data:
            continue
        if m.is_empty:
            add(
                "warning",
                "button-on-empty-slot",
                f"slot {m.slot} holds no motion but keeps button binding {m.button_data:#06x}",
                slot=m.slot,
                address=m.address,
            )
            continue
        key = (m.button_data, m.compare_type)
        first = bound.setdefault(key, m)
        if first is not m:
            add(
                "warning",
                "button-bound-twice",
                f"button {m.button_data:#06x} ({m.compare_type}) also starts slot {first.slot} "
                f"({_name(first)}); the first binding wins, this one never plays",
                slot=m.slot,
                name=_name(m),
                address=m.address,
            )

    for m in project.used_motions:
        _check_motion(m, codes[m.slot], rom, allocated, add)
        if model is not None:
            _limit_findings(m, codes[m.slot], model, add)
    order = {"error": 0, "warning": 1}
    findings.sort(key=lambda f: (order[f.severity], f.slot or 0, f.address or 0))
    return findings


def _check_motion(
    m: Motion,
    code: MotionCode,
    rom: _Map,
    allocated: set[int],
    add: Callable[..., None],
) -> None:
    where = {"slot": m.slot, "name": _name(m)}
    for addr, raw, why in code.invalid:
        add("error", "invalid-instruction", why, address=addr, instruction=f".byte {raw}", **where)
    unknown: dict[str, tuple[int, str, int]] = {}  # ICS list -> (first address, text, count)
    for addr, cmd in code.instructions:
        text = format_command(cmd)
        for sev, c, why in _value_findings(cmd, allocated):
            if c == "unknown-ics" and sev == "warning":  # one finding per motion and ICS set
                first = unknown.setdefault(why, (addr, text, 0))
                unknown[why] = (first[0], first[1], first[2] + 1)
                continue
            add(sev, c, why, address=addr, instruction=text, **where)
        if isinstance(cmd, (Jump, Call)):
            p = rom.problem(cmd.address, entry=False, origin=m)
            if p is not None:
                kind = "JUMP" if isinstance(cmd, Jump) else "CALL"
                reason = f"{kind} target {cmd.address:05X}h: {p[2]}"
                add(p[0], p[1], reason, address=addr, instruction=text, **where)
    for ics, (addr, text, count) in unknown.items():
        add(
            "warning",
            "unknown-ics",
            f"ICS {ics} not in the servo table but moved by {count} instruction"
            f"{'s' if count > 1 else ''} (the first here): the board skips them",
            address=addr,
            instruction=text,
            **where,
        )
    reached = code.reachable({a for a in _rom_targets(rom) if a in code.at})
    last = code.instructions[-1] if code.instructions else None
    if last is not None and not isinstance(last[1], Return):
        falls = code.falls_off(reached)
        add(
            "error" if falls else "warning",
            "no-final-return",
            "the motion runs past its last instruction into erased ROM"
            if falls
            else "the motion does not end with RETURN",
            address=last[0],
            instruction=format_command(last[1]),
            **where,
        )
    texts = {a: format_command(c) for a, c in code.instructions}
    for start, count in code.unreachable_runs(reached):
        add(
            "warning",
            "unreachable-code",
            f"{count} instruction{'s' if count > 1 else ''} no path reaches",
            address=start,
            instruction=texts.get(start, ".byte"),
            **where,
        )


def _rom_targets(rom: _Map) -> set[int]:
    """Every JUMP/CALL target of every motion (entry points into other motions)."""
    out: set[int] = set()
    for code in rom.codes.values():
        for _, cmd in code.instructions:
            if isinstance(cmd, (Jump, Call)):
                out.add(cmd.address)
    return out
