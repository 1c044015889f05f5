"""Encoding program blocks into stored entries (the kinds: :mod:`rcb4hv.hth4.blocks.kinds`)."""

from __future__ import annotations

from collections.abc import Callable

from rcb4hv.errors import EditError, ProtocolError
from rcb4hv.hth4.blocks.fields import Fields
from rcb4hv.hth4.blocks.kinds import (
    BRANCH_KINDS,
    BRANCHES,
    BUTTONS,
    END,
    OPS,
    SERVO_FIELDS,
    VALUE_KINDS,
    VAR_OPS,
    WAIT_STOPPED,
    WAIT_WHILE,
    Block,
    Resolver,
)
from rcb4hv.hth4.blocks.operands import named_ram, parse_operand
from rcb4hv.protocol import (
    Call,
    Com,
    Command,
    CommunicateDevice,
    Condition,
    Data,
    Ics,
    Jump,
    Move,
    Not,
    Ram,
    Return,
    Rom,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
    Shift,
    Sub,
)
from rcb4hv.protocol.frame import split_frames
from rcb4hv.protocol.memory import Button

__all__ = ["encode_block"]


def _value_bytes(f: Fields, name: str, size: int) -> bytes:
    v = f.integer(name, -(1 << (8 * size - 1)), (1 << (8 * size)) - 1)
    return (v & ((1 << (8 * size)) - 1)).to_bytes(size, "little")


def _wrap(where: str, make: Callable[[], Command]) -> bytes:
    try:
        return make().encode()
    except EditError:
        raise
    except ValueError as exc:
        raise EditError(f"{where}: {exc}") from None


def _numbered(prefix: str) -> tuple[int, int]:
    """The numbers ``prefix`` names in RAM (COUNTER0-COUNTER10: (0, 10))."""
    known = [n for n in range(100) if named_ram(f"{prefix}{n}") is not None]
    return (min(known), max(known)) if known else (0, -1)


def _numbered_ram(f: Fields, name: str, prefix: str) -> Ram:
    lo, hi = _numbered(prefix)
    n = f.integer(name, lo, hi)
    address = named_ram(f"{prefix}{n}")
    if address is None:
        raise EditError(f"{f.path(name)}: there is no {prefix}{n} ({prefix}{lo}-{prefix}{hi})")
    return Ram(address)


def _jump(f: Fields, resolve: Resolver, cls: type[Jump] | type[Call] = Jump) -> bytes:
    address = resolve(f.get("to"), f.path("to"))
    cond = Condition.from_byte(f.condition())
    return _wrap(f.where, lambda: cls(address, cond))


def _compare(f: Fields, kind: str) -> Sub:
    if kind == "button_branch":
        names = f.get("buttons")
        if not isinstance(names, list):
            raise EditError(f"{f.path('buttons')}: expected a list like ['UP', 'S1']")
        word = 0
        for i, b in enumerate(names):
            if isinstance(b, str) and b in Button.__members__:
                word |= Button[b]
            elif isinstance(b, int) and not isinstance(b, bool) and 0 <= b <= 0xFFFF:
                word |= b
            else:
                known = ", ".join(x.name or "" for x in BUTTONS)
                raise EditError(f"{f.path('buttons')}[{i}]: {b!r} is not a button ({known})")
        return Sub(Ram(named_ram("BUTTONS") or 0), Data(word.to_bytes(2, "big")), no_write=True)
    if kind == "counter_loop":
        return Sub(_numbered_ram(f, "counter", "COUNTER"), Data(b"\x01"))
    if kind in BRANCH_KINDS:
        prefix, name, size, _ = BRANCH_KINDS[kind]
        dst = _numbered_ram(f, name, prefix)
        return Sub(dst, Data(_value_bytes(f, "value", size)), no_write=True)
    return Sub(*_operands(f), no_write=True)  # compare_branch


def _operands(f: Fields) -> tuple[Ram | Ics | Rom | Com, Ram | Ics | Rom | Data, int | None]:
    dst = parse_operand(f.get("dst"), f.path("dst"))
    src = parse_operand(f.get("src"), f.path("src"))
    size = f.integer("size", 1, 128) if f.has("size") else None
    if isinstance(dst, Data):
        raise EditError(f"{f.path('dst')}: a literal is a source, not a destination")
    if isinstance(src, Com):
        raise EditError(f"{f.path('src')}: COM (the host) is a destination, not a source")
    return dst, src, size


def _encode_data(kind: str, f: Fields) -> bytes:
    w = f.where
    if kind in VALUE_KINDS:
        prefix, name, size, _ = VALUE_KINDS[kind]
        dst = _numbered_ram(f, name, prefix)
        data = Data(_value_bytes(f, "value", size))
        return _wrap(w, lambda: Move(dst, data))
    if kind in ("mixing", "servo_setting"):
        fname = f.text("field")
        if fname not in SERVO_FIELDS:
            raise EditError(f"{f.path('field')}: {fname!r} is not one of {', '.join(SERVO_FIELDS)}")
        offset, width = SERVO_FIELDS[fname]
        ics = f.integer("ics", 0, 35)
        value = Data(_value_bytes(f, "value", width))
        return _wrap(w, lambda: Move(Ics(offset, ics), value))
    if kind == "variable_arith":
        op = f.text("op")
        if op not in VAR_OPS:
            raise EditError(f"{f.path('op')}: {op!r} is not one of {', '.join(VAR_OPS)}")
        dst = _numbered_ram(f, "variable", "VAR")
        data = Data(_value_bytes(f, "value", 2))
        return _wrap(w, lambda: OPS[op](dst, data))
    if kind == "move":
        return _wrap(w, lambda: Move(*_operands(f)))
    if kind == "compare":
        return _wrap(w, lambda: Sub(*_operands(f), no_write=True))
    op = f.text("op")
    if op not in OPS:
        raise EditError(f"{f.path('op')}: {op!r} is not one of {', '.join(OPS)}")
    no_write = f.flag("no_write", False)
    if op in ("not", "shift"):
        target = parse_operand(f.get("dst"), f.path("dst"))
        if not isinstance(target, (Ram, Ics, Rom)):
            raise EditError(f"{f.path('dst')}: NOT and SHIFT work on RAM, ICS or ROM")
        size = f.integer("size", 1, 128)
        if op == "not":
            return _wrap(w, lambda: Not(target, size, no_write))
        count = f.integer("count", 0, 255)
        return _wrap(w, lambda: Shift(target, size, no_write, count))
    return _wrap(w, lambda: OPS[op](*_operands(f), no_write=no_write))


def _pairs_of(f: Fields, name: str) -> dict[int, int]:
    return f.ics_map(name, 0xFFFF if name == "positions" else 0xFF)


def _wait(f: Fields, here: int) -> tuple[bytes, ...]:
    timer = _numbered_ram(f, "timer", "TIMER")
    ms = f.integer("ms", 0, 100 * 0x7FFF)
    if ms % 100:
        raise EditError(f"{f.path('ms')}: the timers count 100 ms steps; {ms} is not one")
    move = Move(timer, Data((ms // 100).to_bytes(2, "little")))
    sub = Sub(timer, Data(WAIT_STOPPED), no_write=True)
    jump = Jump(here + len(move.encode()), Condition.from_byte(WAIT_WHILE))
    return move.encode(), sub.encode(), jump.encode()


def encode_block(block: Block, resolve: Resolver, where: str, here: int = 0) -> tuple[bytes, ...]:
    """The stored entries of ``block`` (one; two for a compare-and-branch; three for a wait)
    placed at ROM address ``here``."""
    f = Fields(block.fields, where)
    kind = block.kind
    if kind == "wait":
        return _wait(f, here)
    if kind == "raw":
        try:
            data = bytes.fromhex(f.text("hex"))
            frames, tail = split_frames(data)
        except (ValueError, ProtocolError) as exc:  # not hex; a frame whose checksum is wrong
            raise EditError(f"{f.path('hex')}: {exc}") from None
        if not frames or tail not in (b"", END):  # the build would refuse the project
            raise EditError(
                f"{f.path('hex')}: not whole command frames ({len(tail)} byte(s) after "
                f"{len(frames)} frame(s))"
            )
        return (data,)
    if kind == "end":
        return (Return().encode() + END,)
    if kind == "return":
        return (Return().encode(),)
    if kind == "pose":
        speed, upd = f.integer("frames", 0, 255), f.flag("update", True)
        positions = _pairs_of(f, "positions")
        return (_wrap(where, lambda: RunConstFrameServo(speed, positions, upd)),)
    if kind in ("servo_stretch", "servo_speed"):
        values = _pairs_of(f, "values")
        cls = SetStretch if kind == "servo_stretch" else SetSpeed
        return (_wrap(where, lambda: cls(values)),)
    if kind == "servo_single":
        ics, speed = f.integer("ics", 0, 0x7F), f.integer("frames", 0, 255)
        pos, upd = f.integer("position", 0, 0xFFFF), f.flag("update", True)
        return (_wrap(where, lambda: RunSingleServo(ics, speed, pos, upd)),)
    if kind == "servo_series":
        moves = f.get("moves")
        if not isinstance(moves, list) or not all(
            isinstance(m, list) and len(m) == 3 for m in moves
        ):
            raise EditError(f"{f.path('moves')}: expected [[ics, frames, position], ...]")
        upd = f.flag("update", True)
        return (_wrap(where, lambda: RunSeriesServo([tuple(m) for m in moves], upd)),)
    if kind in ("jump", "call"):
        return (_jump(f, resolve, Jump if kind == "jump" else Call),)
    if kind == "ics_comm":
        args = (
            f.integer("ics", 0, 35), f.integer("tx_count", 1, 64),
            f.integer("tx_address", 0, 0xFFFF), f.integer("rx_address", 0, 0xFFFF),
        )  # fmt: skip
        return (_wrap(where, lambda: CommunicateDevice(*args)),)
    if kind in BRANCHES:
        compare = _compare(f, kind)
        return (_wrap(where, lambda: compare), _jump(f, resolve))
    return (_encode_data(kind, f),)
