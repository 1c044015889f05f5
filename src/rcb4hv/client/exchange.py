"""The client's transaction helpers: prebuilt read frames and the careful reply hunt.

:meth:`Rcb4Client._roundtrip` takes the fast path when the first read brings exactly the
reply frame it expects; anything else (a NAK, a reply in pieces, stray bytes before it, a
damaged reply) goes through :func:`find_reply`, which hunts for the reply among the bytes.
"""

from __future__ import annotations

import logging
import struct
import time
from typing import Final

from rcb4hv.errors import ChecksumError, Rcb4TimeoutError
from rcb4hv.protocol import NEED_DATA, FrameDecoder
from rcb4hv.transport import Transport

__all__ = ["RAM_READS", "find_reply", "ram_read_frame"]

log = logging.getLogger("rcb4hv.client.core")

_RAM_READ: Final = struct.Struct("<BBB3xHBB")
RAM_READS: dict[tuple[int, int], bytes] = {}
"""RAM read frames already built, by (address, size): a control loop reads the same ones."""
RAM_READS_KEPT: Final = 512


def ram_read_frame(address: int, size: int) -> bytes:
    """The frame of ``Move(Com(), Ram(address), size)`` (a RAM read), built in one step and
    remembered in :data:`RAM_READS`; the caller has checked ``address`` and ``size``."""
    frame = _RAM_READ.pack(
        10, 0x00, 0x20, address, size, (10 + 0x20 + (address & 0xFF) + (address >> 8) + size) & 0xFF
    )
    if len(RAM_READS) >= RAM_READS_KEPT:
        RAM_READS.clear()
    RAM_READS[address, size] = frame
    return frame


def find_reply(
    transport: Transport,
    decoder: FrameDecoder,
    chunk: bytes,
    cmd: int,
    expected: int,
    name: str,
    deadline: float,
    timeout: float,
    corrupt_grace: float,
) -> bytes:
    """The reply frame to ``cmd`` among ``chunk`` and the bytes still to come.

    Bytes that cannot start it (a SIZE other than ``expected`` or 4, a CMD other than
    ``cmd``) are discarded and logged; a damaged candidate is remembered and the wait cut to
    ``corrupt_grace`` (a good copy may follow). Raises the ChecksumError at the deadline if
    only damaged replies came, else Rcb4TimeoutError.
    """
    decoder.reset()
    decoder.receive_data(chunk)
    corrupt: ChecksumError | None = None
    while True:
        while True:
            pending = decoder.pending
            skip = 0
            n = len(pending)
            while skip < n and not (
                (pending[skip] == expected or pending[skip] == 4)
                and (skip + 1 >= n or pending[skip + 1] == cmd)
            ):
                skip += 1
            if skip:
                log.warning(
                    "discarded %d stray byte(s) before the reply to %s: %s",
                    skip,
                    name,
                    pending[:skip].hex(" "),
                )
                decoder.reset()
                decoder.receive_data(pending[skip:])
                pending = pending[skip:]
            if not pending:
                need = 4
                break
            try:
                got_frame = decoder.next_frame()
            except ChecksumError as exc:
                log.warning("reply to %s with a bad checksum: %s", name, exc)
                corrupt = ChecksumError(
                    f"reply to {name} has a bad checksum: {exc.frame.hex(' ')}", exc.frame
                )
                deadline = min(deadline, time.monotonic() + corrupt_grace)
                continue
            if got_frame is NEED_DATA:
                need = max(pending[0] - len(pending), 1)
                break
            assert isinstance(got_frame, bytes)
            return got_frame
        chunk = transport.read(need, deadline)
        if not chunk:
            partial = decoder.reset()
            if corrupt is not None:
                raise corrupt
            got = f" (incomplete: {partial.hex(' ')})" if partial else ""
            raise Rcb4TimeoutError(f"no reply to {name} within {timeout:g} s{got}")
        decoder.receive_data(chunk)
