"""`soccer-lab serve`: the store, the run manager, the viser UI and the FastAPI server (the API, the pages,
rerun's web viewer at /viewer/), started together on checked ports and stopped together. With `classroom`
(serve --class) it listens on the local network and admits only the class (app/web/classroom/)."""

from __future__ import annotations

import errno
import os
import signal
import socket
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Callable

from soccer_lab.app.paths import DATABASE_FILE, DataFolderInUse, DataFolderLock, default_cache_dir

if TYPE_CHECKING:
    from soccer_lab.app.runs.games import ProcessGames, RayGames
    from soccer_lab.app.runs.manager import RunManager

DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8000
DEFAULT_UI_PORT = 8080
VIEWER_FILES = "rerun-web-viewer"  # in the cache folder: the web viewer's files, one folder per rerun version
# Requests still open when serve is told to stop get this long: serve exits within 3 s of Ctrl+C or SIGTERM
GRACEFUL_SHUTDOWN_SECONDS = 1


class ServeError(RuntimeError):
    """The app cannot start (busy port, unusable data folder): one line for the user."""


@dataclass(frozen=True)
class ServeOptions:
    host: str = DEFAULT_HOST
    port: int = DEFAULT_PORT
    ui_port: int = DEFAULT_UI_PORT
    data_dir: Path = Path(".")
    rcssserver: Path | None = None  # the executable rcss runs start their servers from (default: $RCSSSERVER, PATH)
    classroom: bool = False  # classroom mode: the class on the local network, admitted with a join code
    address: str | None = None  # classroom mode: the address students open (default: this machine's LAN address)
    join_code: str | None = None  # classroom mode: the class's join code (default: a new random one)
    ray: bool = False  # classroom mode: the queue's runs play their games on Ray (app/runs/games.py)
    ray_address: str | None = None  # that Ray cluster (default: a local Ray started by serve)
    trusted_proxy: str | None = None  # the one address whose X-Forwarded-For names the visitor (default: none)

    def url(self, port: int) -> str:
        host = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{host}:{port}"


def check_port_free(host: str, port: int, what: str, option: str) -> None:
    """ServeError when `port` is taken, before anything starts (viser would silently move on)."""
    try:
        family = socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)[0][0]
    except socket.gaierror as exc:
        raise ServeError(f"cannot use host {host!r}: {exc.strerror}") from exc
    with socket.socket(family, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as the servers themselves do
        try:
            probe.bind((host, port))
        except OSError as exc:
            if exc.errno == errno.EADDRINUSE:
                raise ServeError(f"port {port} for the {what} is busy: stop what uses it or choose another with {option}")
            raise ServeError(f"cannot listen on {host}:{port} for the {what}: {exc.strerror or exc}") from exc


def check_ports(options: ServeOptions) -> None:
    if options.port == options.ui_port:
        raise ServeError("--port and --ui-port must be two different ports")
    check_port_free(options.host, options.port, "API server", "--port")
    check_port_free(options.host, options.ui_port, "UI", "--ui-port")


def _cleanup_after_sigterm(signum: int, frame: object) -> None:
    """Where uvicorn's re-raised SIGTERM lands once it has shut down: nowhere, so that serve's own cleanup
    runs (the default action would end the process at once, runs still 'running', the viewer orphaned)."""


def serve(options: ServeOptions, echo: Callable[[str], None] = print) -> None:
    """Run everything until Ctrl+C or SIGTERM; runs still going are then marked interrupted (resumable) at
    once, and everything stops within about 3 s."""
    # Imported here: the command's help and its option checks do without the app (FastAPI, viser, rerun).
    import uvicorn

    from soccer_lab.app.web.api import create_app
    from soccer_lab.app.web.api.ui_page import UI_PATH
    from soccer_lab.app.web.origins import SiteAddresses
    from soccer_lab.app.web.rerun_viewer import RerunViewerError, viewer_files, viewer_home
    from soccer_lab.app.runs.manager import MAX_CONCURRENT_RUNS, SHUTDOWN_WAIT_SECONDS, RunManager
    from soccer_lab.app.store import Store
    from soccer_lab.app.web.ui import PortBusyError, start_ui
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.config import GameConfig

    class Server(uvicorn.Server):
        """uvicorn's server, telling `on_exit` as soon as a signal (Ctrl+C, SIGTERM) asks it to stop, and
        `on_listening` once it accepts connections: the addresses are printed only when they answer."""

        def __init__(self, config: uvicorn.Config, on_exit: Callable[[], None], on_listening: Callable[[], None]):
            super().__init__(config)
            self.on_exit = on_exit
            self.on_listening = on_listening

        async def startup(self, sockets: list | None = None) -> None:
            await super().startup(sockets)
            if not self.should_exit:  # it could not bind: uvicorn says why and exits
                self.on_listening()

        def handle_exit(self, sig: int, frame: object) -> None:
            self.on_exit()
            super().handle_exit(sig, frame)

    check_ports(options)
    try:
        options.data_dir.mkdir(parents=True, exist_ok=True)
        # held for the process's life: before the run manager marks runs 'running' as interrupted
        folder_lock = DataFolderLock(options.data_dir, options.url(options.port))
    except DataFolderInUse as exc:
        raise ServeError(str(exc)) from exc
    except OSError as exc:
        raise ServeError(f"cannot create the data folder {options.data_dir}: {exc.strerror or exc}") from exc
    store = Store(options.data_dir / DATABASE_FILE)
    # a class shares the machine: each pupil's run is one process, so as many at once as it has cores
    concurrent = max(MAX_CONCURRENT_RUNS, os.cpu_count() or 1) if options.classroom else MAX_CONCURRENT_RUNS
    runs = RunManager(store, options.data_dir, rcssserver=options.rcssserver, max_concurrent_runs=concurrent,
                      queue_runs=options.classroom)
    try:
        games = _class_games(options, runs)
    except ServeError:
        store.close()
        folder_lock.release()
        raise
    ui = None
    classroom = tournament = None
    site = SiteAddresses.of(options.host, {options.port}, {options.port})
    api_url = options.url(options.port)
    if options.classroom:
        from soccer_lab.app.web.classroom.address import lan_address
        from soccer_lab.app.web.classroom.admission import Classroom, new_join_code, new_teacher_token
        from soccer_lab.app.web.classroom.tournament import Tournament

        address = options.address or lan_address()
        site = SiteAddresses.of(options.host, {options.port}, {options.port}, also=(address,))
        api_url = f"http://{f'[{address}]' if ':' in address else address}:{options.port}"
        classroom = Classroom(store, options.join_code or new_join_code(), new_teacher_token(), api_url)
        runs.student_bounds = lambda settings: classroom.settings.check_student_run(settings)
        tournament = Tournament(store, Vocabulary.default(), GameConfig(), lambda: classroom.settings)
    try:
        try:  # without rerun's viewer the app still serves everything else, and says why
            viewer, viewer_problem = viewer_files(default_cache_dir() / VIEWER_FILES), None
        except RerunViewerError as exc:
            viewer, viewer_problem = None, str(exc)
        try:
            # The UI's page is served from the API's address (no other site can frame it there), and only
            # that page may open the UI's websocket (docs/design.md, "Security")
            ui = start_ui(store, runs, options.host, options.ui_port, api_url=api_url, page_port=options.port,
                          site=site, classroom=classroom, tournament=tournament, viewer_problem=viewer_problem)
        except PortBusyError as exc:  # a port taken between the check and now
            raise ServeError(str(exc)) from exc
        ui_url = f"{api_url}{UI_PATH}"
        # rerun's viewer is served by the app (/viewer/): in classroom mode behind the class's code like the rest
        app = create_app(store, runs, ui_url=ui_url, api_url=api_url, viewer_files=viewer, site=site,
                         ui_websocket=options.url(options.ui_port).replace("http://", "ws://", 1), classroom=classroom,
                         tournament=tournament)
        viewer_line = viewer_home(api_url) if viewer else "not available: " + viewer_problem

        def announce() -> None:
            if classroom is not None:
                echo("soccer-lab classroom is running (Ctrl+C to stop)")
                echo(f"  students open   {api_url}/   (the home page shows its QR code)")
                echo(f"  join code       {classroom.join_code}")
                echo(f"  teacher token   {classroom.teacher_token}   (yours alone: it starts rounds, removes entries)")
                echo(f"  teacher sign-in {api_url}/join.html#teacher={classroom.teacher_token}")
                echo(f"  rerun viewer    {viewer_line}")
                echo(f"  data            {options.data_dir.resolve()}")
                echo(f"  runs            {runs.max_concurrent_runs} at once{' on Ray' if options.ray else ''}, "
                     "the others queued in turn")
            else:
                echo("soccer-lab is running (Ctrl+C to stop)")
                echo(f"  home          {api_url}/")
                echo(f"  UI            {ui_url}")
                echo(f"  API docs      {api_url}/docs   (the JSON API answers under /api/)")
                echo(f"  rerun viewer  {viewer_line}")
                echo(f"  data          {options.data_dir.resolve()}")
            if runs.interrupted_at_start:
                listed = ", ".join(map(str, runs.interrupted_at_start))
                echo(f"  runs cut off last time, now interrupted and resumable: {listed}")

        # uvicorn believes X-Forwarded-For from loopback by default: a script could then be any visitor it
        # names (a new rate limit per request); only a proxy the user names is believed
        config = uvicorn.Config(app, host=options.host, port=options.port, log_level="warning",
                                timeout_graceful_shutdown=GRACEFUL_SHUTDOWN_SECONDS,
                                proxy_headers=options.trusted_proxy is not None,
                                forwarded_allow_ips=options.trusted_proxy or "")
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGTERM, _cleanup_after_sigterm)
        Server(config, on_exit=runs.interrupt_all, on_listening=announce).run()
    finally:
        runs.shutdown()
        if tournament is not None:
            tournament.close(SHUTDOWN_WAIT_SECONDS)
        if games is not None:
            games.__exit__(None, None, None)
        if ui is not None:
            ui.stop()
        store.close()
        folder_lock.release()


def _class_games(options: ServeOptions, runs: "RunManager") -> "ProcessGames | RayGames | None":
    """Classroom mode: where the runs play their games (app/runs/games.py), one run per core of this machine
    or, with `ray`, per CPU of the Ray cluster; ServeError (one line) when Ray is missing or unreachable."""
    if not options.classroom:
        return None
    from soccer_lab.app.experiment.executors import ExecutorError
    from soccer_lab.app.runs.games import ProcessGames, RayGames

    games = RayGames(options.ray_address) if options.ray else ProcessGames(runs.max_concurrent_runs)
    try:
        games.__enter__()
    except ExecutorError as exc:
        raise ServeError(str(exc)) from None
    runs.remote_games = games
    runs.max_concurrent_runs = games.cores()
    return games
