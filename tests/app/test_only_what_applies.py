"""Only what applies, in headless Chromium against the real `soccer-lab serve` (no classroom mode): no class
element or class request, no console error on any page, counts worded right, and a stopped server says so
in one line. (The classroom side, the teacher's sign-in and the pupils' join page, is in
tests/app/test_classroom_serve.py.) Screenshots go to artifacts/screenshots/."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import httpx
import pytest

from tests.app.test_ui_browser import (CHROMIUM, CHROMIUM_ARGS, SCREENSHOTS, TIMEOUT_MS, dismiss_notifications, field,
                                       free_port)

pytestmark = [
    pytest.mark.browser,
    pytest.mark.skipif(shutil.which(CHROMIUM) is None and not Path(CHROMIUM).exists(),
                       reason=f"Chromium not installed at {CHROMIUM} (scripts/test installs it with apt)"),
]
PAGES = ("/", "/ui/", "/docs", "/join.html")


class Serve:
    """`soccer-lab serve` in a subprocess, as a user starts it."""

    def __init__(self, data_dir: Path):
        self.port = free_port()
        arguments = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--data-dir", str(data_dir),
                     "--port", str(self.port), "--ui-port", str(free_port())]
        self.process = subprocess.Popen(arguments, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.url = f"http://127.0.0.1:{self.port}"
        deadline = time.monotonic() + 180
        while time.monotonic() < deadline and self.process.poll() is None:
            try:
                if httpx.get(f"{self.url}/api/server", timeout=2).status_code == 200:
                    return
            except httpx.HTTPError:
                time.sleep(0.2)
        raise AssertionError("serve did not answer")

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait(30)


@pytest.fixture(scope="module")
def served(tmp_path_factory):
    serve = Serve(tmp_path_factory.mktemp("served"))
    yield serve
    serve.stop()


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield launched
        launched.close()


def watched_page(browser):
    """A page that lists its console errors, uncaught exceptions and answers of 400 and above as it goes."""
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    page.set_default_timeout(TIMEOUT_MS)
    problems: list[str] = []
    requested: list[str] = []
    page.on("console", lambda message: problems.append(f"console {message.type}: {message.text}")
            if message.type == "error" else None)
    page.on("pageerror", lambda error: problems.append(f"exception: {error}"))
    page.on("request", lambda request: requested.append(request.url))
    page.on("response", lambda response: problems.append(f"{response.status} {response.url}")
            if response.status >= 400 else None)
    return page, problems, requested


@pytest.mark.parametrize("path", PAGES)
def test_no_page_logs_a_console_error_or_asks_for_a_missing_file(served, browser, path):
    page, problems, requested = watched_page(browser)
    try:
        page.goto(served.url + path)
        page.wait_for_load_state("networkidle")
        if path == "/ui/":
            page.locator(".game-status").wait_for()
        page.wait_for_timeout(1500)  # late requests and errors of scripts that run after the load
        assert problems == []
        assert not any("/api/class" in url for url in requested)
    finally:
        page.close()


def test_home_shows_no_class_element_outside_classroom_mode(served, browser):
    page, problems, requested = watched_page(browser)
    try:
        page.goto(served.url + "/")
        page.locator("#runs tbody tr").first.wait_for()
        page.wait_for_load_state("networkidle")
        assert page.locator("#class, #class-qr, #class-code").count() == 0
        body = page.locator("body").inner_text()
        assert "join code" not in body and "Students open" not in body
        assert page.locator("img:visible").evaluate_all("images => images.filter(i => !i.naturalWidth).length") == 0
        assert problems == [] and not any("/api/class" in url for url in requested)
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SCREENSHOTS / "home-without-class.png"))
    finally:
        page.close()


def test_join_page_outside_classroom_mode_shows_no_teacher_card(served, browser):
    page, problems, _ = watched_page(browser)
    try:
        page.goto(served.url + "/join.html")
        page.wait_for_load_state("networkidle")
        assert not page.locator("#teacher").is_visible()
        assert "teacher" not in page.locator("main").inner_text().lower()
        assert problems == []
    finally:
        page.close()


def test_one_error_and_one_rule_are_worded_in_the_singular(served, browser):
    page, problems, _ = watched_page(browser)
    try:
        page.goto(served.url + "/ui/")
        page.locator(".game-status").wait_for()
        dismiss_notifications(page)
        page.get_by_role("tab", name="Rules").click()
        rules = field(page, "Rules", "textarea")
        rules.fill("if Ball is Nearish then Turn Left")
        page.get_by_role("button", name="Apply").click()
        page.get_by_text("1 error; nothing applied").wait_for()
        rules.fill("if Ball is not VeryFar then Turn Right")
        page.get_by_role("button", name="Apply").click()
        page.locator(".rules-on-pitch", has_text=re.compile(r"\(1 rule\)")).wait_for()
        assert "error(s)" not in page.content() and "(1 rules)" not in page.content()
    finally:
        page.close()


def test_stopped_server_is_said_in_one_line(tmp_path, browser):
    serve = Serve(tmp_path)
    page, _, _ = watched_page(browser)
    try:
        page.goto(serve.url + "/ui/")
        page.locator(".game-status").wait_for()
        notice = page.locator("#server-stopped")
        assert not notice.is_visible()
        page.wait_for_timeout(4000)  # a check while the server runs leaves it hidden
        assert not notice.is_visible()
        serve.stop()
        notice.wait_for(state="visible", timeout=15_000)
        assert notice.inner_text().strip() == ("The soccer-lab server has stopped: start it again (soccer-lab serve), "
                                               "then reload this page.")
        assert notice.bounding_box()["height"] < 60  # one line at 1280 px
        SCREENSHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(SCREENSHOTS / "ui-server-stopped.png"))
    finally:
        page.close()
        serve.stop()
