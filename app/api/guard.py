"""Only this app's own pages (and scripts that say who they are) can change its state (docs/design.md,
"Security"); no other site can frame its pages.

Every request: its Host header must name the address served (a DNS-rebinding page under another name is
refused, 400). A state-changing request (POST, PUT, PATCH, DELETE) must come from the app's own origin
(a foreign Origin, or Sec-Fetch-Site cross-site / same-site, is refused, 403) and must be one a plain
HTML form cannot send: JSON (Content-Type application/json), the header X-Soccer-Lab, or a same-origin
page's request (Sec-Fetch-Site same-origin: the browser sets it, no page can) (else 415). Every response
forbids framing by any page (X-Frame-Options DENY, CSP frame-ancestors 'none') and content sniffing.
"""

from __future__ import annotations

from starlette.types import ASGIApp, Message, Receive, Scope, Send

from app.api.errors import error_response
from app.origins import SiteAddresses

STATE_CHANGING = frozenset({"POST", "PUT", "PATCH", "DELETE"})
CLIENT_HEADER = "x-soccer-lab"  # what a script of the user's may send instead of JSON (any value)
SECURITY_HEADERS = [
    (b"x-frame-options", b"DENY"),
    (b"content-security-policy", b"frame-ancestors 'none'"),
    (b"x-content-type-options", b"nosniff"),
]


class RequestGuard:
    """ASGI middleware; `site` None checks no Host (an app embedded in tests), the rest always."""

    def __init__(self, app: ASGIApp, site: SiteAddresses | None = None):
        self.app = app
        self.site = site

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        headers = {name.decode("latin-1"): value.decode("latin-1") for name, value in scope.get("headers", ())}
        refusal = self._refusal(scope, headers)
        if refusal is not None:
            status, detail = refusal
            if scope["type"] == "websocket":
                await send({"type": "websocket.close", "code": 1008, "reason": detail[:120]})
            else:
                await error_response(status, detail)(scope, receive, self._secured(send))
            return
        await self.app(scope, receive, self._secured(send) if scope["type"] == "http" else send)

    def _refusal(self, scope: Scope, headers: dict[str, str]) -> tuple[int, str] | None:
        if self.site is not None and (why := self.site.host_refusal(headers.get("host"))):
            return 400, why
        if scope["type"] == "websocket":
            if self.site is not None and (why := self.site.origin_refusal(headers.get("origin"))):
                return 403, why
            return None
        if scope["method"] not in STATE_CHANGING:
            return None
        fetch_site = headers.get("sec-fetch-site", "")
        if fetch_site in ("cross-site", "same-site"):
            return 403, f"a {scope['method']} from another site ({fetch_site}) is refused"
        if "origin" in headers and self.site is not None and (why := self.site.origin_refusal(headers["origin"])):
            return 403, why
        media_type = headers.get("content-type", "").split(";")[0].strip().lower()
        if media_type != "application/json" and CLIENT_HEADER not in headers and fetch_site != "same-origin":
            return 415, (f"a {scope['method']} must send Content-Type: application/json or the header "
                         "X-Soccer-Lab (what a form on another site cannot send)")
        return None

    @staticmethod
    def _secured(send: Send) -> Send:
        async def secured(message: Message) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []), *SECURITY_HEADERS]}
            await send(message)

        return secured
