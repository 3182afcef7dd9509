"""The real `soccer-lab serve --class`, on this machine's network address (not 127.0.0.1), as a class meets it:
what it prints, where it listens, every page and the UI's websocket refused without the join code (and with
a wrong one, or from another site), a student's tabs bounded, and in Chromium: the join page, the home
page's QR code, the Class tab where a name typed as HTML stays text, a round's table for everyone, and a
link to a pitch opened by another browser. Screenshots go to artifacts/screenshots/ to look at; the teaching
guide's pictures come from scripts/screenshots, with pupils' names a class would type."""

from __future__ import annotations

import asyncio
import queue
import re
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import httpx
import pytest
import viser
import websockets

from tests.app.test_serve_bind import listening_addresses, wait_for
from tests.app.test_ui_browser import field

CODE = "K7PQ2M"
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
SCREENSHOTS = Path(__file__).resolve().parents[2] / "artifacts" / "screenshots"
TIMEOUT_MS = 180_000  # a shared, busy machine (serve took minutes to start under a load average of 50)
INJECTED = "<img src=x onerror=window.pwned=1>"


def network_address() -> str | None:
    """This machine's address on its network (the interface of the default route), if it has one."""
    from soccer_lab.app.web.classroom.address import lan_address

    address = lan_address()
    return None if address.startswith("127.") else address


ADDRESS = network_address()
pytestmark = pytest.mark.skipif(ADDRESS is None, reason="this machine has no network address besides 127.0.0.1 "
                                                        "(classroom mode serves a local network)")


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


class Served:
    """`serve --class` in a subprocess; its printed lines read as they come."""

    def __init__(self, folder: Path):
        self.port, self.ui_port = free_port(), free_port()
        arguments = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--class",
                     "--host", ADDRESS, "--join-code", CODE, "--data-dir", str(folder), "--port", str(self.port),
                     "--ui-port", str(self.ui_port)]
        self.process = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.lines: queue.Queue[str] = queue.Queue()
        self.printed: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()
        self.teacher_token = self._wait_for(r"teacher token\s+(\S+)").group(1)
        self._wait_for(r"  data ")
        self.url = f"http://{ADDRESS}:{self.port}"

    def _read(self) -> None:
        for line in self.process.stdout:
            self.lines.put(line)

    def _wait_for(self, pattern: str, timeout: float = 900.0) -> re.Match:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                line = self.lines.get(timeout=0.5)
            except queue.Empty:
                assert self.process.poll() is None, "".join(self.printed)
                continue
            self.printed.append(line)
            if match := re.search(pattern, line):
                return match
        raise AssertionError(f"serve never printed {pattern!r}: {''.join(self.printed)}")

    def stop(self) -> None:
        self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(30)
        except subprocess.TimeoutExpired:
            self.process.kill()


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    served = Served(tmp_path_factory.mktemp("class"))
    yield served
    served.stop()


def join(served: Served, name: str) -> httpx.Client:
    client = httpx.Client(base_url=served.url, timeout=30)
    response = client.post("/api/class/join", json={"code": CODE, "name": name})
    assert response.status_code == 200, response.text
    return client


def teacher(served: Served) -> httpx.Client:
    client = httpx.Client(base_url=served.url, timeout=30)
    assert client.post("/api/class/teacher", json={"token": served.teacher_token}).status_code == 200
    return client


def test_it_prints_the_address_code_and_token_and_listens_where_it_says(served):
    printed = "".join(served.printed)
    assert f"students open   {served.url}/" in printed and f"join code       {CODE}" in printed
    assert len(served.teacher_token) >= 20
    # serve prints its addresses as it starts them: the API listens a moment after the lines are out
    for port in (served.port, served.ui_port):
        assert wait_for(lambda: listening_addresses(port)) == {ADDRESS}


def test_nothing_is_answered_without_the_code(served):
    with httpx.Client(base_url=served.url, timeout=30) as stranger:
        for path in ("/api/rulebases", "/api/runs", "/api/class", "/api/class/rounds", "/api/class/qr.svg",
                     "/api/vocabulary"):
            response = stranger.get(path)
            assert response.status_code == 401 and "join the class first" in response.text, path
        for page in ("/", "/ui/", "/docs", "/openapi.json", "/viewer/"):  # to the join page
            assert stranger.get(page).status_code == 303, page
        stranger.cookies.set("soccer_lab_class", "WRONG1")
        assert stranger.get("/api/rulebases").status_code == 401
        assert stranger.post("/api/rulebases", json={"name": "x", "text": "if Ball is At then Kick Straight High"}
                             ).status_code == 401
        foreign = stranger.get("/join.html", headers={"Host": f"evil.example:{served.port}"})
        assert foreign.status_code == 400  # DNS rebinding: a name that is not the class's address


async def first_frame(served: Served, cookies: str | None, origin: str | None) -> tuple[str, object]:
    headers = {"Cookie": cookies} if cookies else {}
    async with websockets.connect(f"ws://{ADDRESS}:{served.ui_port}", origin=origin, additional_headers=headers,
                                  subprotocols=[f"viser-v{viser.__version__}"], open_timeout=60) as connection:
        try:
            return "message", len(await asyncio.wait_for(connection.recv(), 60))
        except websockets.ConnectionClosed as closed:
            return "closed", (closed.rcvd.code, closed.rcvd.reason)


def cookie_header(client: httpx.Client) -> str:
    return "; ".join(f"{name}={value}" for name, value in client.cookies.items())


def test_the_ui_websocket_needs_the_code_and_the_apps_own_page(served):
    ada = join(served, "Ada")
    own = served.url
    kind, what = asyncio.run(first_frame(served, None, own))
    assert kind == "closed" and what[0] == 1008 and "join the class first" in what[1]
    kind, what = asyncio.run(first_frame(served, f"soccer_lab_class=WRONG1; {cookie_header(ada)}".replace(
        f"soccer_lab_class={CODE}", "x=y"), own))
    assert kind == "closed" and what[0] == 1008
    kind, what = asyncio.run(first_frame(served, cookie_header(ada), "http://evil.example"))
    assert kind == "closed" and what[0] == 1008 and "not this app's own page" in what[1]
    kind, size = asyncio.run(first_frame(served, cookie_header(ada), own))
    assert kind == "message" and size > 0


def test_a_students_tabs_are_bounded(served):
    from soccer_lab.app.web.ui import MAX_TABS_PER_STUDENT

    ben = join(served, "Ben")

    async def open_tabs() -> tuple[str, object]:
        opened = []
        try:
            for _ in range(MAX_TABS_PER_STUDENT):
                connection = await websockets.connect(
                    f"ws://{ADDRESS}:{served.ui_port}", origin=served.url, open_timeout=60,
                    additional_headers={"Cookie": cookie_header(ben)}, subprotocols=[f"viser-v{viser.__version__}"])
                opened.append(connection)
                await asyncio.wait_for(connection.recv(), 60)  # admitted: its session is being built
            return await first_frame(served, cookie_header(ben), served.url)
        finally:
            for connection in opened:
                await connection.close()

    kind, what = asyncio.run(open_tabs())
    assert kind == "closed" and what[0] == 1008 and f"{MAX_TABS_PER_STUDENT} tabs of yours" in what[1]


# ---- in Chromium --------------------------------------------------------------------------
@pytest.fixture(scope="module")
def browser():
    if shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists():
        pytest.skip(f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)")
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield launched
        launched.close()


def new_page(browser, width: int = 1600, height: int = 900):
    page = browser.new_context(viewport={"width": width, "height": height}).new_page()
    page.set_default_timeout(TIMEOUT_MS)
    return page


def join_in_browser(page, served: Served, name: str, next_path: str = "/") -> None:
    page.goto(f"{served.url}{next_path}")
    page.wait_for_url(re.compile(r"/join\.html"))
    page.fill("#code", CODE.lower())
    page.fill("#name", name)
    page.click("#join button")


def open_class_tab(page) -> None:
    page.locator(".game-status").wait_for()
    close = page.locator(".mantine-Notification-closeButton")
    for i in range(close.count()):
        close.nth(i).click()
    page.get_by_role("tab", name="Class").click()


@pytest.mark.browser
def test_a_class_in_the_browser(served, browser):
    from playwright.sync_api import expect

    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    # The teacher opens the printed sign-in link (the token in the fragment, never sent to a server) and lands
    # signed in on the home page, the token nowhere on the projected screen
    desk = new_page(browser, 1280, 800)
    desk.goto(f"{served.url}/join.html#teacher=NOT{served.teacher_token}")  # mistyped: refused, the form empty
    expect(desk.locator("#teacher-refusal")).not_to_be_empty()
    assert desk.url == f"{served.url}/join.html#teacher" and desk.locator("#token").input_value() == ""
    assert served.teacher_token not in desk.content()
    desk.goto(f"{served.url}/join.html#teacher={served.teacher_token}")
    desk.wait_for_url(f"{served.url}/")
    assert served.teacher_token not in desk.url + desk.content()
    expect(desk.locator("#class-code")).to_have_text(CODE)
    expect(desk.locator("#class-address")).to_have_text(served.url)
    expect(desk.locator("#class-you")).to_have_text("You are the teacher.")
    qr = desk.locator("#class-qr")
    expect(qr).to_be_visible()
    # the SVG drawn by the app, not a broken image (visible comes before loaded: wait for it to load)
    desk.wait_for_function("() => document.querySelector('#class-qr').complete")
    assert qr.evaluate("image => image.naturalWidth") > 100
    desk.screenshot(path=str(SCREENSHOTS / "classroom-home.png"))

    # A pupil: no teacher card; a wrong code says so in one line; the right one lands on the home page, the name
    # as text
    pupil = new_page(browser, 1280, 800)
    pupil.goto(f"{served.url}/")
    pupil.wait_for_url(re.compile(r"/join\.html"))
    expect(pupil.locator("#teacher")).to_be_hidden()
    assert "teacher" not in pupil.locator("main").inner_text().lower()
    pupil.fill("#code", "WRONG1")
    pupil.fill("#name", INJECTED)
    pupil.click("#join button")
    expect(pupil.locator("#join-refusal")).to_contain_text("not this class's join code")
    pupil.screenshot(path=str(SCREENSHOTS / "classroom-join.png"))
    pupil.fill("#code", CODE)
    pupil.click("#join button")
    pupil.wait_for_url(f"{served.url}/")
    expect(pupil.locator("#class-you")).to_have_text(f"You are {INJECTED}.")

    # Their UI: the Class tab, their entry under their name, shown as text
    pupil.goto(f"{served.url}/ui/")
    open_class_tab(pupil)
    pupil.get_by_role("button", name="Enter the rules on my pitch").click()
    expect(pupil.locator(".class-message")).to_contain_text("Entered as")
    expect(pupil.locator(".class-entries")).to_contain_text(INJECTED)
    expect(pupil.locator(".class-entries")).to_contain_text("1 entry")

    # The teacher enters the demo (the Entry name left empty: the rules' own name), starts a round; everyone
    # sees the table
    desk.goto(f"{served.url}/ui/")
    open_class_tab(desk)
    # it held "GA best", a real-looking name that would have named the demo's entry: empty, its label says why
    entry_name = field(desk, "Entry name (empty: the rules' name)", "input")
    assert entry_name.input_value() == ""
    desk.get_by_role("button", name="Enter the rules on my pitch").click()
    expect(desk.locator(".class-message")).to_contain_text("Entered as “demo (built in)”")
    expect(desk.locator(".class-entries")).to_contain_text("demo (built in)")
    expect(desk.locator(".class-entries")).to_contain_text("2 entries")
    desk.get_by_role("button", name="Start a round").click()
    expect(desk.locator(".class-table tbody tr")).to_have_count(2, timeout=TIMEOUT_MS)
    expect(pupil.locator(".class-table tbody tr")).to_have_count(2, timeout=TIMEOUT_MS)
    expect(pupil.locator(".class-table")).to_contain_text(INJECTED)
    assert pupil.evaluate("window.pwned") is None and desk.evaluate("window.pwned") is None
    assert pupil.locator(".class-table img").count() == 0  # the name stayed text
    pupil.get_by_role("button", name="Watch this game").click()
    expect(pupil.locator(".class-message")).to_contain_text("Watching")
    pupil.screenshot(path=str(SCREENSHOTS / "classroom-round.png"))

    # A link to the pitch, opened by another pupil's browser: the same rules and seed
    pupil.get_by_role("tab", name="Play").click()
    pupil.get_by_role("button", name="Pause").click()
    pupil.get_by_role("button", name="Link to this pitch").click()
    link_field = pupil.locator("xpath=//label[normalize-space(text())='Link (select, copy)']"
                               "/ancestor::div[contains(@class,'mantine-Flex-root')][1]//input").first
    expect(link_field).to_have_value(re.compile(r"/ui/\?pitch="))
    link = link_field.input_value()
    assert link.startswith(f"{served.url}/ui/?pitch=")
    tick = pupil.locator(".game-status").get_attribute("data-tick")
    friend = new_page(browser)
    join_in_browser(friend, served, "Cai", next_path=link.removeprefix(served.url))
    friend.wait_for_url(re.compile(r"/ui/\?pitch="))
    friend.locator(".game-status").wait_for()
    expect(friend.locator(".game-status")).to_have_attribute("data-tick", tick)
    assert friend.evaluate("window.pwned") is None

    # A damaged link: one line saying so, not a broken page
    friend.goto(link[:-12] + "AAAA")
    expect(friend.locator(".link-refused")).to_contain_text("This link could not be opened")
