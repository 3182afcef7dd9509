"""The viser UI of `soccer-lab serve` (spec 7): one Session per browser tab, each with its own pitch,
game, editor and panels; evolution runs in the RunManager's threads and sessions listen to it.

    handle = start_ui(store, runs, host="127.0.0.1", port=8080)
    print(handle.url)
    ...
    handle.stop()
"""

from __future__ import annotations

import logging
import threading
from dataclasses import dataclass, field

import viser

from typing import TYPE_CHECKING

from app.ui.context import UiContext
from fuzzy.vocabulary import Vocabulary
from soccer.config import GameConfig

if TYPE_CHECKING:
    from app.runs import RunManager
    from app.store import Store
    from app.ui.session import Session

log = logging.getLogger(__name__)
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8080
TITLE = "soccer-lab"


class PortBusyError(OSError):
    pass


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
) -> UiHandle:
    """Start the viser server on host:port (PortBusyError if the port is taken: viser would silently
    move to the next one) and give every connecting browser tab its own session. `api_url`: where the
    JSON API answers, for links to the files it serves."""
    from app.ui.session import Session

    context = UiContext(store, runs, vocabulary, game or GameConfig(), api_url=api_url)
    server = viser.ViserServer(host=host, port=port, label=TITLE, verbose=False)
    if server.get_port() != port:
        server.stop()
        raise PortBusyError(f"port {port} on {host} is busy (choose another with --ui-port)")
    handle = UiHandle(server, context)

    @server.on_client_connect
    def _(client: viser.ClientHandle) -> None:
        session = Session(client, context)
        with handle.lock:
            handle.sessions[client.client_id] = session

    @server.on_client_disconnect
    def _(client: viser.ClientHandle) -> None:
        with handle.lock:
            session = handle.sessions.pop(client.client_id, None)
        if session is not None:
            session.close()

    return handle
