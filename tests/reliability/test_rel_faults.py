"""Fault injection on a real TCP link to the emulator: drop, corrupt, delay, duplicate, split,
disconnect. Every call ends within its timeout (+ LOADED_SLACK) with the right typed error, is never
retried, and the next calls on the healed link succeed."""

from __future__ import annotations

import time
from collections.abc import Iterator

import pytest

from rcb4hv.errors import Rcb4TimeoutError
from rcb4hv.protocol import Data, Ram
from rcb4hv.transport import Fault
from tests.reliability.linkfaults import LinkFault
from tests.reliability.scenarios import (
    FAULT_SCENARIOS,
    LOADED_SLACK,
    FaultScenario,
    TcpRig,
    run_fault_scenario,
    tcp_rig,
)


@pytest.fixture(scope="module")
def rig() -> Iterator[TcpRig]:
    # real time is the thing under test here; on a loaded runner (load 4 on two cores) a reply
    # or the board's frame-timeout NAK can be late by a good part of a second, so the client
    # waits 1 s and the board's frame timeout is 0.2 s (a split request's short gap is a tenth
    # of it, the long gap three times it: both still far from the other side)
    with tcp_rig(timeout=1.0, frame_timeout=0.2) as r:
        r.client.acknowledge_check(timeout=2.0)
        yield r


@pytest.mark.parametrize("scenario", FAULT_SCENARIOS, ids=[s.name for s in FAULT_SCENARIOS])
def test_fault_scenario(rig: TcpRig, scenario: FaultScenario) -> None:
    value = bytes((len(scenario.name), 0x5A, 0xA5, 0x3C))
    rig.client.write_ram(0x0462, value)
    outcome = run_fault_scenario(rig, scenario, value, LOADED_SLACK)
    assert outcome.ok, outcome.why
    if scenario.expected is not None:
        assert outcome.got in {e.__name__ for e in scenario.expected}


def test_the_client_never_retries_a_write(rig: TcpRig) -> None:
    """No retries in Rcb4Client: a write whose reply is lost is sent exactly once (a retry of
    a non-idempotent command, e.g. ADD, would apply it twice)."""
    client = rig.client
    client.write_ram(0x0462, b"\x00\x00")
    rig.faults.inject(Fault.DROP_REPLY)
    before = rig.faults.transactions
    with pytest.raises(Rcb4TimeoutError):
        client.add(Ram(0x0462), Data(b"\x01\x00"), 2)
    assert rig.faults.transactions - before == 1
    time.sleep(0.05)
    assert client.read_ram(0x0462, 2) == b"\x01\x00"  # applied once, not twice


def test_scenario_checker_flags_a_wrong_outcome(rig: TcpRig) -> None:
    """The checker bites: a duplicated reply declared as a timeout is reported as a failure."""
    wrong = FaultScenario("duplicate as timeout", LinkFault.DUPLICATE_REPLY, (Rcb4TimeoutError,))
    value = b"\x01\x02\x03\x04"
    rig.client.write_ram(0x0462, value)
    outcome = run_fault_scenario(rig, wrong, value, LOADED_SLACK)
    assert not outcome.ok and "expected Rcb4TimeoutError" in outcome.why
    assert outcome.elapsed < rig.client.timeout + LOADED_SLACK
