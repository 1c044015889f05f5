"""Hypothesis strategies for every command of the protocol core (shared by all test suites)."""

from __future__ import annotations

from hypothesis import strategies as st

from rcb4hv import protocol as p

ics_numbers = st.integers(0, 35)
single_servo_ics = st.integers(0, 0x7F)  # 0Fh: bits 6-0 of the ICS byte, any value
positions = st.integers(0, 0xFFFF)
speeds = st.integers(0, 255)
stretch_values = st.integers(0, 255)  # 12h: any byte (documented 1-127; real projects send 0)


def _ram(size: int) -> st.SearchStrategy[p.Ram]:
    return st.integers(0, p.RAM_SIZE - size).map(p.Ram)


def _rom(size: int) -> st.SearchStrategy[p.Rom]:
    return st.integers(0, p.ROM_SIZE - size).map(p.Rom)


def _ics() -> st.SearchStrategy[p.Ics]:
    return st.builds(p.Ics, st.integers(0, 255), ics_numbers)


@st.composite
def _binary(draw: st.DrawFn, cls: type, max_size: int, allow_com: bool) -> p.Command:
    size = draw(st.integers(1, min(max_size, 121)))
    dsts = [_ram(size), _ics(), _rom(size)]
    if allow_com:
        dsts.append(st.just(p.Com()))
    dst = draw(st.one_of(*dsts))
    src = draw(
        st.one_of(
            _ram(size), _ics(), _rom(size), st.binary(min_size=size, max_size=size).map(p.Data)
        )
    )
    if cls is p.Move:
        return p.Move(dst, src, size)
    return cls(dst, src, size, draw(st.booleans()))  # type: ignore[no-any-return]


@st.composite
def _unary(draw: st.DrawFn, cls: type) -> p.Command:
    size = draw(st.integers(1, 128))
    dst = draw(st.one_of(_ram(size), _ics(), _rom(size)))
    if cls is p.Not:
        return p.Not(dst, size, draw(st.booleans()))
    return p.Shift(dst, size, draw(st.booleans()), draw(st.integers(0, 255)))


conditions = st.builds(p.Condition, st.booleans(), st.booleans(), st.booleans(), st.booleans())

commands: st.SearchStrategy[p.Command] = st.one_of(
    _binary(p.Move, 128, True),
    *(_binary(c, 128, False) for c in (p.And, p.Or, p.Xor)),
    *(_binary(c, 2, True) for c in (p.Add, p.Sub, p.Mul, p.Div, p.Mod)),
    _unary(p.Not),
    _unary(p.Shift),
    st.builds(p.Jump, st.integers(0, 0xFFFFFF), conditions),
    st.builds(p.Call, st.integers(0, 0xFFFFFF), conditions),
    st.just(p.Return()),
    st.integers(1, 64).flatmap(
        lambda n: st.builds(
            p.CommunicateDevice,
            ics_numbers,
            st.just(n),
            st.integers(0, p.RAM_SIZE - n),
            st.integers(0, p.RAM_SIZE - 1),
        )
    ),
    st.builds(p.RunSingleServo, single_servo_ics, speeds, positions, st.booleans()),
    st.builds(
        p.RunConstFrameServo,
        speeds,
        st.dictionaries(ics_numbers, positions, max_size=36),
        st.booleans(),
    ),
    st.dictionaries(ics_numbers, st.tuples(speeds, positions), max_size=36).flatmap(
        lambda d: st.builds(
            p.RunSeriesServo,
            st.just([(k, s, v) for k, (s, v) in d.items()]),
            st.booleans(),
        )
    ),
    st.builds(p.SetSpeed, st.dictionaries(ics_numbers, stretch_values, max_size=36)),
    st.builds(p.SetStretch, st.dictionaries(ics_numbers, stretch_values, max_size=36)),
    st.just(p.GetVersionInfo()),
    st.builds(p.AcknowledgeCheck, st.booleans()),
)
"""Any valid command."""

command_frames = commands.map(p.encode_command)
"""Any valid command frame."""
