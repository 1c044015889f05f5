"""Human-readable and JSON-friendly views of commands and replies (for logs, the CLI, tests)."""

from __future__ import annotations

from dataclasses import fields

from rcb4hv.protocol.branches import Call, CommunicateDevice, Condition, Jump, Return
from rcb4hv.protocol.datacmds import BinaryOp, Move, Not, Shift
from rcb4hv.protocol.memory import position_to_degrees
from rcb4hv.protocol.operands import (
    POSITION_FREE,
    POSITION_HOLD,
    Com,
    Data,
    Ics,
    Ram,
    Rom,
    operand_text,
)
from rcb4hv.protocol.registry import Command, spec_of
from rcb4hv.protocol.replies import Ack, DataReply, Nak, Reply, VersionReply
from rcb4hv.protocol.servocmds import (
    AcknowledgeCheck,
    GetVersionInfo,
    RunConstFrameServo,
    RunSeriesServo,
    RunSingleServo,
    SetSpeed,
    SetStretch,
)

__all__ = ["command_fields", "command_name", "describe_command", "describe_reply", "operand_text"]


def command_name(cmd: Command) -> str:
    """The class name, which is also the name used in the command reference."""
    return type(cmd).__name__


def _position_text(pos: int) -> str:
    if pos == POSITION_FREE:
        return "free (8000h)"
    if pos == POSITION_HOLD:
        return "hold (7FFFh)"
    return f"{pos} ({position_to_degrees(pos):+.1f}°)"


def _flag_text(set_update_flag: bool) -> str:
    return "" if set_update_flag else ", update flags untouched"


def describe_command(cmd: Command) -> str:
    """One line saying what ``cmd`` does."""
    name = command_name(cmd)
    if isinstance(cmd, Move):
        if isinstance(cmd.dst, Com):
            return f"Move: read {cmd.nbytes} byte(s) from {operand_text(cmd.src)} to the host"
        return f"Move: {operand_text(cmd.dst)} <- {operand_text(cmd.src)} ({cmd.nbytes} byte(s))"
    if isinstance(cmd, Shift):
        n = cmd.right_bits
        how = "no shift" if n == 0 else (f"right by {n}" if n > 0 else f"left by {-n}")
        nw = " (flags only)" if cmd.no_write else ""
        return f"Shift{nw}: {operand_text(cmd.dst)} {how} ({cmd.size} byte(s))"
    if isinstance(cmd, Not):
        nw = " (flags only)" if cmd.no_write else ""
        return f"Not{nw}: {operand_text(cmd.dst)} = ~{operand_text(cmd.dst)} ({cmd.size} byte(s))"
    if isinstance(cmd, BinaryOp):
        nw = " (flags only, no write-back)" if cmd.no_write else ""
        return (
            f"{name}{nw}: {operand_text(cmd.dst)} {spec_of(type(cmd)).symbol} "
            f"{operand_text(cmd.src)} ({cmd.nbytes} byte(s))"
        )
    if isinstance(cmd, (Jump, Call)):
        when = "" if cmd.condition == Condition() else f" if {cmd.condition}"
        return f"{name} to ROM {cmd.address:06X}h{when}"
    if isinstance(cmd, Return):
        return "Return (pop the call stack)"
    if isinstance(cmd, CommunicateDevice):
        return (
            f"CommunicateDevice: send {cmd.tx_count} byte(s) from RAM[{cmd.tx_address:04X}h] to "
            f"ICS {cmd.ics}, answer to RAM[{cmd.rx_address:04X}h]"
        )
    if isinstance(cmd, RunSingleServo):
        return (
            f"RunSingleServo: ICS {cmd.ics} to position {_position_text(cmd.position)} "
            f"at speed {cmd.speed}{_flag_text(cmd.set_update_flag)}"
        )
    if isinstance(cmd, RunConstFrameServo):
        servos = ", ".join(f"ICS {k}: {_position_text(v)}" for k, v in cmd.positions)
        return (
            f"RunConstFrameServo: speed {cmd.speed}, {len(cmd.positions)} servo(s): {servos}"
            f"{_flag_text(cmd.set_update_flag)}"
        )
    if isinstance(cmd, RunSeriesServo):
        servos = ", ".join(f"ICS {k}: {_position_text(v)} at speed {s}" for k, s, v in cmd.moves)
        return f"RunSeriesServo: {servos}{_flag_text(cmd.set_update_flag)}"
    if isinstance(cmd, (SetSpeed, SetStretch)):
        values = ", ".join(f"ICS {k}: {v}" for k, v in cmd.values)
        return f"{name}: {values}"
    if isinstance(cmd, GetVersionInfo):
        return "GetVersionInfo: ask for the version string"
    if isinstance(cmd, AcknowledgeCheck):
        form = "04 FE 06 08" if cmd.long_form else "03 FE 01"
        return f"AcknowledgeCheck ({form})"
    return name  # pragma: no cover - every command is handled above


def _json_value(value: object) -> object:
    if isinstance(value, (Ram, Ics, Rom, Com, Data)):
        out: dict[str, object] = {"kind": type(value).__name__.upper()}
        for f in fields(value):
            v = getattr(value, f.name)
            out[f.name] = v.hex(" ").upper() if isinstance(v, bytes) else v
        return out
    if isinstance(value, Condition):
        return {"byte": value.to_byte(), "text": str(value)}
    if isinstance(value, tuple):
        return [_json_value(v) for v in value]
    if isinstance(value, bytes):
        return value.hex(" ").upper()
    return value


def command_fields(cmd: Command) -> dict[str, object]:
    """``{"command": name, <field>: value, ...}`` with JSON-serialisable values."""
    out: dict[str, object] = {"command": command_name(cmd)}
    for f in fields(cmd):
        out[f.name] = _json_value(getattr(cmd, f.name))
    return out


def describe_reply(reply: Reply) -> str:
    """One line saying what a reply says."""
    if isinstance(reply, Ack):
        return f"ACK of {reply.cmd:02X}h"
    if isinstance(reply, Nak):
        return f"NAK of {reply.cmd:02X}h"
    if isinstance(reply, VersionReply):
        return f"version {reply.text!r}"
    assert isinstance(reply, DataReply)
    return f"data reply to {reply.cmd:02X}h: {reply.data.hex(' ').upper()}"
