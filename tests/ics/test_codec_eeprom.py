"""The ICS codec and EEPROM model: golden bytes from the public protocol facts, round trips."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.errors import IcsError
from rcb4hv.ics import codec as c
from rcb4hv.ics.eeprom import (
    DEFAULT_EEPROM,
    FIELDS,
    RESERVED_BYTES,
    Eeprom,
    pack_nibbles,
    unpack_nibbles,
)

# FACTS "ICS 3.5 on the wire": position 7500 (0 degrees) is 3Ah, 4Ch in 7-bit halves.
GOLDEN = [
    (c.encode_position(0, 7500), "80 3a 4c"),
    (c.encode_position(5, 11500), "85 59 6c"),
    (c.encode_position(31, 3500), "9f 1b 2c"),
    (c.encode_position(2, c.POSITION_FREE), "82 00 00"),
    (c.encode_read(0, c.Sc.EEPROM), "a0 00"),
    (c.encode_read(3, c.Sc.STRETCH), "a3 01"),
    (c.encode_read(3, c.Sc.POSITION), "a3 05"),
    (c.encode_write(1, c.Sc.SPEED, 100), "c1 02 64"),
    (c.encode_write(1, c.Sc.CURRENT, 30), "c1 03 1e"),
    (c.encode_id_read(), "ff 00 00 00"),
    (c.encode_id_write(5), "e5 01 01 01"),
]


@pytest.mark.parametrize(("command", "golden"), GOLDEN)
def test_commands_are_the_documented_bytes(command: bytes, golden: str) -> None:
    assert command == bytes.fromhex(golden)


def test_eeprom_write_is_command_sc0_and_64_nibbles() -> None:
    frame = c.encode_eeprom_write(4, DEFAULT_EEPROM)
    assert frame[:2] == b"\xc4\x00" and frame[2:] == DEFAULT_EEPROM and len(frame) == 66
    assert c.command_length(frame[:2]) == 66 and c.reply_length(frame) == 2


@pytest.mark.parametrize(
    ("command", "reply", "decoded"),
    [
        ("80 3a 4c", "00 3a 4c", c.PositionReply(0, 7500)),
        ("a3 01", "23 01 3c", c.ValueReply(3, c.Sc.STRETCH, 60)),
        ("a3 05", "23 05 3e 40", c.ValueReply(3, c.Sc.POSITION, 8000)),
        ("c1 02 64", "41 02 64", c.WriteReply(1, c.Sc.SPEED, 100)),
        ("ff 00 00 00", "e7", c.IdReply(7)),
        ("e5 01 01 01", "e5", c.IdReply(5)),
    ],
)
def test_replies_decode(command: str, reply: str, decoded: c.Reply) -> None:
    assert c.decode_reply(bytes.fromhex(command), bytes.fromhex(reply)) == decoded


@pytest.mark.parametrize(
    ("command", "reply"),
    [
        ("a3 01", "24 01 3c"),  # another servo's answer
        ("a3 01", "23 02 3c"),  # another sub-command
        ("80 3a 4c", "00 3a"),  # short
        ("ff 00 00 00", "07"),  # not E0h|id
    ],
)
def test_wrong_replies_raise(command: str, reply: str) -> None:
    with pytest.raises(IcsError):
        c.decode_reply(bytes.fromhex(command), bytes.fromhex(reply))


def test_strip_echo_checks_the_echo() -> None:
    cmd = bytes.fromhex("a0 01")
    assert c.strip_echo(cmd, bytes.fromhex("a0 01 20 01 5a")) == bytes.fromhex("20 01 5a")
    with pytest.raises(IcsError):
        c.strip_echo(cmd, bytes.fromhex("a1 01 20 01 5a"))


def test_bad_arguments_are_value_errors() -> None:
    for bad in (lambda: c.encode_position(32, 7500), lambda: c.encode_position(0, 12000)):
        with pytest.raises(ValueError):
            bad()
    with pytest.raises(ValueError):
        c.encode_write(0, c.Sc.POSITION, 1)
    with pytest.raises(ValueError):
        c.encode_write(0, c.Sc.STRETCH, 128)


@given(st.integers(0, 0x3FFF))
def test_seven_bit_halves_round_trip(value: int) -> None:
    hi, lo = c.split7(value)
    assert hi < 0x80 and lo < 0x80 and c.join7(hi, lo) == value


@given(st.integers(1, 8).flatmap(lambda n: st.tuples(st.just(n), st.integers(0, 16**n - 1))))
def test_nibble_packing_round_trips(case: tuple[int, int]) -> None:
    count, value = case
    packed = pack_nibbles(value, count)
    assert len(packed) == count and all(b <= 0x0F for b in packed)
    assert unpack_nibbles(packed) == value


@given(st.binary(min_size=64, max_size=64).map(lambda b: bytes(x & 0x0F for x in b)))
def test_eeprom_bytes_round_trip_through_fields_and_json(data: bytes) -> None:
    e = Eeprom(data)
    assert Eeprom.from_json(e.to_json()) == e
    # setting every field to the value it has changes no byte
    same = e.replace(**{f.name: e.get(f.name) for f in FIELDS if f.low <= e.get(f.name) <= f.high})
    assert same.data == data


@given(
    st.binary(min_size=64, max_size=64).map(lambda b: bytes(x & 0x0F for x in b)),
    st.integers(1, 127),
    st.integers(3500, 11500),
    st.booleans(),
)
def test_setting_fields_keeps_the_do_not_change_bytes(
    data: bytes, stretch: int, pulse: int, reverse: bool
) -> None:
    e = Eeprom(data).replace(stretch=stretch, max_pulse=pulse, reverse=int(reverse))
    assert e.stretch == stretch and e.get("max_pulse") == pulse and e.get("reverse") == reverse
    assert all(e.data[n - 1] == data[n - 1] for n in RESERVED_BYTES)


def test_the_default_eeprom_decodes_to_its_documented_values() -> None:
    f = Eeprom().fields()
    assert Eeprom().header_ok
    assert (f["stretch"], f["speed"], f["punch"], f["dead_band"], f["damping"]) == (
        90,
        127,
        0,
        2,
        30,
    )
    assert (f["max_pulse"], f["min_pulse"], f["baud"], f["id"]) == (11500, 3500, 1250000, 0)
    assert (f["free"], f["reverse"], f["rotation"], f["slave"]) == (1, 0, 0, 0)
    assert (f["stretch_1"], f["stretch_2"], f["stretch_3"]) == (30, 60, 127)
    assert (1, 2, 25, 26, *range(33, 51), 55, 56) == RESERVED_BYTES


def test_stretch_is_stored_doubled_and_baud_in_the_low_nibble() -> None:
    e = Eeprom().replace(stretch=60, baud=115200)
    assert e.data[2:4] == bytes((0x7, 0x8))  # 120 = 78h
    assert e.data[27] == 10 and e.baud == 115200


def test_restore_merge_keeps_the_targets_reserved_bytes_and_id() -> None:
    target = Eeprom(bytes(range(16)) * 4).replace(id=7)
    backup = Eeprom().replace(stretch=20, id=3)
    merged = target.merged_from(backup)
    assert merged.stretch == 20 and merged.servo_id == 7
    assert all(merged.data[n - 1] == target.data[n - 1] for n in RESERVED_BYTES)


@pytest.mark.parametrize(
    "bad",
    [
        {},
        {"format": "x"},
        {"format": "rcb4hv-ics-eeprom/1", "bytes": [0] * 63},
        {"format": "rcb4hv-ics-eeprom/1", "bytes": [16] * 64},
    ],
)
def test_malformed_backups_are_typed_errors(bad: object) -> None:
    with pytest.raises(IcsError):
        Eeprom.from_json(bad)
