"""Who may talk to ``rcb4hv ui``: Host/Origin checks, the access token, upload size limits.

A pure ASGI middleware (HTTP and websocket alike):

* ``Host`` must name the server (``127.0.0.1``/``localhost``/``[::1]`` or the bind address,
  with its port): a page on another site that resolves its own name to 127.0.0.1 (DNS
  rebinding) is refused.
* ``Origin``, when a browser sends one, must be ``http://`` + such a host: another site's page
  cannot post to the app or open its websocket.
* With a token (``--allow-remote``), every request and websocket must carry it: ``?token=``
  once (the answer sets an HttpOnly cookie the browser sends from then on), the cookie, or an
  ``X-Rcb4hv-Token`` header.
* Request bodies larger than ``max_body`` (uploads) are refused with 413 before they are read.
"""

from __future__ import annotations

import hmac
import http.cookies
import logging
import secrets
import urllib.parse
from collections.abc import Awaitable, Callable, MutableMapping
from dataclasses import dataclass, field
from typing import Any

__all__ = ["COOKIE", "AccessPolicy", "GuardMiddleware", "new_token"]

log = logging.getLogger(__name__)

COOKIE = "rcb4hv_token"
HEADER = b"x-rcb4hv-token"
LOCAL_NAMES = ("127.0.0.1", "localhost", "[::1]")

Scope = MutableMapping[str, Any]
Message = MutableMapping[str, Any]
Receive = Callable[[], Awaitable[Message]]
Send = Callable[[Message], Awaitable[None]]
ASGIApp = Callable[[Scope, Receive, Send], Awaitable[None]]


def new_token() -> str:
    """A random access token (128 bits, URL-safe)."""
    return secrets.token_urlsafe(16)


@dataclass
class AccessPolicy:
    """What the guard accepts. ``port`` is filled in once the server has bound its socket."""

    bind_host: str = "127.0.0.1"
    port: int = 0
    token: str | None = None
    max_body: int = 4 * 1024 * 1024
    extra_hosts: set[str] = field(default_factory=set)

    def hosts(self) -> set[str]:
        names = {*LOCAL_NAMES, self.bind_host, *self.extra_hosts}
        if ":" in self.bind_host and not self.bind_host.startswith("["):
            names.add(f"[{self.bind_host}]")
        return {f"{n}:{self.port}" for n in names} | set(self.extra_hosts)

    def host_ok(self, host: str | None) -> bool:
        return host is not None and host.lower() in self.hosts()

    def origin_ok(self, origin: str | None) -> bool:
        if origin is None:
            return True
        parts = urllib.parse.urlsplit(origin)
        return parts.scheme in ("http", "https") and self.host_ok(parts.netloc)

    def token_ok(self, presented: str | None) -> bool:
        if self.token is None:
            return True
        return presented is not None and hmac.compare_digest(presented, self.token)


def _headers(scope: Scope) -> dict[bytes, bytes]:
    return {k.lower(): v for k, v in scope.get("headers", [])}


def _presented_token(scope: Scope, headers: dict[bytes, bytes]) -> tuple[str | None, bool]:
    """(token, came from the query string)."""
    query = urllib.parse.parse_qs(scope.get("query_string", b"").decode("latin-1"))
    if "token" in query:
        return query["token"][0], True
    if HEADER in headers:
        return headers[HEADER].decode("latin-1"), False
    cookie = http.cookies.SimpleCookie()
    try:
        cookie.load(headers.get(b"cookie", b"").decode("latin-1"))
    except http.cookies.CookieError:
        return None, False
    morsel = cookie.get(COOKIE)
    return (morsel.value if morsel else None), False


class GuardMiddleware:
    """Wrap ``app`` with ``policy`` (see the module docstring)."""

    def __init__(self, app: ASGIApp, policy: AccessPolicy) -> None:
        self.app = app
        self.policy = policy

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        headers = _headers(scope)
        host = headers.get(b"host", b"").decode("latin-1") or None
        origin = headers.get(b"origin", b"").decode("latin-1") or None
        token, from_query = _presented_token(scope, headers)
        why = None
        if not self.policy.host_ok(host):
            why = f"Host {host!r} is not this server"
        elif not self.policy.origin_ok(origin):
            why = f"Origin {origin!r} is not this server"
        elif not self.policy.token_ok(token):
            why = "missing or wrong access token"
        if why is not None:
            log.warning("refused %s %s: %s", scope["type"], scope.get("path"), why)
            await _refuse(scope, send, 403, why)
            return
        if scope["type"] == "http":
            size = headers.get(b"content-length")
            if size is not None and size.isdigit() and int(size) > self.policy.max_body:
                await _refuse(scope, send, 413, f"request body over {self.policy.max_body} bytes")
                return
            if from_query and self.policy.token is not None:
                send = _with_cookie(send, self.policy.token)
            await _http(self.app, scope, receive, send)
            return
        await self.app(scope, receive, send)


async def _http(app: ASGIApp, scope: Scope, receive: Receive, send: Send) -> None:
    """Serve one HTTP request; a browser tab closed while it was served is no error.

    Starlette's ``BaseHTTPMiddleware`` (NiceGUI's middlewares are) raises ``RuntimeError("No
    response returned.")`` when the client went away before the answer, and uvicorn logged it
    as a full "Exception in ASGI application" traceback that looked like a crash."""
    left = False

    async def watched() -> Message:
        nonlocal left
        message = await receive()
        left = left or message["type"] == "http.disconnect"
        return message

    try:
        await app(scope, watched, send)
    except RuntimeError as exc:
        if not left:
            raise
        log.debug(
            "%s %s: the client left before the answer (%s)",
            scope.get("method"),
            scope.get("path"),
            exc,
        )


def _with_cookie(send: Send, token: str) -> Send:
    async def wrapped(message: Message) -> None:
        if message["type"] == "http.response.start":
            value = f"{COOKIE}={token}; Path=/; HttpOnly; SameSite=Strict"
            message["headers"] = [*message.get("headers", []), (b"set-cookie", value.encode())]
        await send(message)

    return wrapped


async def _refuse(scope: Scope, send: Send, status: int, why: str) -> None:
    if scope["type"] == "websocket":
        await send({"type": "websocket.close", "code": 1008, "reason": why[:120]})
        return
    body = f"{status}: {why}\n".encode()
    await send(
        {
            "type": "http.response.start",
            "status": status,
            "headers": [
                (b"content-type", b"text/plain; charset=utf-8"),
                (b"content-length", str(len(body)).encode()),
            ],
        }
    )
    await send({"type": "http.response.body", "body": body})
