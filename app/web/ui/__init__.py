"""The viser UI of `soccer-lab serve`: one Session per browser tab, each with its own pitch,
game, editor and panels; evolution runs in the RunManager's threads and sessions listen to it.

    handle = start_ui(store, runs, host="127.0.0.1", port=8080)
    print(handle.url)
    ...
    handle.stop()

viser (1.1) checks no Origin: any web page could open the UI's websocket and drive it (delete a saved
rulebase...). `admit_only` hooks into viser's websocket server, whose connect callbacks run before it sends
anything and before any per-client GUI is built: a handshake whose Host is not the address served or whose
Origin is not the app's own page is closed at once (1008). In classroom mode the handshake must also carry
the class's cookies (app/web/classroom/admission.py), and a student has at most MAX_TABS_PER_STUDENT tabs. The
hook keeps what the session needs from the handshake (`Handshake`: who, the page's origin, a pitch link's
token). It reads viser's `_live_connections`; if an upgrade changes that, the UI refuses to start
(tests/app/test_security.py guards it). docs/design.md, "Security", says why this hook and not a proxy.
"""

from __future__ import annotations

import contextlib
import io
import logging
import threading
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable
from urllib.parse import parse_qs, urlsplit

import viser

from soccer_lab.app.web.access import LOCAL, Visitor
from soccer_lab.app.web.origins import SiteAddresses
from soccer_lab.app.web.ui.context import UiContext
from soccer_lab.app.web.ui.layout import Layout
from soccer_lab.app.web.ui.pitch import PitchGeometry, draw_pitch
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig

if TYPE_CHECKING:
    from soccer_lab.app.web.classroom.admission import Classroom
    from soccer_lab.app.web.classroom.tournament import Tournament
    from soccer_lab.app.runs.manager import RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui.session import Session

log = logging.getLogger(__name__)
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8080
TITLE = "soccer-lab"


# viser warns when something is queued for a connection that has closed. A closing tab's socket is
# done a moment before viser calls our disconnect callback, which stops the tab's session at once; a
# frame sent in that moment trips the warning, with nothing to tell (tests/app/test_ui_browser.py
# checks that a closed tab's session stops).
CLOSED_TAB_WARNING = r"Queued a \w+ on a closed connection"


class PortBusyError(OSError):
    pass


POLICY_VIOLATION = 1008  # the websocket close code for a refused handshake
MAX_TABS_PER_STUDENT = 3  # each tab is a session playing its own game: a student cannot open fifty


@dataclass(frozen=True)
class Handshake:
    """What an admitted websocket's handshake said: who it is, the page's origin (links are made to it), and
    the token of the pitch link the page was opened with."""

    visitor: Visitor
    origin: str | None
    link: str | None


def _viser_server_without_banner(host: str, port: int) -> viser.ViserServer:
    """viser's server, without the box it always prints (verbose=False does not stop it): the box names viser's
    bare address, whose page is refused by the origin check and stays on "Connecting...", so it must not be the
    first address a teacher reads (serve prints the UI's own)."""
    with contextlib.redirect_stdout(io.StringIO()):
        return viser.ViserServer(host=host, port=port, label=TITLE, verbose=False)


def admit_only(server: viser.ViserServer, site: SiteAddresses, classroom: Classroom | None = None,
               tabs_of: Callable[[Visitor], int] = lambda visitor: 0) -> dict[int, Handshake]:
    """Close at once every websocket whose handshake is not from `site`'s own pages, or in classroom mode not
    from a browser of the class (see the module's doc). The admitted ones' handshakes, by client id (the
    caller pops each)."""
    websockets_server = server._websock_server
    live = getattr(websockets_server, "_live_connections", None)
    if not isinstance(live, dict):
        server.stop()
        raise RuntimeError("this viser version keeps no _live_connections: the UI cannot check origins "
                           f"(viser {viser.__version__}; see app/web/ui/__init__.py)")

    from soccer_lab.app.web.pitch_link import LINK_PARAMETER  # here: soccer_lab.app.web.pitch_link reads the UI's style (soccer_lab.app.web.ui)

    told: set[str] = set()
    handshakes: dict[int, Handshake] = {}

    def read(websocket: Any) -> Handshake | str:
        try:
            headers = websocket.request.headers
            hosts, origins, cookies = headers.get_all("Host"), headers.get_all("Origin"), headers.get_all("Cookie")
            query = parse_qs(urlsplit(websocket.request.path).query)
        except Exception:  # fail closed: a handshake this code cannot read is refused
            return "the handshake cannot be read"
        if len(hosts) != 1 or len(origins) > 1 or len(cookies) > 1:
            return "a handshake with several Host, Origin or Cookie headers is refused"
        origin = origins[0] if origins else None
        refusal = site.host_refusal(hosts[0]) or site.origin_refusal(origin)
        if refusal is not None:
            return refusal
        visitor = LOCAL if classroom is None else classroom.admit(cookies[0] if cookies else None)
        if visitor is None:
            return "join the class first (the join page of the class's address)"
        if visitor.is_student and tabs_of(visitor) >= MAX_TABS_PER_STUDENT:
            return f"{MAX_TABS_PER_STUDENT} tabs of yours are open: close one"
        links = query.get(LINK_PARAMETER, [])
        return Handshake(visitor, origin, links[0] if len(links) == 1 else None)

    async def admit(connection: Any) -> None:
        websocket = live.get(connection.client_id)
        handshake = read(websocket)
        if isinstance(handshake, Handshake):
            handshakes[connection.client_id] = handshake
            return
        refusal = handshake
        if refusal not in told:  # a refused page's client retries every few seconds: say it once
            told.add(refusal)
            log.warning("UI websocket refused: %s", refusal)
        if websocket is not None:
            await websocket.close(POLICY_VIOLATION, refusal[:120])

    websockets_server.on_client_connect(admit)
    websockets_server.on_client_disconnect(lambda connection: handshakes.pop(connection.client_id, None))
    return handshakes


@dataclass
class UiHandle:
    server: viser.ViserServer
    context: UiContext
    sessions: dict[int, "Session"] = field(default_factory=dict)
    lock: threading.Lock = field(default_factory=threading.Lock)

    @property
    def url(self) -> str:
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def stop(self) -> None:
        with self.lock:
            sessions = list(self.sessions.values())
            self.sessions.clear()
        for session in sessions:
            session.close()
        for session in sessions:
            session.join(timeout=5.0)  # no frame may still be on its way when the server stops
        with contextlib.redirect_stdout(io.StringIO()):  # viser's "(viser) Server stopped": serve says "stopped"
            self.server.stop()


def start_ui(
    store: Store,
    runs: RunManager,
    host: str = DEFAULT_HOST,
    port: int = DEFAULT_PORT,
    *,
    game: GameConfig | None = None,
    vocabulary: Vocabulary = Vocabulary.default(),
    api_url: str | None = None,
    viewer_problem: str | None = None,
    page_port: int | None = None,
    site: SiteAddresses | None = None,
    classroom: Classroom | None = None,
    tournament: Tournament | None = None,
) -> UiHandle:
    """Start the viser server on host:port (PortBusyError if the port is taken: viser would silently
    move to the next one) and give every connecting browser tab its own session. `api_url`: where the
    JSON API answers, for links to the files it serves. Only pages served from host:`page_port` (default:
    viser's own, `port`) may open the UI's websocket; `soccer-lab serve` serves the UI's page from the API's
    address, with headers forbidding framing (app/web/api/ui_page.py). `site`: the names served (default: `host`'s).
    `classroom` and `tournament` (classroom mode): only the class's browsers are admitted, each session is its
    visitor's (app/web/access.py), and a Class tab plays the tournament."""
    from soccer_lab.app.web.ui.player_qualities import PlayerQualities
    from soccer_lab.app.web.ui.session import Session

    warnings.filterwarnings("ignore", message=CLOSED_TAB_WARNING, category=UserWarning)
    context = UiContext(store, runs, vocabulary, game or GameConfig(), api_url=api_url, viewer_problem=viewer_problem,
                        player_qualities=PlayerQualities(vocabulary))
    server = _viser_server_without_banner(host, port)
    if server.get_port() != port:
        server.stop()
        raise PortBusyError(f"port {port} on {host} is busy (choose another with --ui-port)")
    site = site or SiteAddresses.of(host, {port}, {page_port or port})
    handle = UiHandle(server, context)

    def tabs_of(visitor: Visitor) -> int:
        with handle.lock:
            open_tabs = [session.visitor for session in handle.sessions.values()]
        waiting = [handshake.visitor for handshake in handshakes.values()]
        return sum(other.student_id == visitor.student_id for other in open_tabs + waiting)

    handshakes = admit_only(server, SiteAddresses(site.names, frozenset({port}), site.origin_ports), classroom,
                            tabs_of)
    draw_pitch(server.scene, PitchGeometry.from_world(context.game.world), Session.first_game(context).frame())
    layout = Layout(server)

    def close_session(client_id: int) -> None:
        with handle.lock:
            session = handle.sessions.pop(client_id, None)
            context.frames.tabs = len(handle.sessions)
        if session is not None:
            session.close()

    @server.on_client_connect
    def _(client: viser.ClientHandle) -> None:
        handshake = handshakes.pop(client.client_id, None)
        if handshake is None:  # never admitted: fail closed (no session; outside classroom mode, the one user)
            if classroom is not None:
                return
            handshake = Handshake(LOCAL, None, None)
        session = Session(client, context, layout, connected=lambda: client.client_id in server.get_clients(),
                          visitor=handshake.visitor, origin=handshake.origin, link=handshake.link,
                          tournament=tournament)
        with handle.lock:
            handle.sessions[client.client_id] = session
            context.frames.tabs = len(handle.sessions)
        if client.client_id not in server.get_clients():  # the tab closed while its session was built
            close_session(client.client_id)

    @server.on_client_disconnect
    async def _(client: viser.ClientHandle) -> None:
        # In viser's event loop, right as the connection closes: the session stops drawing before it
        # can queue another frame for a tab that is gone (a sync callback would wait for a thread).
        close_session(client.client_id)

    return handle
