"""The trials of :mod:`rcb4hv.project.robust` as Ray tasks (the ``[scale]`` extra): any
picklable function over picklable jobs, so this module imports nothing of the trials."""

from __future__ import annotations

import socket
from collections.abc import Callable, Sequence
from typing import Any, TypeVar

from rcb4hv.errors import ScaleError

__all__ = ["PROBE_TIMEOUT_S", "probe", "require_ray", "run_ray"]

T = TypeVar("T")
R = TypeVar("R")


def require_ray() -> Any:
    """The ``ray`` module, or :class:`ScaleError` saying which extra installs it."""
    try:
        import ray
    except ImportError as exc:
        raise ScaleError(
            "Ray is not installed: pip install 'rcb4hv[scale]' (or pip install ray)"
        ) from exc
    return ray


PROBE_TIMEOUT_S = 5.0
"""Seconds a cluster address has to accept a TCP connection (Ray itself waits minutes)."""


def probe(address: str | None) -> None:
    """:class:`ScaleError` unless ``address`` (``host:port`` or ``ray://host:port``; None,
    ``auto`` and ``local`` are not probed) accepts a TCP connection."""
    if address in (None, "", "auto", "local"):
        return
    assert address is not None
    hostport = address.split("://", 1)[-1].rstrip("/")
    host, _, port = hostport.rpartition(":")
    if not host or not port.isdigit():
        raise ScaleError(f"Ray address {address!r}: expected HOST:PORT or ray://HOST:PORT")
    try:
        socket.create_connection((host, int(port)), timeout=PROBE_TIMEOUT_S).close()
    except OSError as exc:
        raise ScaleError(f"Ray at {address!r} answers nothing: {exc}") from exc


def run_ray(
    fn: Callable[[T], R],
    jobs: Sequence[T],
    address: str | None,
    progress: Callable[[int], object] | None,
) -> list[R]:
    """Run ``fn`` on each of ``jobs`` as Ray tasks on the cluster at ``address`` (None: start
    a local Ray, or join the one already started in this process); the results in the jobs'
    order. A KeyboardInterrupt (Ctrl-C, or raised by ``progress``) cancels the tasks not yet
    done and is re-raised."""
    ray = require_ray()
    if not ray.is_initialized():
        probe(address)
        try:
            ray.init(address=address, include_dashboard=False, log_to_driver=False)
        except (ConnectionError, RuntimeError, ValueError) as exc:
            raise ScaleError(f"Ray at {address!r} answers nothing: {exc}") from exc
    task = ray.remote(fn)
    refs = [task.remote(j) for j in jobs]
    order = {r: i for i, r in enumerate(refs)}
    out: list[R | None] = [None] * len(refs)
    pending = list(refs)
    try:
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            for r in done:
                out[order[r]] = ray.get(r)
                if progress is not None:
                    progress(1)
    except KeyboardInterrupt:  # Ctrl-C: the tasks not yet done are not left to run
        for r in pending:
            ray.cancel(r)
        raise
    return [r for r in out if r is not None]
