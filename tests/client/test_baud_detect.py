"""Baud-rate detection against a scripted serial link: a board that answers at one rate only,
and whose answers may arrive late (a busy host, a slow adapter)."""

from __future__ import annotations

import pytest

from rcb4hv.client import Rcb4Client
from rcb4hv.errors import TransportError
from rcb4hv.protocol import Ack, AcknowledgeCheck, encode_reply
from tests.client.scripted import ScriptedTransport

ACK = encode_reply(Ack(AcknowledgeCheck().cmd))
PROBE_S = 0.01


class ScriptedLink(ScriptedTransport):
    """A board at ``board_rate``. The answers to the first ``late`` checks sent at that rate
    arrive only while the host sends its next frame (after the host gave up waiting)."""

    url = "/dev/ttyFAKE0"

    def __init__(self, board_rate: int, late: int = 0) -> None:
        super().__init__()
        self.board_rate = board_rate
        self.late = late
        self.rate = 115200
        self.rates: list[int] = []
        self._in_flight = bytearray()

    def set_baudrate(self, baudrate: int) -> None:
        self.rate = baudrate
        self.rates.append(baudrate)

    def write(self, data: bytes) -> None:
        self.writes.append(bytes(data))
        self._rx += self._in_flight  # a late answer to the previous check lands now
        self._in_flight.clear()
        if self.rate != self.board_rate:
            return  # at the wrong rate the board hears noise and stays silent
        if self.late > 0:
            self.late -= 1
            self._in_flight += ACK
        else:
            self._rx += ACK


@pytest.mark.parametrize("board_rate", [1250000, 625000, 115200])
def test_finds_the_rate_the_board_answers_at(board_rate: int) -> None:
    link = ScriptedLink(board_rate)
    assert Rcb4Client(link).detect_baudrate(probe_timeout=PROBE_S) == board_rate
    assert link.rate == board_rate


def test_a_late_answer_is_not_taken_for_the_next_rate() -> None:
    """The ACK to the check at 1,250,000 baud arrives while the check at the next rate goes
    out: the board is still found at 1,250,000 (taking it as 625,000's answer was a bug)."""
    link = ScriptedLink(1250000, late=1)
    assert Rcb4Client(link).detect_baudrate(probe_timeout=PROBE_S) == 1250000
    assert link.rates == [1250000]


def test_a_rate_whose_only_answer_is_stale_is_not_confirmed() -> None:
    """One try a rate: the late ACK to the check at 1,250,000 baud lands at 625,000, but does
    not make 625,000 the board's rate, since the second check there goes unanswered."""
    link = ScriptedLink(1250000, late=1)
    with pytest.raises(TransportError, match="no answer"):
        Rcb4Client(link).detect_baudrate(probe_timeout=PROBE_S, tries=1)
    assert link.rates == [1250000, 625000, 115200]


def test_answers_that_always_come_late_still_find_the_rate() -> None:
    link = ScriptedLink(625000, late=100)
    assert Rcb4Client(link).detect_baudrate(probe_timeout=PROBE_S) == 625000


def test_no_answer_at_any_rate_is_a_transport_error() -> None:
    with pytest.raises(TransportError, match="no answer to an ACK check at any baud rate"):
        Rcb4Client(ScriptedLink(board_rate=57600)).detect_baudrate(probe_timeout=PROBE_S)
