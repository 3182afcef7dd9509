"""Every bad request gets a 4xx with a message saying what was wrong, never a 500 (docs/reference/api.md).
An error's body is bounded (at most MAX_ERROR_BYTES): the first problems and their count, never the input
echoed whole."""

from __future__ import annotations

import json
from typing import Any

import anyio
from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from soccer_lab.app.web.access import Forbidden
from soccer_lab.app.web.api.body_shape import BODY_SHAPE, BodyShape, ShapeRefused
from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.store import NotFound, StoreError
from soccer_lab.app.web.validation import describe_problems, dotted, problem_message
from soccer_lab.fuzzy.parser import RuleSyntaxError

MAX_BODY_BYTES = 1_000_000
MAX_ERROR_BYTES = 16_000  # an error's whole body
MAX_ERRORS = 20  # problems listed; `error_count` says how many there were
MAX_DETAIL_CHARACTERS = 1_000
BODY_METHODS = frozenset({"POST", "PUT", "PATCH", "DELETE"})


def error_response(status: int, detail: str, errors: list[dict[str, Any]] | None = None,
                   error_count: int | None = None) -> JSONResponse:
    """{"detail", "errors", "error_count"}: the first MAX_ERRORS problems, cut to fit MAX_ERROR_BYTES."""
    errors = errors or []
    count = len(errors) if error_count is None else error_count
    body = {"detail": _cut(detail, MAX_DETAIL_CHARACTERS), "errors": errors[:MAX_ERRORS], "error_count": count}
    while len(json.dumps(body, ensure_ascii=False).encode()) > MAX_ERROR_BYTES and body["errors"]:
        body["errors"] = body["errors"][:-1]  # only a problem's own long text gets here
    return JSONResponse(body, status_code=status)


def _cut(text: str, characters: int) -> str:
    return text if len(text) <= characters else f"{text[:characters]}... ({len(text) - characters:,} more characters)"


def _where(location: tuple[Any, ...]) -> str:
    return dotted(tuple(part for part in location if part != "body")) or "body"


async def _invalid_request(_: Request, exc: RequestValidationError) -> JSONResponse:
    problems = list(exc.errors())
    shown = problems[:MAX_ERRORS]
    errors = [{"location": _cut(_where(tuple(e.get("loc", ()))), 200), "message": _cut(problem_message(e), 300),
               "type": e.get("type", "")} for e in shown]
    more = f"; and {len(problems) - len(shown):,} more" if len(problems) > len(shown) else ""
    if any(e["type"] == "json_invalid" for e in errors):
        return error_response(400, "malformed JSON: " + "; ".join(e["message"] for e in errors), errors,
                              len(problems))
    return error_response(422, describe_problems(shown, where=_where) + more, errors, len(problems))


async def _rule_syntax(_: Request, exc: RuleSyntaxError) -> JSONResponse:
    shown = exc.errors[:MAX_ERRORS]
    errors = [{"line": e.line, "column": e.column, "message": _cut(e.message, 300)} for e in shown]
    more = f" (and {len(exc.errors) - 1:,} more errors)" if len(exc.errors) > 1 else ""
    return error_response(422, f"invalid rule text: {_cut(str(exc), 300)}{more}", errors, len(exc.errors))


async def _http(_: Request, exc: StarletteHTTPException) -> JSONResponse:
    """Starlette's own refusals (an unknown path, a method a route does not take) in the usual shape."""
    response = error_response(exc.status_code, str(exc.detail))
    response.headers.update(exc.headers or {})  # 405's Allow
    return response


async def _not_found(_: Request, exc: NotFound) -> JSONResponse:
    return error_response(404, str(exc))


async def _conflict(_: Request, exc: RunStateError) -> JSONResponse:
    return error_response(409, str(exc))


async def _forbidden(_: Request, exc: Forbidden) -> JSONResponse:
    return error_response(403, str(exc))


async def _refused(_: Request, exc: StoreError) -> JSONResponse:
    return error_response(422, str(exc))


def install_error_handlers(app: FastAPI) -> None:
    app.add_exception_handler(StarletteHTTPException, _http)
    app.add_exception_handler(RequestValidationError, _invalid_request)
    app.add_exception_handler(RuleSyntaxError, _rule_syntax)
    app.add_exception_handler(NotFound, _not_found)
    app.add_exception_handler(RunStateError, _conflict)
    app.add_exception_handler(StoreError, _refused)
    app.add_exception_handler(Forbidden, _forbidden)  # before StoreError and RunStateError: its own class's


class BodyGuard:
    """A request body bounded before it is paid for: 413 over `limit` bytes (declared by Content-Length, or
    streamed), then a JSON body's shape checked off the event loop (app/web/api/body_shape.py): 400 when it is
    not UTF-8 JSON, 413 when it is too large in shape. The body read is handed on whole to the app."""

    def __init__(self, app: ASGIApp, limit: int = MAX_BODY_BYTES, shape: BodyShape = BODY_SHAPE):
        self.app = app
        self.limit = limit
        self.shape = shape
        # One check at a time: a parse holds the GIL throughout, so ten at once would take turns with the
        # event loop ten deep; one at a time, every other request waits at most one parse (~0.1 s for 1 MB)
        self._checking = anyio.CapacityLimiter(1)

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http" or scope["method"] not in BODY_METHODS:
            await self.app(scope, receive, send)
            return
        headers = dict(scope.get("headers", ()))
        declared = headers.get(b"content-length", b"")
        if declared.isdigit() and int(declared) > self.limit:
            await self._too_large()(scope, receive, send)
            return
        body, disconnected = await self._read(receive)
        if disconnected:  # no one to answer
            return
        if body is None:
            await self._too_large()(scope, receive, send)
            return
        if body and _is_json(headers.get(b"content-type", b"")):
            try:  # a thread: parsing a large body must not hold every other request
                await anyio.to_thread.run_sync(self.shape.check, body, limiter=self._checking)
            except ShapeRefused as refused:
                await error_response(refused.status, refused.detail)(scope, receive, send)
                return
        await self.app(scope, _replay(body, receive), send)

    async def _read(self, receive: Receive) -> tuple[bytes | None, bool]:
        """(the body, whether the client left); None when it passes the limit."""
        chunks, size = [], 0
        while True:
            message = await receive()
            if message["type"] == "http.disconnect":
                return b"".join(chunks), True
            chunk = message.get("body", b"")
            size += len(chunk)
            if size > self.limit:
                return None, False
            chunks.append(chunk)
            if not message.get("more_body", False):
                return b"".join(chunks), False

    def _too_large(self) -> JSONResponse:
        return error_response(413, f"request body larger than {self.limit} bytes")


def _is_json(content_type: bytes) -> bool:
    """Whether FastAPI reads this body as JSON: no Content-Type, or application/json or one of its kind."""
    media = content_type.split(b";")[0].strip().lower()
    return not media or media == b"application/json" or (media.startswith(b"application/") and media.endswith(b"+json"))


def _replay(body: bytes, receive: Receive) -> Receive:
    """The app's receive: the body read, then the client's own messages (its disconnect)."""
    sent = False

    async def replayed() -> Message:
        nonlocal sent
        if not sent:
            sent = True
            return {"type": "http.request", "body": body, "more_body": False}
        return await receive()

    return replayed
