"""The app's UI page carries the projector view's key (viser has no keys of its own)."""

from __future__ import annotations

from fastapi import FastAPI
from fastapi.testclient import TestClient

from soccer_lab.app.web.api.ui_page import ui_router
from soccer_lab.app.web.ui.projector import LEAVE_LABEL, PROJECTOR_KEY_SCRIPT, TOGGLE_LABEL


def test_the_ui_page_has_the_projector_key():
    app = FastAPI()
    app.include_router(ui_router("ws://127.0.0.1:8080"))
    page = TestClient(app, base_url="http://127.0.0.1:8000").get("/ui/").text
    script = f"<script>{PROJECTOR_KEY_SCRIPT}</script>"
    assert script in page and page.index(script) < page.index("</body>")
    assert TOGGLE_LABEL in PROJECTOR_KEY_SCRIPT and LEAVE_LABEL in PROJECTOR_KEY_SCRIPT
