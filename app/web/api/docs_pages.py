"""The API's interactive docs, whole from this app, so they work on a network without internet:
Swagger UI at /docs (fastapi-offline serves its script and style) and ReDoc at /redoc. ReDoc's script,
also fastapi-offline's copy, would still fetch one picture from its maker's CDN (the "API docs by Redocly"
logo): that script is served with the app's own icon in its place."""

from __future__ import annotations

import functools
from pathlib import Path

import fastapi_offline
from fastapi import FastAPI
from fastapi.openapi.docs import get_redoc_html
from fastapi.responses import HTMLResponse, Response

REDOC_SCRIPT = Path(fastapi_offline.__file__).parent / "static" / "redoc.standalone.js"
REDOC_CDN_LOGO = "https://cdn.redoc.ly/redoc/logo-mini.svg"
LOCAL_LOGO = "/favicon.svg"  # static/favicon.svg
REDOC_URL = "/redoc"
REDOC_SCRIPT_URL = "/redoc-assets/redoc.standalone.js"  # beside fastapi-offline's mount: a route inside it is never reached


@functools.cache
def redoc_script() -> bytes:
    return REDOC_SCRIPT.read_text(encoding="utf-8").replace(REDOC_CDN_LOGO, LOCAL_LOGO).encode("utf-8")


def install_redoc(app: FastAPI) -> None:
    """ReDoc at /redoc over the app's OpenAPI document, its script from REDOC_SCRIPT_URL."""

    @app.get(REDOC_SCRIPT_URL, include_in_schema=False)
    def script() -> Response:
        return Response(redoc_script(), media_type="application/javascript")

    @app.get(REDOC_URL, include_in_schema=False)
    def page() -> HTMLResponse:
        return get_redoc_html(openapi_url=app.openapi_url, title=f"{app.title} - ReDoc", redoc_js_url=REDOC_SCRIPT_URL,
                              redoc_favicon_url=LOCAL_LOGO, with_google_fonts=False)
