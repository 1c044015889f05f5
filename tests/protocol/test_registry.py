"""There is one command table (rcb4hv.protocol.registry) and everything keyed by command
comes from it: decoders, describe's operators, the assembler's and disassembler's mnemonics,
the emulator's dispatch and ALU operations. Nothing else lists the command classes."""

from __future__ import annotations

import ast
import inspect
import typing
from pathlib import Path

import pytest

import rcb4hv
from rcb4hv.asm import assemble
from rcb4hv.asm.disassembler import format_command
from rcb4hv.asm.syntax import SHIFT_WORDS
from rcb4hv.emulator import Board
from rcb4hv.emulator.alu import OP_OF, AluOp
from rcb4hv.protocol import (
    AcknowledgeCheck,
    Add,
    And,
    Call,
    Com,
    Command,
    CommunicateDevice,
    Condition,
    Data,
    Div,
    GetVersionInfo,
    Ics,
    Jump,
    Mod,
    Move,
    Mul,
    Not,
    Or,
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
    Xor,
    branches,
    datacmds,
    decode_command,
    encode_command,
    servocmds,
)
from rcb4hv.protocol.describe import describe_command
from rcb4hv.protocol.registry import (
    BINARY_OPS,
    BY_MNEMONIC,
    COMMANDS,
    DECODERS,
    SPECS,
    spec_of,
)

SRC = Path(rcb4hv.__file__).parent

# one instance of every command: the test's own list, checked against the registry below
SAMPLES: list[Command] = [
    Move(Ram(0x0100), Data(b"\x01\x02")),
    And(Ram(0x0100), Ram(0x0200), 2, True),
    Or(Ics(4, 3), Data(b"\x80")),
    Xor(Rom(0x1000), Ram(0x0010), 1),
    Not(Ram(0x0300), 2),
    Shift.left(Ram(0x0300), 3, 2),
    Add(Com(), Rom(0x2000), 2),
    Sub(Ram(0x0100), Data(b"\x05\x00")),
    Mul(Ram(0x0100), Data(b"\x03")),
    Div(Ram(0x0100), Data(b"\x02")),
    Mod(Ram(0x0100), Data(b"\x07"), no_write=True),
    Jump(0x0C15, Condition.if_zero()),
    Call(0x0B80),
    Return(),
    CommunicateDevice(3, 2, 0x0300, 0x0310),
    RunSingleServo(5, 10, 7500),
    RunConstFrameServo(20, {0: 7500, 3: 8000}),
    RunSeriesServo([(1, 5, 7000), (2, 6, 8000)], set_update_flag=False),
    SetStretch({0: 60, 1: 70}),
    SetSpeed({2: 100}),
    GetVersionInfo(),
    AcknowledgeCheck(long_form=True),
]


def _command_classes() -> set[type]:
    """Every concrete command class defined in the protocol's command modules: a class with
    an ``encode`` method and a real command byte, that no other such class derives from."""
    found: set[type] = set()
    for module in (datacmds, branches, servocmds):
        for _, obj in inspect.getmembers(module, inspect.isclass):
            own = obj.__module__ == module.__name__ and hasattr(obj, "encode")
            if own and getattr(obj, "cmd", -1) >= 0:
                found.add(obj)
    return {c for c in found if not any(o is not c and issubclass(o, c) for o in found)}


def test_every_command_class_is_in_the_table_exactly_once() -> None:
    classes = [s.cls for s in COMMANDS]
    assert len(classes) == len(set(classes)) == 22
    assert set(classes) == _command_classes()
    assert set(classes) == set(typing.get_args(Command))
    assert {type(c) for c in SAMPLES} == set(classes)
    assert [s.opcode for s in COMMANDS] == sorted(s.opcode for s in COMMANDS)


@pytest.mark.parametrize("spec", COMMANDS, ids=lambda s: s.mnemonic)
def test_each_row_is_the_class_own_codec(spec: object) -> None:
    assert spec is SPECS[spec.cls] is spec_of(spec.cls) is BY_MNEMONIC[spec.mnemonic]  # type: ignore[attr-defined]
    cls = spec.cls  # type: ignore[attr-defined]
    assert spec.opcode == cls.cmd  # type: ignore[attr-defined]
    assert spec.decode == cls.from_frame  # type: ignore[attr-defined]
    # decode_command finds this class's decoder by command byte
    assert DECODERS[spec.opcode] is not None  # type: ignore[attr-defined]
    sample = next(c for c in SAMPLES if type(c) is cls)
    frame = encode_command(sample)
    assert frame[1] == spec.opcode  # type: ignore[attr-defined]
    assert decode_command(frame) == sample
    assert DECODERS[frame[1]](frame) == sample


def test_binary_operations_take_operator_and_mnemonic_from_the_table() -> None:
    assert {s.cls for s in BINARY_OPS} == {And, Or, Xor, Add, Sub, Mul, Div, Mod}
    for cmd in SAMPLES:
        spec = spec_of(type(cmd))
        text = describe_command(cmd)
        if spec.symbol is not None:
            assert f" {spec.symbol} " in text
        else:
            assert not any(f" {s.symbol} " in text for s in BINARY_OPS)


@pytest.mark.parametrize("cmd", SAMPLES, ids=lambda c: type(c).__name__)
def test_asm_mnemonics_come_from_the_table(cmd: Command) -> None:
    spec = spec_of(type(cmd))
    text = format_command(cmd)
    word = text.split()[0].split(".")[0]
    assert SHIFT_WORDS.get(word, word) == spec.mnemonic
    assert assemble(text).data == encode_command(cmd)


def test_emulator_dispatch_is_built_from_the_table() -> None:
    board = Board()
    try:
        dispatch = board._interp.dispatch
        assert set(dispatch) == set(SPECS)
        for spec in COMMANDS:
            handler = dispatch[spec.cls]
            assert handler.__self__ is board._interp  # type: ignore[attr-defined]
            name = handler.__name__  # type: ignore[attr-defined]
            if spec.cls in OP_OF:
                assert name == "_exec_alu"
                # the ALU operation is the command byte
                assert OP_OF[spec.cls] == AluOp(spec.opcode)
                assert OP_OF[spec.cls].name == spec.mnemonic
            else:
                assert name in (f"_exec_{spec.mnemonic.lower()}", "_exec_servo", "_exec_stretch")
        assert set(OP_OF) == {s.cls for s in COMMANDS if s.opcode in set(AluOp)}
    finally:
        board.close()


def _string_constants(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and isinstance(node.value, str):
            out.add(node.value)
    return out


def test_no_parallel_table_of_operators_or_mnemonics() -> None:
    """The binary operations' operators and mnemonics (once written in five tables) are
    written once, in registry.py."""
    words = {s.mnemonic for s in BINARY_OPS} | {s.symbol for s in BINARY_OPS if s.symbol}
    holders: dict[str, list[str]] = {}
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if rel == "protocol/registry.py" or rel.startswith("cli/"):
            continue
        for word in _string_constants(path) & words:
            holders.setdefault(word, []).append(rel)
    assert holders == {}


def test_each_public_name_has_one_home() -> None:
    """Every name ``rcb4hv.protocol`` exports is in the ``__all__`` of exactly one of its
    modules (no chain of re-exports: the package imports each from where it is defined)."""
    import importlib
    import pkgutil

    import rcb4hv.protocol as protocol

    modules = [
        importlib.import_module(f"rcb4hv.protocol.{m.name}")
        for m in pkgutil.iter_modules(protocol.__path__)
    ]
    for name in protocol.__all__:
        homes = [m.__name__ for m in modules if name in getattr(m, "__all__", ())]
        assert len(homes) == 1, (name, homes)
