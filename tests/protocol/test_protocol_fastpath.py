"""The fast paths of the protocol core give exactly what the plain definitions give."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.protocol.frame import checksum, sum_ok


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
