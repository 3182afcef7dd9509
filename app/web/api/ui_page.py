"""The UI's page served from the app's address (`/ui/`), so that the page the UI's websocket admits is
one that no other site can frame (app/web/api/guard.py adds the headers; app/web/ui/__init__.py admits only this
page's origin). The page is viser's own client, from the installed viser package; it opens the websocket
named by its `websocket` query parameter: viser's port, where the sessions live, on the host name the
browser used for the page (so that the class's cookies, which belong to that name, go with the handshake).

A link to a pitch (`/ui/?pitch=TOKEN`, app/web/pitch_link.py) is passed on in the websocket's own query, which
the handshake hook reads: the session starts from it. A link that cannot be read answers one line, not
a broken page."""

from __future__ import annotations

import html
from pathlib import Path
from urllib.parse import quote, urlsplit

import viser
from fastapi import APIRouter, Request
from fastapi.responses import HTMLResponse, RedirectResponse, Response

from soccer_lab.app.web.pitch_link import LINK_PARAMETER, LinkError, decode_link
from soccer_lab.app.web.ui.projector import PROJECTOR_KEY_SCRIPT

UI_PATH = "/ui/"
CLIENT_PAGE = Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"
WEBSOCKET_PARAMETER = "websocket"  # viser's client connects where this query parameter says
SERVER_CHECK_MS = 3000
# viser's client only greys out when its server goes: this line says so. The UI's page and its websocket come
# from the same serve process, so the page asks the API whether it still answers (the websocket itself may
# live in viser's worker, out of the page's reach); any answer, even a refusal, means it runs.
STOPPED_NOTICE = f"""<div id="server-stopped" role="alert" hidden style="position:fixed; top:0; left:0; right:0;
 z-index:2147483647; padding:8px 12px; background:#c62828; color:#fff; font:600 16px system-ui, sans-serif;
 text-align:center">The soccer-lab server has stopped: start it again (soccer-lab serve), then reload this page.</div>
<script>
(() => {{
  const notice = document.getElementById("server-stopped");
  async function check() {{
    try {{ await fetch("/api/server", {{cache: "no-store"}}); notice.hidden = true; }}
    catch (error) {{ notice.hidden = false; }}
  }}
  setInterval(check, {SERVER_CHECK_MS});
}})();
</script>
</body>""".encode()


def ui_router(websocket_url: str) -> APIRouter:
    """GET /ui/: viser's client page, told to connect to `websocket_url`'s port (e.g. ws://127.0.0.1:8080) on
    the host name the page was opened under."""
    router = APIRouter(include_in_schema=False)
    page = with_projector_key(CLIENT_PAGE.read_bytes()).replace(b"</body>", STOPPED_NOTICE, 1)
    ui_port = urlsplit(websocket_url).port

    @router.get("/ui", include_in_schema=False)
    @router.get(UI_PATH, include_in_schema=False)
    def ui(request: Request) -> Response:
        link = request.query_params.get(LINK_PARAMETER)
        if link is not None:
            try:
                decode_link(link)
            except LinkError as exc:
                return bad_link_page(str(exc))
        host = request.url.hostname or "127.0.0.1"
        websocket = f"ws://{f'[{host}]' if ':' in host else host}:{ui_port}"
        if link is not None:
            websocket += f"/?{LINK_PARAMETER}={link}"
        if request.url.path != UI_PATH or request.query_params.get(WEBSOCKET_PARAMETER) != websocket:
            query = f"{LINK_PARAMETER}={link}&" if link is not None else ""
            return RedirectResponse(f"{UI_PATH}?{query}{WEBSOCKET_PARAMETER}={quote(websocket, safe=':/')}", 307)
        return HTMLResponse(page, headers={"Cache-Control": "no-cache"})

    return router


def with_projector_key(page: bytes) -> bytes:
    """viser's page with the projector view's key (app/web/ui/projector.py)."""
    script = f"<script>{PROJECTOR_KEY_SCRIPT}</script></body>".encode()
    return page.replace(b"</body>", script, 1)


def bad_link_page(reason: str) -> HTMLResponse:
    """One line saying why, and the way to the app: never a broken page."""
    body = (f'<!doctype html><html lang="en"><head><meta charset="utf-8"><title>soccer-lab: link not opened</title>'
            f'<link rel="stylesheet" href="/style.css"></head><body><main><p class="link-refused">'
            f'This link could not be opened: {html.escape(reason)}. <a href="{UI_PATH}">Open the app</a>.</p>'
            f"</main></body></html>")
    return HTMLResponse(body, status_code=400)
