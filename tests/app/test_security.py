"""No web page but the app's own can drive it (issue 25): a foreign Host (DNS rebinding) refused on every
route, a form POST from another site refused and nothing changed, a foreign Origin refused, pages that no
site can frame; the UI's websocket refused to a foreign origin or Host before it is sent anything."""

from __future__ import annotations

import asyncio
import socket

import pytest
import viser
import websockets
from fastapi.testclient import TestClient

from soccer_lab.app.web.api import create_app
from soccer_lab.app.web.origins import SiteAddresses
from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import Store

PORT = 8000
OWN = f"http://127.0.0.1:{PORT}"
SITE = SiteAddresses.of("127.0.0.1", {PORT}, {PORT})
RULES = {"name": "kept", "text": "if Ball is At then Kick Straight High"}


@pytest.fixture
def client(tmp_path):
    store = Store(tmp_path / DATABASE_FILE)
    runs = RunManager(store, tmp_path)
    app = create_app(store, runs, site=SITE, ui_websocket="ws://127.0.0.1:8080")
    with TestClient(app, base_url=OWN, raise_server_exceptions=False) as client:
        yield client
    runs.shutdown()
    store.close()


def saved(client) -> int:
    response = client.post("/api/rulebases", json=RULES, headers={"Origin": OWN})
    assert response.status_code == 201, response.text
    return response.json()["id"]


@pytest.mark.parametrize("host", ["evil.example", f"evil.example:{PORT}", "127.0.0.1:9999", "127.0.0.2:8000", ""])
def test_a_foreign_host_is_refused_on_every_route(client, host):
    for method, path in (("GET", "/api/rulebases"), ("GET", "/"), ("GET", "/ui/"), ("POST", "/api/rules/parse")):
        response = client.request(method, path, headers={"Host": host}, json={"text": ""})
        assert response.status_code == 400, (method, path)
        assert "is not this app's address" in response.json()["detail"]


def test_the_addresses_aliases_are_accepted(client):
    for host in (f"127.0.0.1:{PORT}", f"localhost:{PORT}", f"[::1]:{PORT}"):
        assert client.get("/api/rulebases", headers={"Host": host}).status_code == 200, host


def test_a_form_post_from_another_site_is_refused_and_changes_nothing(client):
    rulebase = saved(client)
    run = client.post("/api/runs", json={"ga": {"population_size": 4, "max_generations": 1}},
                      headers={"Origin": OWN}).json()
    client.app.state.runs.wait(run["id"], timeout=120)
    # What a plain HTML form on another site sends: a form body, no custom header, its own Origin.
    form = {"Content-Type": "application/x-www-form-urlencoded", "Origin": "http://evil.example",
            "Sec-Fetch-Site": "cross-site"}
    for method, path in (("POST", f"/api/runs/{run['id']}/resume"), ("DELETE", f"/api/rulebases/{rulebase}"),
                         ("POST", "/api/rulebases")):
        response = client.request(method, path, headers=form, content="name=x&text=y")
        assert response.status_code == 403, (path, response.text)
        assert "another site" in response.json()["detail"] or "not this app's own page" in response.json()["detail"]
    # The same form as an old browser sends it (no Origin, no Sec-Fetch-Site): refused for its content type.
    response = client.post(f"/api/runs/{run['id']}/resume", headers={"Content-Type": "text/plain"}, content="x")
    assert response.status_code == 415 and "application/json" in response.json()["detail"]
    assert client.get(f"/api/rulebases/{rulebase}").status_code == 200
    assert client.get(f"/api/runs/{run['id']}").json()["status"] == "finished"


def test_a_foreign_origin_is_refused_even_with_json(client):
    response = client.post("/api/rulebases", json=RULES, headers={"Origin": "http://127.0.0.1:9999"})
    assert response.status_code == 403 and "not this app's own page" in response.json()["detail"]
    response = client.post("/api/rulebases", json=RULES, headers={"Origin": "null"})
    assert response.status_code == 403
    assert client.get("/api/rulebases").json() == []


def test_the_apps_own_requests_pass(client):
    rulebase = saved(client)  # JSON from the app's origin
    # A same-origin page's body-less request (the docs page's "Try it out"): the browser says same-origin.
    deleted = client.delete(f"/api/rulebases/{rulebase}", headers={"Sec-Fetch-Site": "same-origin", "Origin": OWN})
    assert deleted.status_code == 204
    # A script: the custom header instead of a JSON body.
    assert client.post("/api/rules/parse", json={"text": ""}).status_code == 200
    rulebase = saved(client)
    assert client.delete(f"/api/rulebases/{rulebase}", headers={"X-Soccer-Lab": "1"}).status_code == 204


def test_no_site_can_frame_the_pages(client):
    for path in ("/", "/ui/", "/api/server", "/docs"):
        response = client.get(path, follow_redirects=True)
        assert response.headers["x-frame-options"] == "DENY", path
        assert response.headers["content-security-policy"] == "frame-ancestors 'none'", path


def test_the_ui_page_is_served_from_the_apps_address_with_its_websocket(client):
    response = client.get("/ui", follow_redirects=False)
    assert response.status_code == 307 and response.headers["location"] == "/ui/?websocket=ws://127.0.0.1:8080"
    page = client.get("/ui/?websocket=ws://127.0.0.1:8080")
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    # Any other websocket is not the app's: the page is only served pointing at its own.
    assert client.get("/ui/?websocket=ws://evil.example:1", follow_redirects=False).status_code == 307


# ---- the UI's websocket ---------------------------------------------------------------------
def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def ui(tmp_path_factory):
    from soccer_lab.app.web.ui import start_ui

    folder = tmp_path_factory.mktemp("ui")
    store = Store(folder / DATABASE_FILE)
    runs = RunManager(store, folder)
    page_port = free_port()  # where the app serves the UI's page (serve: the API's port)
    handle = start_ui(store, runs, port=free_port(), page_port=page_port)
    yield handle, page_port
    handle.stop()
    runs.shutdown()
    store.close()


async def first_frame(url: str, origin: str | None = None, port: int | None = None) -> tuple[str, object]:
    """What the server does first with a websocket opened like a page of `origin` would (to `port` on this
    machine whatever `url`'s host, whose name the Host header carries): ('message', n bytes) or ('closed',
    (code, reason))."""
    subprotocol = f"viser-v{viser.__version__}"
    direct = {"host": "127.0.0.1", "port": port} if port else {}
    async with websockets.connect(url, origin=origin, subprotocols=[subprotocol], open_timeout=30,
                                  **direct) as connection:
        try:
            message = await asyncio.wait_for(connection.recv(), 30)
            return "message", len(message)
        except websockets.ConnectionClosed as closed:
            return "closed", (closed.rcvd.code, closed.rcvd.reason)


def test_a_foreign_origin_websocket_is_refused_before_anything_is_sent(ui):
    handle, page_port = ui
    url = f"ws://127.0.0.1:{handle.server.get_port()}"
    for origin in ("http://evil.example", f"http://127.0.0.1:{handle.server.get_port()}", "null"):
        kind, what = asyncio.run(first_frame(url, origin=origin))
        assert kind == "closed" and what[0] == 1008 and "not this app's own page" in what[1], origin
    kind, what = asyncio.run(first_frame(url))  # a page that says no origin at all
    assert kind == "closed" and what[0] == 1008
    assert handle.sessions == {}  # no session was built for any of them


def test_a_foreign_host_websocket_is_refused(ui):
    handle, page_port = ui
    port = handle.server.get_port()
    kind, what = asyncio.run(first_frame(f"ws://evil.example:{port}", origin=f"http://127.0.0.1:{page_port}", port=port))
    assert kind == "closed" and what[0] == 1008 and "is not this app's address" in what[1]


def test_the_apps_own_page_gets_the_ui(ui):
    handle, page_port = ui
    url = f"ws://127.0.0.1:{handle.server.get_port()}"
    kind, size = asyncio.run(first_frame(url, origin=f"http://localhost:{page_port}"))
    assert kind == "message" and size > 0
