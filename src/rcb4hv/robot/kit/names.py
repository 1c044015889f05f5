"""What a HeartToHeart4 servo name says: side, limb position, body part, axis, segment.

Kondo's sample projects name each servo slot in Japanese (``右肩（ピッチ）`` right shoulder
pitch, ``左膝`` left knee, ``首ヨー`` neck yaw, ``右前脚（ロール）`` right front leg roll,
``右後足車輪`` right rear wheel, ``右中脚（先）`` right middle leg tip); users also write
English (``R shoulder pitch``, ``left knee``, ``right middle leg tip``); ``rcb4hv project new``
names them after the model's joints (``r_front_knee``, ``l_shoulder_pitch``, ``neck_pitch2``),
read as the words they stand for. Unused slots are spares (``右拡張3``, "right spare 3") and
carry no joint.
"""

from __future__ import annotations

import re
import unicodedata
from dataclasses import dataclass
from typing import Literal

from rcb4hv.robot.model import Side, side_of_name

__all__ = ["Part", "Role", "parse_servo_name"]

Part = Literal[
    "shoulder",
    "elbow",
    "wrist",
    "gripper",
    "hip",
    "knee",
    "ankle",
    "neck",
    "waist",
    "wheel",
    "jaw",
    "leg",
    "arm",
    "tail",
]
Axis = Literal["pitch", "roll", "yaw"]
Position = Literal["front", "middle", "rear"]
Segment = Literal["root", "mid", "tip"]


@dataclass(frozen=True)
class Role:
    """A servo name's meaning; ``None`` fields: the name does not say."""

    side: Side
    part: Part
    axis: Axis | None = None
    position: Position | None = None
    segment: Segment | None = None


_SPARE = re.compile(r"拡張|予備|spare|unused|\bext", re.I)
# parts, most specific first (手首 before 手 and 首, 足首 before 足 and 首)
_PARTS: tuple[tuple[str, Part], ...] = (
    (r"車輪|wheel|タイヤ|tire|tyre", "wheel"),
    (r"手首|wrist", "wrist"),
    (r"足首|ankle", "ankle"),
    (r"肩|shoulder", "shoulder"),
    (r"肘|ひじ|ヒジ|elbow", "elbow"),
    (r"ハンド|グリッパ|グリップ|手|hand|gripper|grip|finger", "gripper"),
    (r"腿|股|もも|hip|crotch|thigh", "hip"),
    (r"膝|ひざ|ヒザ|knee", "knee"),
    (r"アゴ|あご|顎|口|jaw|mouth", "jaw"),
    (r"首|頭|neck|head", "neck"),
    (r"腰|胴|waist|torso|chest", "waist"),
    (r"尻尾|しっぽ|tail", "tail"),
    (r"脚|足|leg|foot|feet", "leg"),
    (r"腕|arm", "arm"),
)
_AXES: tuple[tuple[str, Axis], ...] = (
    (r"ピッチ|pitch", "pitch"),
    (r"ロール|roll", "roll"),
    (r"ヨー|yaw", "yaw"),
)
_SEGMENT_JA = re.compile(r"[(\s]\s*(元|根元|中|先端|先)\s*\)?\s*$|(元|先端|先)$")
_SEGMENT_EN = re.compile(r"\b(?:leg|arm)\b\W*(root|base|mid|middle|tip|end)\b", re.I)
_POSITION_JA = re.compile(r"(前|中|後)(?=脚|足|\(|車輪|輪|腕)|^[右左]?(前|後)")
_POSITION_EN = re.compile(r"\b(front|fore|middle|mid|rear|back|hind)\b\W*(?:leg|wheel|arm)?", re.I)


# rcb4hv's own joint names (snake case, the side an r_/l_ prefix): the kit's joint slots
# (:data:`rcb4hv.robot.kit.convention.LIMBS`) name a limb by position and then its joint; the
# L6 leg's "lift" is its middle joint (yaw, lift, knee), and the L4R's "arm_roll" the roll of
# its arm at the shoulder (Kondo's 右肩ロール)
_JOINT_NAME = re.compile(r"(?:[lr]_)?[a-z]+[0-9]*(?:_[a-z]+[0-9]*)*", re.I)
_AXIS_WORDS = frozenset({"pitch", "roll", "yaw"})


def _joint_words(name: str) -> str:
    """An rcb4hv joint name as the words it stands for (``r_front_lift`` -> ``right front leg
    mid``); any other name as it is."""
    if _JOINT_NAME.fullmatch(name) is None or "_" not in name:
        return name
    words = name.lower().split("_")
    out = []
    for i, word in enumerate(words):
        after = words[i + 1] if i + 1 < len(words) else ""
        if i == 0 and word in ("r", "l"):
            out.append("right" if word == "r" else "left")
        elif word == "lift":
            out.append("leg mid")
        elif word == "arm" and after in _AXIS_WORDS:
            out.append("shoulder")
        else:
            out.append(word)
    return " ".join(out)


def _norm(text: str) -> str:
    return _joint_words(unicodedata.normalize("NFKC", text).strip())


def parse_servo_name(name: str | None) -> Role | None:
    """The role a servo name gives, or None for a spare or a name that says nothing."""
    if not name:
        return None
    n = _norm(name)
    if _SPARE.search(n):
        return None
    part: Part | None = None
    for pattern, p in _PARTS:
        if re.search(pattern, n, re.I):
            part = p
            break
    if part is None and _POSITION_JA.search(n) is None and _POSITION_EN.search(n) is None:
        return None
    part = part or "leg"  # 右前（ヨー）, front yaw: a limb position and an axis name a leg joint
    side: Side = side_of_name(n) or "centre"
    axis: Axis | None = None
    for pattern, a in _AXES:
        if re.search(pattern, n, re.I):
            axis = a
            break
    position: Position | None = None
    segment: Segment | None = None
    m = _SEGMENT_EN.search(n)
    if m is not None:
        word = m.group(1).lower()
        segment = "root" if word in ("root", "base") else "tip" if word in ("tip", "end") else "mid"
        n_pos = n[: m.start(1)]
    else:
        n_pos = n
        j = _SEGMENT_JA.search(n)
        if j is not None:
            word = j.group(1) or j.group(2)
            segment = "root" if word in ("元", "根元") else "tip" if word[0] == "先" else "mid"
            n_pos = n[: j.start()]
    pm = _POSITION_JA.search(n_pos)
    if pm is not None:
        word = pm.group(1) or pm.group(2)
        position = "front" if word == "前" else "rear" if word == "後" else "middle"
    else:
        e = _POSITION_EN.search(n_pos)
        if e is not None:
            word = e.group(1).lower()
            position = (
                "front" if word in ("front", "fore") else
                "middle" if word in ("middle", "mid") else "rear"
            )  # fmt: skip
    return Role(side=side, part=part, axis=axis, position=position, segment=segment)
