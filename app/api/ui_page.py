"""The UI's page served from the app's address (`/ui/`), so that the page the UI's websocket admits is
one that no other site can frame (app/api/guard.py adds the headers; app/ui/__init__.py admits only this
page's origin). The page is viser's own client, from the installed viser package; it opens the websocket
named by its `websocket` query parameter: viser's port, where the sessions live."""

from __future__ import annotations

from pathlib import Path
from urllib.parse import quote

import viser
from fastapi import APIRouter, Request
from fastapi.responses import HTMLResponse, RedirectResponse, Response

UI_PATH = "/ui/"
CLIENT_PAGE = Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"
WEBSOCKET_PARAMETER = "websocket"  # viser's client connects where this query parameter says


def ui_router(websocket_url: str) -> APIRouter:
    """GET /ui/: viser's client page, told to connect to `websocket_url` (e.g. ws://127.0.0.1:8080)."""
    router = APIRouter(include_in_schema=False)
    page = CLIENT_PAGE.read_bytes()

    @router.get("/ui", include_in_schema=False)
    @router.get(UI_PATH, include_in_schema=False)
    def ui(request: Request) -> Response:
        if request.url.path != UI_PATH or request.query_params.get(WEBSOCKET_PARAMETER) != websocket_url:
            return RedirectResponse(f"{UI_PATH}?{WEBSOCKET_PARAMETER}={quote(websocket_url, safe=':/')}", 307)
        return HTMLResponse(page, headers={"Cache-Control": "no-cache"})

    return router
