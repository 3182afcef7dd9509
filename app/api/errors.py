"""Every bad request gets a 4xx with a message saying what was wrong, never a 500 (docs/reference/api.md)."""

from __future__ import annotations

from typing import Any

from fastapi import FastAPI, HTTPException, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.access import Forbidden
from app.runs import RunStateError
from app.store import NotFound, StoreError
from app.validation import describe_problems, dotted, problem_message
from fuzzy.parser import RuleSyntaxError

MAX_BODY_BYTES = 1_000_000


def error_response(status: int, detail: str, errors: list[dict[str, Any]] | None = None) -> JSONResponse:
    return JSONResponse({"detail": detail, "errors": errors or []}, status_code=status)


def _where(location: tuple[Any, ...]) -> str:
    return dotted(tuple(part for part in location if part != "body")) or "body"


async def _invalid_request(_: Request, exc: RequestValidationError) -> JSONResponse:
    problems = list(exc.errors())
    errors = [{"location": _where(tuple(e.get("loc", ()))), "message": problem_message(e), "type": e.get("type", "")}
              for e in problems]
    if any(e["type"] == "json_invalid" for e in errors):
        return error_response(400, "malformed JSON: " + "; ".join(e["message"] for e in errors), errors)
    return error_response(422, describe_problems(problems, where=_where), errors)


async def _rule_syntax(_: Request, exc: RuleSyntaxError) -> JSONResponse:
    errors = [{"line": e.line, "column": e.column, "message": e.message} for e in exc.errors]
    return error_response(422, f"invalid rule text: {exc}", errors)


async def _not_found(_: Request, exc: NotFound) -> JSONResponse:
    return error_response(404, str(exc))


async def _conflict(_: Request, exc: RunStateError) -> JSONResponse:
    return error_response(409, str(exc))


async def _forbidden(_: Request, exc: Forbidden) -> JSONResponse:
    return error_response(403, str(exc))


async def _refused(_: Request, exc: StoreError) -> JSONResponse:
    return error_response(422, str(exc))


def install_error_handlers(app: FastAPI) -> None:
    app.add_exception_handler(RequestValidationError, _invalid_request)
    app.add_exception_handler(RuleSyntaxError, _rule_syntax)
    app.add_exception_handler(NotFound, _not_found)
    app.add_exception_handler(RunStateError, _conflict)
    app.add_exception_handler(StoreError, _refused)
    app.add_exception_handler(Forbidden, _forbidden)  # before StoreError and RunStateError: its own class's


class BodySizeLimit:
    """413 for a body over `limit` bytes, declared (Content-Length) or streamed (chunked)."""

    def __init__(self, app: ASGIApp, limit: int = MAX_BODY_BYTES):
        self.app = app
        self.limit = limit

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        declared = dict(scope.get("headers", ())).get(b"content-length", b"")
        if declared.isdigit() and int(declared) > self.limit:
            await error_response(413, f"request body larger than {self.limit} bytes")(scope, receive, send)
            return
        received = 0

        async def counted_receive() -> Message:
            nonlocal received
            message = await receive()
            if message["type"] == "http.request":
                received += len(message.get("body", b""))
                if received > self.limit:
                    # An HTTPException: FastAPI's body reader passes it through as it is.
                    raise HTTPException(413, f"request body larger than {self.limit} bytes")
            return message

        await self.app(scope, counted_receive, send)
