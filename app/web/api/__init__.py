"""The FastAPI application: the JSON API under /api, its OpenAPI document, the landing page."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from fastapi import APIRouter, FastAPI
from fastapi_offline import FastAPIOffline
from fastapi.staticfiles import StaticFiles

from soccer_lab.app.web.api.docs_pages import install_redoc
from soccer_lab.app.web.api.errors import MAX_BODY_BYTES, BodyGuard, install_error_handlers
from soccer_lab.app.web.api.guard import RequestGuard
from soccer_lab.app.web.api.models import ServerInfo
from soccer_lab.app.web.api.routes import classroom as classroom_routes
from soccer_lab.app.web.api.routes import experiments, knockouts, lineage, rulebases, rules, runs, vocabulary
from soccer_lab.app.web.api.ui_page import UI_PATH, ui_router
from soccer_lab.app.web.origins import SiteAddresses
from soccer_lab.app.web.rerun_viewer import VIEWER_PATH, viewer_home
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import Store

if TYPE_CHECKING:
    from soccer_lab.app.web.classroom.admission import Classroom
    from soccer_lab.app.web.classroom.tournament import Tournament

STATIC_DIR = Path(__file__).resolve().parents[3] / "static"  # static/ beside app/, as soccer_lab/static once installed
API_PREFIX = "/api"
DOCS_URL = "/docs"  # fastapi-offline's Swagger UI (FastAPI's own docs_url is off)


def create_app(
    store: Store,
    run_manager: RunManager,
    *,
    ui_url: str | None = None,
    api_url: str | None = None,
    viewer_files: Path | None = None,
    max_body_bytes: int = MAX_BODY_BYTES,
    site: SiteAddresses | None = None,
    ui_websocket: str | None = None,
    classroom: Classroom | None = None,
    tournament: Tournament | None = None,
) -> FastAPI:
    """The API over `store` and `run_manager`; `ui_url` is linked from the landing page. With `viewer_files`
    (app/web/rerun_viewer.py) rerun's web viewer is served at /viewer/, at `api_url`'s address. `site`: the address
    served, whose Host headers and origins are accepted (app/web/api/guard.py; None: any Host, for tests).
    `ui_websocket`: the UI's websocket (ws://host:ui_port), whose page the app then serves at /ui/.
    `classroom` and `tournament` (classroom mode): every request must come from the class (app/web/api/guard.py),
    and /api/class serves the class's tournament.
    The interactive docs (/docs, /redoc) come whole from here: a school network without internet shows
    them too (docs_pages.py)."""
    app = FastAPIOffline(
        redoc_url=None,  # docs_pages.install_redoc: fastapi-offline's ReDoc still fetches its maker's logo
        title="soccer-lab",
        summary="Evolve, inspect and teach fuzzy-rule robot soccer players.",
        version="0.1.0",
    )
    app.state.store = store
    app.state.runs = run_manager
    app.state.classroom = classroom
    app.state.tournament = tournament
    install_redoc(app)
    install_error_handlers(app)
    app.add_middleware(BodyGuard, limit=max_body_bytes)
    app.add_middleware(RequestGuard, site=site, classroom=classroom)  # outermost: checked before anything else

    api = APIRouter(prefix=API_PREFIX)
    for module in (vocabulary, rulebases, rules, runs, lineage, experiments):
        api.include_router(module.router)
    if classroom is not None:
        api.include_router(classroom_routes.router)
        api.include_router(knockouts.router)

    @api.get("/server", tags=["server"], summary="Addresses of the UI, the rerun viewer and the API docs")
    def server() -> ServerInfo:
        viewer = viewer_files is not None and api_url is not None
        return ServerInfo(ui=ui_url, viewer=f"{api_url}{VIEWER_PATH}" if viewer else None,
                          viewer_home=viewer_home(api_url) if viewer else None, docs=DOCS_URL,
                          classroom=classroom is not None)

    app.include_router(api)
    if ui_websocket:
        app.include_router(ui_router(ui_websocket))
    if viewer_files is not None:
        app.mount(VIEWER_PATH.rstrip("/"), StaticFiles(directory=viewer_files, html=True), name="viewer")
    app.mount("/", StaticFiles(directory=STATIC_DIR, html=True), name="static")
    return app
