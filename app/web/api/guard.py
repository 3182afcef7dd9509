"""Only this app's own pages (and scripts that say who they are) can change its state (docs/design.md,
"Security"); no other site can frame its pages.

Every request: its Host header must name the address served (a DNS-rebinding page under another name is
refused, 400). A state-changing request (POST, PUT, PATCH, DELETE) must come from the app's own origin
(a foreign Origin, or Sec-Fetch-Site cross-site / same-site, is refused, 403) and must be one a plain
HTML form cannot send: JSON (Content-Type application/json), the header X-Soccer-Lab, or a same-origin
page's request (Sec-Fetch-Site same-origin: the browser sets it, no page can) (else 415). Every response
forbids framing by any page (X-Frame-Options DENY, CSP frame-ancestors 'none') and content sniffing.

In classroom mode (`classroom` given) every request must also come from a browser that joined the class
(app/web/classroom/admission.py: the join code's cookie, compared in constant time, and a student's or the
teacher's); only the join page, its style and icon, and the join requests themselves are open. A page asked
for without them is sent to the join page (303, with the page to come back to), anything else is refused
(401). Every visitor's request rate is bounded (429 with Retry-After), each request weighed by its cost
before it is paid: a game-playing one costs PLAYING_REQUEST_COST, and a body one more per BODY_BYTES_PER_REQUEST bytes (a 1 MB body a
visitor's whole burst). A join or teacher sign-in costs one, and a wrong code or token WRONG_GUESS_COST
more once known (the route charges it, RATE_KEY_STATE names whom): the code cannot be guessed quickly, yet
a pupil who mistyped it, or a class joining from one address, is not made to wait. A visitor is their class cookie's, else the address that connected: forwarded-for
headers count only from the proxy `serve --trusted-proxy` names (uvicorn's setting, app/web/server.py). The admitted visitor is left in the request's state for the routes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING
from urllib.parse import quote

from starlette.responses import RedirectResponse, Response
from starlette.types import ASGIApp, Message, Receive, Scope, Send

from soccer_lab.app.web.api.errors import MAX_BODY_BYTES, error_response
from soccer_lab.app.web.classroom.admission import WRONG_GUESS_COST
from soccer_lab.app.web.origins import SiteAddresses

if TYPE_CHECKING:
    from soccer_lab.app.web.classroom.admission import Classroom

STATE_CHANGING = frozenset({"POST", "PUT", "PATCH", "DELETE"})
CLIENT_HEADER = "x-soccer-lab"  # what a script of the user's may send instead of JSON (any value)
SECURITY_HEADERS = [
    (b"x-frame-options", b"DENY"),
    (b"content-security-policy", b"frame-ancestors 'none'"),
    (b"x-content-type-options", b"nosniff"),
    (b"referrer-policy", b"no-referrer"),
]
JOIN_PAGE = "/join.html"
# What a browser that has not joined may fetch: the join page and what it shows, and the join requests
OPEN_TO_ALL = frozenset({("GET", JOIN_PAGE), ("GET", "/style.css"), ("GET", "/favicon.svg"),
                         ("POST", "/api/class/join"), ("POST", "/api/class/teacher")})
RATE_KEY_STATE = "rate_key"  # where the guard leaves the visitor's rate key, for a charge after the fact
# Requests that play games (seconds of CPU each) cost this many requests of a visitor's rate
PLAYING_REQUESTS = frozenset({"/api/rules/usage", "/api/rules/simplify"})
PLAYING_REQUEST_COST = 30
BODY_BYTES_PER_REQUEST = 4_000


def request_cost(path: str, headers: dict[str, str], most: float) -> float:
    """What a request costs of its visitor's rate, known before its body is read: its kind, and its body's
    declared size (a body without Content-Length, streamed, is charged as the largest); at most `most`."""
    kind = PLAYING_REQUEST_COST if path in PLAYING_REQUESTS else 1
    declared = headers.get("content-length", "")
    size = int(declared) if declared.isdigit() else MAX_BODY_BYTES if "transfer-encoding" in headers else 0
    return min(most, kind + size // BODY_BYTES_PER_REQUEST)


class RequestGuard:
    """ASGI middleware; `site` None checks no Host (an app embedded in tests), the rest always."""

    def __init__(self, app: ASGIApp, site: SiteAddresses | None = None, classroom: Classroom | None = None):
        self.app = app
        self.site = site
        self.classroom = classroom

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] not in ("http", "websocket"):
            await self.app(scope, receive, send)
            return
        headers = {name.decode("latin-1"): value.decode("latin-1") for name, value in scope.get("headers", ())}
        refusal = self._refusal(scope, headers)
        if refusal is None and self.classroom is not None:
            response = self._class_refusal(scope, headers)
            if response is not None:
                if scope["type"] == "websocket":
                    await send({"type": "websocket.close", "code": 1008, "reason": "join the class first"})
                else:
                    await response(scope, receive, self._secured(send))
                return
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

    def _class_refusal(self, scope: Scope, headers: dict[str, str]) -> Response | None:
        classroom = self.classroom
        path, method = scope["path"], scope.get("method", "GET")
        visitor = classroom.admit(headers.get("cookie"))
        if visitor is None:
            key = f"address:{(scope.get('client') or ('?',))[0]}"
        else:
            key = "teacher" if visitor.teacher else f"student:{visitor.student_id}"
        wait = classroom.rate.take(key, request_cost(path, headers, classroom.rate.burst))
        if wait is not None:
            seconds = max(1, round(wait + 0.5))
            refusal = error_response(429, f"too many requests: at most {classroom.rate.per_second:g} a second each (a "
                                          f"game-playing request counts {PLAYING_REQUEST_COST}, a wrong join code "
                                          f"{WRONG_GUESS_COST}, a body one more per {BODY_BYTES_PER_REQUEST:,} bytes); "
                                          f"try again in {seconds} s")
            refusal.headers["Retry-After"] = str(seconds)
            return refusal
        scope.setdefault("state", {})[RATE_KEY_STATE] = key
        if (method, path) in OPEN_TO_ALL:
            return None
        if visitor is None:
            if scope["type"] == "http" and method == "GET" and not path.startswith("/api/"):
                query = scope.get("query_string", b"").decode("latin-1")
                back = path + (f"?{query}" if query else "")  # e.g. a pitch link: opened once joined
                return RedirectResponse(f"{JOIN_PAGE}?next={quote(back, safe='')}", status_code=303)
            return error_response(401, f"join the class first: open {classroom.address}{JOIN_PAGE} and enter the "
                                       "class's join code")
        scope.setdefault("state", {})["visitor"] = visitor
        return None

    @staticmethod
    def _secured(send: Send) -> Send:
        async def secured(message: Message) -> None:
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []), *SECURITY_HEADERS]}
            await send(message)

        return secured
