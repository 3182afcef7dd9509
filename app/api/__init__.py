"""The FastAPI application: the JSON API under /api, its OpenAPI document, the landing page."""

from __future__ import annotations

from pathlib import Path

from fastapi import APIRouter, FastAPI
from fastapi.middleware.cors import CORSMiddleware
from fastapi.staticfiles import StaticFiles

from app.api.errors import MAX_BODY_BYTES, BodySizeLimit, install_error_handlers
from app.api.guard import RequestGuard
from app.api.models import ServerInfo
from app.api.routes import experiments, lineage, rulebases, rules, runs, vocabulary
from app.api.ui_page import UI_PATH, ui_router
from app.origins import SiteAddresses
from app.rerun_viewer import viewer_home
from app.runs import RunManager
from app.store import Store

STATIC_DIR = Path(__file__).resolve().parents[2] / "static"
API_PREFIX = "/api"


def create_app(
    store: Store,
    run_manager: RunManager,
    *,
    ui_url: str | None = None,
    viewer_url: str | None = None,
    max_body_bytes: int = MAX_BODY_BYTES,
    site: SiteAddresses | None = None,
    ui_websocket: str | None = None,
) -> FastAPI:
    """The API over `store` and `run_manager`; ui_url/viewer_url are linked from the landing page
    (the rerun viewer also fetches recordings from here, hence CORS for its origin). `site`: the address
    served, whose Host headers and origins are accepted (app/api/guard.py; None: any Host, for tests).
    `ui_websocket`: the UI's websocket (ws://host:ui_port), whose page the app then serves at /ui/."""
    app = FastAPI(
        title="soccer-lab",
        summary="Evolve, inspect and teach fuzzy-rule robot soccer players.",
        version="0.1.0",
    )
    app.state.store = store
    app.state.runs = run_manager
    install_error_handlers(app)
    app.add_middleware(BodySizeLimit, limit=max_body_bytes)
    if viewer_url:
        app.add_middleware(CORSMiddleware, allow_origins=[viewer_url.rstrip("/")], allow_methods=["GET"])
    app.add_middleware(RequestGuard, site=site)  # outermost: checked before anything else runs

    api = APIRouter(prefix=API_PREFIX)
    for module in (vocabulary, rulebases, rules, runs, lineage, experiments):
        api.include_router(module.router)

    @api.get("/server", tags=["server"], summary="Addresses of the UI, the rerun viewer and the API docs")
    def server() -> ServerInfo:
        return ServerInfo(ui=ui_url, viewer=viewer_url, viewer_home=viewer_home(viewer_url) if viewer_url else None,
                          docs=app.docs_url or "")

    app.include_router(api)
    if ui_websocket:
        app.include_router(ui_router(ui_websocket))
    app.mount("/", StaticFiles(directory=STATIC_DIR, html=True), name="static")
    return app
