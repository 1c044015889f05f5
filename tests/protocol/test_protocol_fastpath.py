"""The fast paths of the protocol core give exactly what the plain definitions give."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.protocol import RunConstFrameServo, RunSingleServo
from rcb4hv.protocol.frame import checksum, sum_ok
from rcb4hv.protocol.servoframes import const_frame_servo_frame, single_servo_frame


@given(st.binary(max_size=300))
def test_checksum_is_the_low_byte_of_the_sum(data: bytes) -> None:
    assert checksum(data) == sum(data) & 0xFF


@given(st.binary(min_size=1, max_size=256))
def test_sum_ok_accepts_exactly_the_right_last_byte(data: bytes) -> None:
    assert sum_ok(data) == (data[-1] == sum(data[:-1]) & 0xFF)
    fixed = data[:-1] + bytes((sum(data[:-1]) & 0xFF,))
    assert sum_ok(fixed)
    assert sum_ok(bytearray(fixed))


def test_sum_ok_at_the_largest_sums() -> None:
    frame = b"\xff" * 255 + bytes(((255 * 255) & 0xFF,))
    assert sum_ok(frame)
    assert not sum_ok(frame[:-1] + bytes(((frame[-1] + 1) & 0xFF,)))


# --------------------------------------------------------------------------- servo frames

_any_int = st.one_of(
    st.integers(-3, 300), st.integers(0, 0x1_0005), st.integers(-(1 << 20), 1 << 20)
)
_odd = st.one_of(st.booleans(), st.floats(0, 40), st.none(), st.text(max_size=1))
_ics = st.one_of(st.integers(0, 35), st.integers(-2, 40), st.integers(100, 130), _odd)
_pos = st.one_of(st.integers(0, 0xFFFF), _any_int, _odd)
_speed = st.one_of(st.integers(0, 255), _any_int, _odd)
_flag = st.one_of(st.booleans(), st.integers(0, 2), st.none())


def _same(fast: object, slow: object) -> None:
    """Both calls give the same frame, or both raise ValueError."""
    results = []
    for call in (fast, slow):
        try:
            results.append(call())  # type: ignore[operator]
        except ValueError:
            results.append(ValueError)
    assert results[0] == results[1]


@given(st.dictionaries(_ics, _pos, max_size=37), _speed, _flag)
def test_const_frame_fast_path_is_the_dataclass(
    positions: dict[object, object], speed: object, flag: object
) -> None:
    _same(
        lambda: const_frame_servo_frame(speed, positions, flag),  # type: ignore[arg-type]
        lambda: RunConstFrameServo(speed, positions, flag).encode(),  # type: ignore[arg-type]
    )


@given(st.lists(st.tuples(_ics, _pos), max_size=6), _speed)
def test_const_frame_fast_path_takes_pairs_too(
    pairs: list[tuple[object, object]], speed: object
) -> None:
    _same(
        lambda: const_frame_servo_frame(speed, pairs),  # type: ignore[arg-type]
        lambda: RunConstFrameServo(speed, pairs).encode(),  # type: ignore[arg-type]
    )


@given(_ics, _speed, _pos, _flag)
def test_single_servo_fast_path_is_the_dataclass(
    ics: object, speed: object, position: object, flag: object
) -> None:
    _same(
        lambda: single_servo_frame(ics, speed, position, flag),  # type: ignore[arg-type]
        lambda: RunSingleServo(ics, speed, position, flag).encode(),  # type: ignore[arg-type]
    )


def test_servo_frames_golden() -> None:
    assert single_servo_frame(2, 30, 7500) == bytes.fromhex("07 0F 02 1E 4C 1D 9F")
    ids = (0, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19)
    frame = const_frame_servo_frame(10, dict.fromkeys(ids, 7600))
    assert frame == RunConstFrameServo(10, dict.fromkeys(ids, 7600)).encode()
    assert len(frame) == 9 + 2 * len(ids) and frame[:8] == bytes.fromhex("2B 10 FD FC 0F 00 00 0A")
    every = const_frame_servo_frame(1, dict.fromkeys(range(36), 0x8000), set_update_flag=False)
    assert every[2:7] == bytes.fromhex("FF FF FF FF 8F")


@given(
    st.dictionaries(st.integers(0, 35), st.integers(0, 0xFFFF), min_size=1, max_size=36),
    st.integers(0, 255),
    st.booleans(),
)
def test_const_frame_bytes_against_a_plain_encoding(
    positions: dict[int, int], speed: int, flag: bool
) -> None:
    """Byte by byte as the command reference lays 10h out, written without the fast code."""
    bitmap = sum(1 << k for k in positions) | (0 if flag else 1 << 39)
    body = bytes([9 + 2 * len(positions), 0x10]) + bitmap.to_bytes(5, "little") + bytes([speed])
    body += b"".join(positions[k].to_bytes(2, "little") for k in sorted(positions))
    expected = body + bytes([sum(body) & 0xFF])
    assert const_frame_servo_frame(speed, positions, flag) == expected
    assert RunConstFrameServo(speed, positions, flag).encode() == expected
