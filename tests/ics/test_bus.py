"""The emulated ICS bus on a virtual clock: echo first, silence, delays, ID commands, garbage."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.emulator import VirtualClock
from rcb4hv.ics import EmulatedBus, EmulatedServo, IcsSettings
from rcb4hv.ics import codec as c
from rcb4hv.ics.eeprom import Eeprom


def h(text: str) -> bytes:
    return bytes.fromhex(text)


def bus_of(*ids: int, settings: IcsSettings | None = None) -> tuple[EmulatedBus, VirtualClock]:
    clock = VirtualClock()
    return EmulatedBus.with_ids(ids or (0,), clock=clock, settings=settings), clock


def test_echo_then_reply() -> None:
    bus, _ = bus_of(0)
    assert bus.feed(h("a0 01")) == h("a0 01 20 01 5a")  # stretch 90
    assert bus.feed(h("80 3a 4c")) == h("80 3a 4c 00 3a 4c")
    assert bus.feed(h("ff 00 00 00")) == h("ff 00 00 00 e0")


def test_an_absent_id_gets_only_the_echo() -> None:
    bus, clock = bus_of(0)
    assert bus.feed(h("a5 01")) == h("a5 01")
    clock.advance(1.0)
    bus.tick()
    assert bus.take_output() == b""


def test_a_command_split_across_feeds_is_answered_when_whole() -> None:
    bus, _ = bus_of(2)
    assert bus.feed(h("c2")) == h("c2")
    assert bus.feed(h("02")) == h("02")
    assert bus.feed(h("64")) == h("64 42 02 64")


def test_eeprom_write_answers_after_the_documented_delay() -> None:
    bus, clock = bus_of(1)
    frame = c.encode_eeprom_write(1, Eeprom().replace(id=1, stretch=40).data)
    assert bus.feed(frame) == frame  # the echo only
    assert bus.poll_timeout() == pytest.approx(0.35)
    clock.advance(0.34)
    bus.tick()
    assert bus.take_output() == b""
    assert bus.feed(h("a1 01")) == h("a1 01")  # busy writing: silent
    clock.advance(0.02)
    bus.tick()
    assert bus.take_output() == h("41 00")
    assert bus.feed(h("a1 01")) == h("a1 01 21 01 28")  # stretch 40 took effect


def test_live_writes_do_not_persist_by_default() -> None:
    bus, _ = bus_of(0)
    bus.feed(h("c0 01 20"))
    servo = bus.servo(0)
    assert servo is not None and servo.stretch == 0x20 and servo.eeprom.stretch == 90
    persist, _ = bus_of(0, settings=IcsSettings(live_writes_persist=True))
    persist.feed(h("c0 01 20"))
    s2 = persist.servo(0)
    assert s2 is not None and s2.eeprom.stretch == 0x20


def test_id_write_renumbers_and_the_new_id_answers() -> None:
    bus, _ = bus_of(0)
    assert bus.feed(h("e9 01 01 01")) == h("e9 01 01 01 e9")
    assert bus.feed(h("a0 01")) == h("a0 01")
    assert bus.feed(h("a9 01")) == h("a9 01 29 01 5a")
    servo = bus.servo(9)
    assert servo is not None and servo.eeprom.servo_id == 9


def test_id_read_with_two_servos_collides() -> None:
    bus, _ = bus_of(1, 2)
    assert bus.feed(h("ff 00 00 00")) == h("ff 00 00 00") + bytes((0xE1 & 0xE2,))
    silent, _ = bus_of(1, 2, settings=IcsSettings(id_collision="silent"))
    assert silent.feed(h("ff 00 00 00")) == h("ff 00 00 00")


def test_position_read_is_ics36_only() -> None:
    bus, _ = bus_of(0)
    assert bus.feed(h("a0 05")) == h("a0 05 20 05 3a 4c")
    old, _ = bus_of(0, settings=IcsSettings(version="3.5"))
    assert old.feed(h("a0 05")) == h("a0 05")


def test_the_servo_moves_at_its_speed_and_reports_where_it_is() -> None:
    bus, clock = bus_of(0)
    bus.feed(h("c0 02 7f"))
    bus.feed(c.encode_position(0, 8000))  # 500 counts at ~13675 counts/s: ~37 ms
    clock.advance(0.01)
    mid = c.join7(*bus.feed(h("a0 05"))[-2:])
    assert 7500 < mid < 8000
    clock.advance(0.1)
    assert c.join7(*bus.feed(h("a0 05"))[-2:]) == 8000
    assert bus.feed(h("80 00 00"))[-3:] == h("00 3e 40")  # free: answers where it is


def test_targets_are_clamped_to_the_eeprom_limits() -> None:
    clock = VirtualClock()
    servo = EmulatedServo(0, Eeprom().replace(max_pulse=9000))
    bus = EmulatedBus([servo], clock=clock)
    bus.feed(c.encode_position(0, 11000))
    clock.advance(1.0)
    assert servo.position(clock.now()) == 9000


def test_load_reads_back_as_current_and_temperature() -> None:
    bus, _ = bus_of(0)
    servo = bus.servo(0)
    assert servo is not None
    servo.set_load(-1.5, 90.0)
    assert bus.feed(h("a0 03"))[-1] == 64 + 15  # reverse, 0.1 A a count
    assert bus.feed(h("a0 04"))[-1] == 47  # 90 degC on the rcb4 table


def test_a_servo_at_another_baud_than_the_host_is_silent() -> None:
    bus, _ = bus_of(0)
    bus.host_baud = 1250000
    assert bus.feed(h("a0 01")) == h("a0 01")
    bus.host_baud = 115200
    assert bus.feed(h("a0 01")) == h("a0 01 20 01 5a")


def test_0eh_style_exchange_returns_the_answer_without_echo() -> None:
    bus, _ = bus_of(4)
    assert bus.exchange(h("a4 02")) == h("24 02 7f")
    assert bus.exchange(h("a5 02")) is None


@given(st.lists(st.binary(max_size=80), max_size=12))
def test_garbage_never_crashes_and_the_echo_always_comes_first(chunks: list[bytes]) -> None:
    bus, clock = bus_of(0, 1, 31)
    for chunk in chunks:
        out = bus.feed(chunk)
        assert out[: len(chunk)] == chunk
        clock.advance(0.05)
        bus.tick()
        bus.take_output()
    # whatever came before (even an ID or EEPROM write), a whole command still gets an answer
    clock.advance(1.0)
    bus.tick()
    bus.take_output()
    sid = bus.servos[0].servo_id
    command = c.encode_read(sid, c.Sc.SPEED)
    out = bus.feed(b"\xff" + command)  # a lone command byte first: the next one resyncs
    reply = c.decode_reply(command, c.strip_echo(b"\xff" + command, out))
    assert isinstance(reply, c.ValueReply) and reply.servo_id == sid


@given(st.sampled_from([0, 1]), st.integers(1, 127))
def test_settings_conversions_are_monotonic(sign: int, raw: int) -> None:
    s = IcsSettings()
    t = s.temperature_c(raw)
    assert s.temperature_c(raw - 1) >= t
    assert abs(s.temperature_raw(t) - raw) <= 1
    amps = (raw % 64) * s.current_scale_a * (-1 if sign else 1)
    got = s.current_raw(amps)
    assert got == (raw % 64) + (64 if sign and raw % 64 else 0)
