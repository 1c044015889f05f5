"""What differs between two projects, in words: settings, servos, motions, poses, servo values.

:func:`diff_projects` returns one :class:`Change` per difference, in file order: project
settings (``Config``, KRI-3, startup and priority motions, ...), servo settings (trim, home
position, ... per ICS number), then per motion slot: a motion added or removed, renamed,
bound to another button, and inside a motion each pose added or removed, each changed frame
count and each changed servo value (one change per servo), and each other block added,
removed or changed. Poses are numbered from 1 as the editor shows them. An empty list means
the two projects hold the same data.

Inside a motion the entries are matched with :class:`difflib.SequenceMatcher`; a JUMP /
CALL within the motion is compared without its address (an inserted pose moves every later
address), so an inserted pose shows as one added pose, not as changed branches.
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass, fields
from typing import Any

from rcb4hv.hth4.model import Motion, PriorityMotionSlot, Project, ServoConfig
from rcb4hv.hth4.poses import Block, Pose, motion_blocks
from rcb4hv.protocol.memory.map import SystemRegister

__all__ = ["Change", "diff_projects"]

#: compared on their own (motions, servos, priority checks) or carrying no data: the layout
#: is how the file was written (line ends, byte-order mark, namespace order)
_SKIP_PROJECT = {"motions", "servos", "priority_motions", "layout"}
_SKIP_SERVO = {"key", "device_number"}
_MOTION_FIELDS = ("key_code", "date", "address", "number", "key")


@dataclass(frozen=True)
class Change:
    """One difference. ``slot`` names the motion slot (None for project / servo settings),
    ``pose`` the 1-based pose, ``ics`` the servo; ``old`` / ``new`` the values."""

    kind: str
    text: str
    slot: int | None = None
    pose: int | None = None
    ics: int | None = None
    field: str | None = None
    old: Any = None
    new: Any = None

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict (absent fields left out; values as text if not JSON)."""
        out: dict[str, Any] = {"kind": self.kind, "text": self.text}
        for name in ("slot", "pose", "ics", "field", "old", "new"):
            value = getattr(self, name)
            if value is not None:
                ok = isinstance(value, (int, str, float, bool, list, dict))
                out[name] = value if ok else str(value)
        return out


def _text(value: object) -> object:
    if isinstance(value, bytes):
        return value.hex(" ").upper()
    return value


def diff_projects(a: Project, b: Project) -> list[Change]:
    """The differences from project ``a`` to project ``b`` (module docstring)."""
    out: list[Change] = []
    for f in fields(Project):
        if f.name in _SKIP_PROJECT:
            continue
        old, new = getattr(a, f.name), getattr(b, f.name)
        if old != new:
            text = _setting_text(a, b, f.name)
            if text is None:
                text = f"project setting {f.name}: {_short(old)} -> {_short(new)}"
            out.append(Change("setting", text, field=f.name, old=_text(old), new=_text(new)))
    out.extend(_priority_changes(a.priority_motions, b.priority_motions))
    out.extend(_servo_changes(a.servos, b.servos))
    old_m = {m.slot: m for m in a.motions}
    new_m = {m.slot: m for m in b.motions}
    for slot in sorted(old_m.keys() | new_m.keys()):
        out.extend(_motion_changes(slot, old_m.get(slot), new_m.get(slot)))
    return out


def _setting_text(a: Project, b: Project, name: str) -> str | None:
    """The system register and the AD references in words, not bytes (None: bytes)."""
    if name == "config":
        try:
            ra, rb = SystemRegister.from_word(a.system_register), b.system_register
            da, db = ra.describe(), SystemRegister.from_word(rb).describe()
        except ValueError:
            return None
        moved = [f"{k} {da[k]} -> {db[k]}" for k in da if k != "word" and da[k] != db[k]]
        head = f"project setting config: system register {da['word']}h -> {db['word']}h"
        return head + (f" ({', '.join(moved)})" if moved else " (reserved bits)")
    if name == "adc_reference" and len(a.adc_reference) == len(b.adc_reference):
        pairs = zip(a.adc_reference_words, b.adc_reference_words, strict=True)
        moved = [f"AD{ch} {x} -> {y}" for ch, (x, y) in enumerate(pairs) if x != y]
        return f"project setting adc_reference: {', '.join(moved)}" if moved else None
    return None


def _short(value: object, width: int = 60) -> str:
    text = str(_text(value))
    return text if len(text) <= width else text[: width - 3] + "..."


def _priority_text(slot: PriorityMotionSlot | None) -> str:
    m = None if slot is None else slot.motion
    if m is None:
        return "unused"
    return f"{m.name or 'unnamed'!r} at {m.address:05X}h when {m.port} {m.compare_type} {m.value}"


def _priority_changes(
    a: tuple[PriorityMotionSlot, ...], b: tuple[PriorityMotionSlot, ...]
) -> list[Change]:
    """One change per priority check (``PriorityMotionCollection`` key) that differs."""
    old, new = {p.key: p for p in a}, {p.key: p for p in b}
    out: list[Change] = []
    for key in sorted(old.keys() | new.keys(), key=lambda k: (len(k), k)):
        was, now = _priority_text(old.get(key)), _priority_text(new.get(key))
        if old.get(key) != new.get(key):
            text = f"priority motion check {key}: {was} -> {now}"
            out.append(Change("setting", text, field="priority_motions", old=was, new=now))
    return out


def _servo_changes(a: tuple[ServoConfig, ...], b: tuple[ServoConfig, ...]) -> list[Change]:
    out: list[Change] = []
    old = {s.device_number: s for s in a}
    new = {s.device_number: s for s in b}
    for ics in sorted(old.keys() | new.keys()):
        sa, sb = old.get(ics), new.get(ics)
        if sa is None or sb is None:
            what = "added" if sa is None else "removed"
            out.append(Change("servo", f"ICS {ics}: servo configuration {what}", ics=ics))
            continue
        for f in fields(ServoConfig):
            va, vb = getattr(sa, f.name), getattr(sb, f.name)
            if f.name not in _SKIP_SERVO and va != vb:
                text = f"ICS {ics} ({sb.name}): {f.name} {_short(va)} -> {_short(vb)}"
                was, now = _text(va), _text(vb)
                out.append(Change("servo", text, ics=ics, field=f.name, old=was, new=now))
    return out


def _label(m: Motion) -> str:
    return f"motion {m.slot} ({m.name})"


def _motion_changes(slot: int, a: Motion | None, b: Motion | None) -> list[Change]:
    if a == b:
        return []
    if a is None or a.is_empty:
        if b is None or b.is_empty:
            return _fields(slot, a, b, ("name", "button_data", "compare_type", *_MOTION_FIELDS))
        n = sum(1 for x in motion_blocks(b) if x.pose is not None)
        text = f"{_label(b)}: new motion, {n} poses, {b.code_size} bytes"
        return [Change("motion-added", text, slot=slot, new=b.name)]
    if b is None or b.is_empty:
        return [Change("motion-removed", f"{_label(a)}: removed", slot=slot, old=a.name)]
    out: list[Change] = []
    if a.name != b.name:
        text = f"motion {slot}: renamed {a.name!r} -> {b.name!r}"
        out.append(Change("motion-renamed", text, slot=slot, old=a.name, new=b.name))
    if a.button != b.button:
        text = f"{_label(b)}: button {a.button_data} ({a.compare_type}) -> "
        text += f"{b.button_data} ({b.compare_type})"
        out.append(Change("button", text, slot=slot, old=a.button_data, new=b.button_data))
    out.extend(_fields(slot, a, b, _MOTION_FIELDS))
    if a.frames != b.frames:
        out.extend(_block_changes(a, b))
    return out


def _fields(slot: int, a: Motion | None, b: Motion | None, names: tuple[str, ...]) -> list[Change]:
    out: list[Change] = []
    for name in names:
        va = None if a is None else getattr(a, name)
        vb = None if b is None else getattr(b, name)
        if va != vb:
            text = f"motion {slot}: {name} {_short(va)} -> {_short(vb)}"
            out.append(Change("motion-field", text, slot=slot, field=name, old=va, new=vb))
    return out


def _key(motion: Motion, block: Block) -> tuple[object, ...]:
    if block.pose is not None:
        return ("pose", block.pose.speed, block.pose.positions)
    lo, hi = motion.address, motion.address + len(motion.rom_bytes())
    if block.target is not None and lo <= block.target < hi:
        return (block.kind, "internal", motion.frames[block.entry][5])
    return (block.kind, motion.frames[block.entry])


def _block_changes(a: Motion, b: Motion) -> list[Change]:
    ba, bb = motion_blocks(a), motion_blocks(b)
    ka, kb = [_key(a, x) for x in ba], [_key(b, x) for x in bb]
    matcher = difflib.SequenceMatcher(a=ka, b=kb, autojunk=False)
    out: list[Change] = []
    slot = b.slot
    for tag, i1, i2, j1, j2 in matcher.get_opcodes():
        if tag == "equal":
            continue
        olds, news = list(ba[i1:i2]), list(bb[j1:j2])
        while olds and news and olds[0].pose is not None and news[0].pose is not None:
            out.extend(_pose_changes(b, olds.pop(0).pose, news.pop(0).pose))
        while olds and news and olds[0].kind == news[0].kind and olds[0].pose is None:
            old, new = olds.pop(0), news.pop(0)
            text = f"{_label(b)}: {new.kind} block changed: {old.text} -> {new.text}"
            out.append(Change("block", text, slot=slot, old=old.text, new=new.text))
        for x in olds:
            out.append(_added_removed(b, x, "removed"))
        for x in news:
            out.append(_added_removed(b, x, "added"))
    return out


def _added_removed(m: Motion, block: Block, what: str) -> Change:
    if block.pose is not None:
        text = f"{_label(m)}: pose {block.pose.index + 1} {what} (frame {block.pose.speed})"
        return Change(f"pose-{what}", text, slot=m.slot, pose=block.pose.index + 1)
    text = f"{_label(m)}: {block.kind} block {what}: {block.text}"
    return Change(f"block-{what}", text, slot=m.slot)


def _pose_changes(m: Motion, a: Pose | None, b: Pose | None) -> list[Change]:
    assert a is not None and b is not None
    out: list[Change] = []
    where = f"{_label(m)} pose {b.index + 1}"
    if a.speed != b.speed:
        text = f"{where}: frame {a.speed} -> {b.speed}"
        out.append(Change("pose-frames", text, m.slot, b.index + 1, old=a.speed, new=b.speed))
    va, vb = a.values, b.values
    for ics in sorted(va.keys() | vb.keys()):
        x, y = va.get(ics), vb.get(ics)
        if x != y:
            text = f"{where}: ICS {ics} {x if x is not None else '-'} -> "
            text += f"{y if y is not None else '-'}"
            out.append(Change("pose-servo", text, m.slot, b.index + 1, ics, old=x, new=y))
    if a.set_update_flag != b.set_update_flag:
        text = f"{where}: update flag {a.set_update_flag} -> {b.set_update_flag}"
        out.append(Change("pose-flag", text, m.slot, b.index + 1))
    return out
