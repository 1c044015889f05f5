"""Program blocks: each stored entry of a motion as a block a HeartToHeart4 user knows.

A block is a ``kind`` and named fields (its JSON object, :class:`Block`). It is built on the
protocol's command classes (:func:`~rcb4hv.protocol.decode_command` reads an entry, the
command's ``encode()`` writes it back), so encoding a decoded block gives its bytes back
exactly. The kinds (fields in brackets; ``to`` is a branch target, see
:mod:`rcb4hv.hth4.blocks.program`; ``if`` a condition name, :data:`CONDITIONS`):

* servo: ``pose`` [frames, positions {ICS: value}, update], ``servo_stretch`` /
  ``servo_speed`` [values {ICS: value}], ``servo_single`` [ics, frames, position, update],
  ``servo_series`` [moves [[ics, frames, position]], update];
* flow: ``jump`` / ``call`` [to, if], ``return``, ``end`` (HeartToHeart4's closing
  ``03 0D 10 FF``);
* compare-and-branch (HeartToHeart4's compare boxes: a no-write SUB then a conditional JUMP,
  two entries): ``button_branch`` [buttons, if, to], ``ad_branch`` [channel, value, if, to],
  ``variable_branch`` [variable, ...], ``counter_branch`` [counter, ...], ``pa_branch``
  [pa, ...], ``timer_branch`` [timer, ...], ``compare_branch`` [dst, src, size, if, to];
  ``counter_loop`` [counter, if, to] (counter minus one, branch when it reaches zero);
  ``compare`` [dst, src, size] (a compare not followed by its branch);
* settings and variables: ``counter_set`` [counter, value], ``variable_set`` [variable,
  value], ``timer_set`` [timer, value], ``ad_reference`` [channel, value], ``mixing`` /
  ``servo_setting`` [ics, field, value], ``variable_arith`` [op, variable, value];
* generic data: ``move`` [dst, src, size] (RAM / ROM moves), ``arith`` [op, dst, src, size,
  no_write, count] (AND .. MOD, NOT, SHIFT), ``ics_comm`` [ics, tx_count, tx_address,
  rx_address];
* ``raw`` [hex]: bytes that are none of these (no HeartToHeart4 version writes them).

Operands are named by :mod:`rcb4hv.hth4.blocks.operands`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from itertools import pairwise
from typing import Final

from rcb4hv.errors import EditError, ProtocolError
from rcb4hv.hth4.blocks.fields import Fields, Json, condition_json, ics_map_json
from rcb4hv.hth4.blocks.operands import operand_name
from rcb4hv.hth4.motioncode import split_frames
from rcb4hv.protocol import (
    ALWAYS,
    Add,
    And,
    Call,
    Command,
    CommunicateDevice,
    Condition,
    Data,
    Div,
    Ics,
    Jump,
    Mod,
    Move,
    Mul,
    Not,
    Or,
    Ram,
    Return,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
    Shift,
    Sub,
    Xor,
    decode_command,
)
from rcb4hv.protocol.memory import SERVO, Button

__all__ = ["FIELDS", "KINDS", "Block", "Namer", "Resolver", "decode_group", "pairs", "waits"]

Namer = Callable[[int], Json]
"""ROM address -> the JSON of a branch target (a label, a motion, an address)."""
Resolver = Callable[[Json, str], int]
"""(JSON branch target, where) -> ROM address; EditError naming ``where`` if unknown."""

END: Final = b"\xff"


@dataclass(frozen=True)
class Block:
    """One block: ``kind``, its named ``fields`` and an optional ``label`` branches use."""

    kind: str
    fields: Mapping[str, Json] = field(default_factory=dict)
    label: str | None = None

    def to_json(self) -> dict[str, Json]:
        head: dict[str, Json] = {} if self.label is None else {"label": self.label}
        return {**head, "kind": self.kind, **self.fields}

    @classmethod
    def from_json(cls, obj: Json, where: str) -> Block:
        if not isinstance(obj, Mapping):
            raise EditError(f"{where}: a block is an object with a 'kind', not {obj!r}")
        kind = obj.get("kind")
        if kind not in KINDS:
            raise EditError(f"{where}.kind: {kind!r} is not a block kind ({', '.join(KINDS)})")
        label = obj.get("label")
        if label is not None and (not isinstance(label, str) or not label):
            raise EditError(f"{where}.label: a label is a non-empty string, not {label!r}")
        rest = {k: v for k, v in obj.items() if k not in ("kind", "label")}
        Fields(rest, where).check_known(("kind", "label", *FIELDS[str(kind)]))
        return cls(str(kind), rest, label)


# ------------------------------------------------------------------------------ tables

OPS: Final[dict[str, type]] = {
    "and": And, "or": Or, "xor": Xor, "add": Add, "sub": Sub,
    "mul": Mul, "div": Div, "mod": Mod, "not": Not, "shift": Shift,
}  # fmt: skip
OP_NAMES: Final = {cls: name for name, cls in OPS.items()}
VAR_OPS: Final = ("add", "sub", "mul", "div", "mod")

VALUE_KINDS: Final = {
    # kind: (name prefix, field, size, signed)
    "counter_set": ("COUNTER", "counter", 1, False),
    "variable_set": ("VAR", "variable", 2, True),
    "timer_set": ("TIMER", "timer", 2, False),
    "ad_reference": ("AD_REF", "channel", 2, True),
}
BRANCH_KINDS: Final = {
    "ad_branch": ("AD", "channel", 2, True),
    "variable_branch": ("VAR", "variable", 2, True),
    "counter_branch": ("COUNTER", "counter", 1, False),
    "pa_branch": ("PA", "pa", 1, False),
    "timer_branch": ("TIMER", "timer", 2, False),
}
SERVO_FIELDS: Final = {
    f.name: (f.offset, f.size)
    for f in (
        SERVO.F_TYPE, SERVO.F_ID, SERVO.F_BASE, SERVO.F_OUTPUT, SERVO.F_SPEED, SERVO.F_END,
        SERVO.F_WIDTH, SERVO.F_MIX1_SOURCE, SERVO.F_MIX1_METHOD, SERVO.F_MIX2_SOURCE,
        SERVO.F_MIX2_METHOD,
    )
}  # fmt: skip
MIXING: Final = ("mix1_source", "mix1_method", "mix2_source", "mix2_method")
BUTTONS: Final = tuple(b for b in Button if b)

BRANCHES: Final = ("button_branch", "counter_loop", "compare_branch", *BRANCH_KINDS)
"""The kinds that are two entries: a compare and its conditional JUMP."""

KINDS: Final = (
    "pose", "servo_stretch", "servo_speed", "servo_single", "servo_series",
    "jump", "call", "return", "end", *BRANCHES, "compare", "wait",
    *VALUE_KINDS, "mixing", "servo_setting", "variable_arith", "move", "arith", "ics_comm",
    "raw",
)  # fmt: skip
"""Every block kind."""

_BRANCH_TAIL: Final = ("if", "to")
FIELDS: Final[dict[str, tuple[str, ...]]] = {
    "pose": ("frames", "positions", "update"),
    "servo_stretch": ("values",),
    "servo_speed": ("values",),
    "servo_single": ("ics", "frames", "position", "update"),
    "servo_series": ("moves", "update"),
    "jump": _BRANCH_TAIL,
    "call": _BRANCH_TAIL,
    "return": (),
    "end": (),
    "button_branch": ("buttons", *_BRANCH_TAIL),
    **{k: (name, "value", *_BRANCH_TAIL) for k, (_, name, _, _) in BRANCH_KINDS.items()},
    "compare_branch": ("dst", "src", "size", *_BRANCH_TAIL),
    "counter_loop": ("counter", *_BRANCH_TAIL),
    "compare": ("dst", "src", "size"),
    "wait": ("timer", "ms"),
    **{k: (name, "value") for k, (_, name, _, _) in VALUE_KINDS.items()},
    "mixing": ("ics", "field", "value"),
    "servo_setting": ("ics", "field", "value"),
    "variable_arith": ("op", "variable", "value"),
    "move": ("dst", "src", "size"),
    "arith": ("op", "dst", "src", "size", "no_write", "count"),
    "ics_comm": ("ics", "tx_count", "tx_address", "rx_address"),
    "raw": ("hex",),
}
"""The fields each kind may have (any other is refused, naming it)."""
assert set(FIELDS) == set(KINDS)


def _numbered(name: str, prefix: str) -> int | None:
    tail = name[len(prefix) :]
    return int(tail) if name.startswith(prefix) and tail.isdigit() else None


def _literal(cmd: Move | Sub | Add | Mul | Div | Mod, size: int, signed: bool) -> int | None:
    if not isinstance(cmd.src, Data) or cmd.nbytes != size:
        return None
    return int.from_bytes(cmd.src.data, "little", signed=signed)


# ------------------------------------------------------------------------------ decoding


def exact_command(entry: bytes) -> tuple[Command, bool] | None:
    """(command, ends with HeartToHeart4's FF) when ``entry`` is one frame that encodes back to
    itself (an FF only after a RETURN); None for anything else."""
    try:
        frames, tail = split_frames(entry)
        if len(frames) != 1:
            return None
        cmd = decode_command(frames[0])
    except ProtocolError:
        return None
    if cmd.encode() != frames[0]:
        return None
    if not tail:
        return cmd, False
    return (cmd, True) if tail == END and isinstance(cmd, Return) else None


def _is_counter_step(cmd: Command) -> bool:
    return (
        isinstance(cmd, Sub)
        and not cmd.no_write
        and isinstance(cmd.dst, Ram)
        and _numbered(operand_name(cmd.dst), "COUNTER") is not None
        and cmd.src == Data(b"\x01")
    )


def pairs(first: bytes, second: bytes) -> bool:
    """True if entries ``first`` and ``second`` make one compare-and-branch block."""
    a, b = exact_command(first), exact_command(second)
    if a is None or b is None or a[1] or b[1]:
        return False
    cmd, jump = a[0], b[0]
    if not isinstance(jump, Jump) or jump.condition == ALWAYS:
        return False
    return (isinstance(cmd, Sub) and cmd.no_write) or _is_counter_step(cmd)


def _data_json(cmd: Move | Sub | Add | Mul | Div | Mod | And | Or | Xor) -> dict[str, Json]:
    out: dict[str, Json] = {"dst": operand_name(cmd.dst), "src": operand_name(cmd.src)}
    if not isinstance(cmd.src, Data):
        out["size"] = cmd.nbytes
    return out


def _button_word(cmd: Sub) -> int | None:
    """The button word a compare tests the remote's buttons (RAM BUTTONS) against, or None."""
    if not isinstance(cmd.dst, Ram) or operand_name(cmd.dst) != "BUTTONS":
        return None
    if not isinstance(cmd.src, Data) or cmd.nbytes != 2:
        return None
    return int.from_bytes(cmd.src.data, "big")


def button_tests(entries: Sequence[bytes]) -> list[tuple[int, Json]]:
    """(button word, condition) of each button branch (``button_branch`` block) among a
    motion's ``entries``, in ROM order: what the motion reads from the remote."""
    out: list[tuple[int, Json]] = []
    for first, second in pairwise(entries):
        if not pairs(first, second):
            continue
        a, b = exact_command(first), exact_command(second)
        assert a is not None and b is not None  # pairs() decoded both
        cmd, jump = a[0], b[0]
        assert isinstance(cmd, Sub) and isinstance(jump, Jump)  # and said what they are
        word = _button_word(cmd)
        if word is not None:
            out.append((word, condition_json(jump.condition.to_byte())))
    return out


def _branch(cmd: Sub, jump: Jump, namer: Namer) -> tuple[str, dict[str, Json]]:
    tail: dict[str, Json] = {
        "if": condition_json(jump.condition.to_byte()),
        "to": namer(jump.address),
    }
    if _is_counter_step(cmd):
        assert isinstance(cmd.dst, Ram)
        return "counter_loop", {"counter": _numbered(operand_name(cmd.dst), "COUNTER"), **tail}
    dst = operand_name(cmd.dst) if isinstance(cmd.dst, Ram) else ""
    word = _button_word(cmd)
    if word is not None:
        names: list[Json] = [b.name for b in BUTTONS if word & b]
        rest = word & ~sum(BUTTONS)
        return "button_branch", {"buttons": names + ([rest] if rest else []), **tail}
    for kind, (prefix, name, size, signed) in BRANCH_KINDS.items():
        n, value = _numbered(dst, prefix), _literal(cmd, size, signed)
        if n is not None and value is not None:
            return kind, {name: n, "value": value, **tail}
    return "compare_branch", {**_data_json(cmd), **tail}


def _data(cmd: Command) -> tuple[str, dict[str, Json]] | None:
    if isinstance(cmd, Move):
        dst = operand_name(cmd.dst) if isinstance(cmd.dst, Ram) else ""
        for kind, (prefix, name, size, signed) in VALUE_KINDS.items():
            n, value = _numbered(dst, prefix), _literal(cmd, size, signed)
            if n is not None and value is not None:
                return kind, {name: n, "value": value}
        if isinstance(cmd.dst, Ics) and isinstance(cmd.src, Data):
            for fname, (offset, width) in SERVO_FIELDS.items():
                if cmd.dst.offset == offset and cmd.nbytes == width:
                    kind = "mixing" if fname in MIXING else "servo_setting"
                    value = int.from_bytes(cmd.src.data, "little")
                    return kind, {"ics": cmd.dst.ics, "field": fname, "value": value}
        return "move", _data_json(cmd)
    if isinstance(cmd, Sub) and cmd.no_write:
        return "compare", _data_json(cmd)
    if isinstance(cmd, (Add, Sub, Mul, Div, Mod)) and not cmd.no_write and isinstance(cmd.dst, Ram):
        n, value = _numbered(operand_name(cmd.dst), "VAR"), _literal(cmd, 2, True)
        if n is not None and value is not None:
            return "variable_arith", {"op": OP_NAMES[type(cmd)], "variable": n, "value": value}
    if isinstance(cmd, (And, Or, Xor, Add, Sub, Mul, Div, Mod)):
        out = {"op": OP_NAMES[type(cmd)], **_data_json(cmd)}
        return "arith", {**out, "no_write": True} if cmd.no_write else out
    if isinstance(cmd, (Not, Shift)):
        out = {"op": OP_NAMES[type(cmd)], "dst": operand_name(cmd.dst), "size": cmd.size}
        if isinstance(cmd, Shift):
            out["count"] = cmd.count
        return "arith", {**out, "no_write": True} if cmd.no_write else out
    return None


def _update(flag: bool) -> dict[str, Json]:
    return {} if flag else {"update": False}


def _single(cmd: Command, end: bool, namer: Namer) -> tuple[str, dict[str, Json]] | None:
    if isinstance(cmd, Return):
        return ("end" if end else "return"), {}
    if isinstance(cmd, RunConstFrameServo):
        return "pose", {
            "frames": cmd.speed,
            "positions": ics_map_json(cmd.positions),
            **_update(cmd.set_update_flag),
        }
    if isinstance(cmd, SetStretch):
        return "servo_stretch", {"values": ics_map_json(cmd.values)}
    if isinstance(cmd, SetSpeed):
        return "servo_speed", {"values": ics_map_json(cmd.values)}
    if isinstance(cmd, RunSingleServo):
        return "servo_single", {
            "ics": cmd.ics, "frames": cmd.speed, "position": cmd.position,
            **_update(cmd.set_update_flag),
        }  # fmt: skip
    if isinstance(cmd, RunSeriesServo):
        moves: list[Json] = [list(m) for m in cmd.moves]
        return "servo_series", {"moves": moves, **_update(cmd.set_update_flag)}
    if isinstance(cmd, (Jump, Call)):
        out: dict[str, Json] = {"to": namer(cmd.address)}
        if cmd.condition != ALWAYS:
            out["if"] = condition_json(cmd.condition.to_byte())
        return ("jump" if isinstance(cmd, Jump) else "call"), out
    if isinstance(cmd, CommunicateDevice):
        return "ics_comm", {
            "ics": cmd.ics, "tx_count": cmd.tx_count, "tx_address": cmd.tx_address,
            "rx_address": cmd.rx_address,
        }  # fmt: skip
    return _data(cmd)


WAIT_STOPPED: Final = b"\x00\x80"
"""A timer's stopped bit (bit 15, spec 10.3) as the literal of the wait's compare."""
WAIT_WHILE: Final = 0x04
"""The wait's JUMP condition: back while the timer has not stopped (Z = 0)."""


def waits(entries: tuple[bytes, ...], second: int) -> bool:
    """True if three entries are HeartToHeart4's timer wait: MOVE TIMERk <- n; SUB (no write)
    TIMERk - 8000h; JUMP back to that SUB while Z = 0 (``second`` = the SUB's address)."""
    got = [exact_command(e) for e in entries]
    if len(got) != 3 or any(g is None or g[1] for g in got):
        return False
    move, sub, jump = (g[0] for g in got if g is not None)
    return (
        isinstance(move, Move)
        and isinstance(move.dst, Ram)
        and _numbered(operand_name(move.dst), "TIMER") is not None
        and isinstance(move.src, Data)
        and move.nbytes == 2
        and sub == Sub(move.dst, Data(WAIT_STOPPED), no_write=True)
        and jump == Jump(second, Condition.from_byte(WAIT_WHILE))
    )


def decode_group(entries: tuple[bytes, ...], namer: Namer) -> Block:
    """The block of one entry, of a compare entry and its branch (:func:`pairs`) or of a timer
    wait (:func:`waits`)."""
    raw = Block("raw", {"hex": b"".join(entries).hex(" ").upper()})
    if len(entries) == 3:
        got = exact_command(entries[0])
        assert got is not None and isinstance(got[0], Move) and isinstance(got[0].dst, Ram)
        assert isinstance(got[0].src, Data)
        timer = _numbered(operand_name(got[0].dst), "TIMER")
        ms = 100 * int.from_bytes(got[0].src.data, "little")
        return Block("wait", {"timer": timer, "ms": ms})
    if len(entries) == 2:
        a, b = exact_command(entries[0]), exact_command(entries[1])
        assert a is not None and b is not None and isinstance(a[0], Sub)
        assert isinstance(b[0], Jump)
        kind, fields = _branch(a[0], b[0], namer)
        return Block(kind, fields)
    got = exact_command(entries[0])
    if got is None:
        return raw
    made = _single(*got, namer)
    return raw if made is None else Block(*made)
