"""Issue 36's request probe against the real `soccer-lab serve`: forwarded-for headers believed only from the
proxy `--trusted-proxy` names, the IPv6 loopback served (`--host ::1`), and `next` after joining (the join
page's script, in Chromium) taking the browser only to a path of the app's own site."""

from __future__ import annotations

import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from urllib.parse import quote, unquote, urlsplit

import httpx
import pytest

from tests.app.test_classroom_serve import CHROMIUM, CHROMIUM_ARGS

CODE = "K7PQ2M"


def free_port(host: str = "127.0.0.1") -> int:
    with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET) as probe:
        probe.bind((host, 0))
        return probe.getsockname()[1]


def ipv6_loopback() -> bool:
    try:
        free_port("::1")
        return True
    except OSError:
        return False


def listening(host: str, port: int, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while True:
        try:
            socket.create_connection((host, port), timeout=1).close()
            return
        except OSError:
            assert time.monotonic() < deadline, f"nothing listens on {host} port {port}"
            time.sleep(0.1)


class Serve:
    """`soccer-lab serve` with `options` in its own process, read until it prints its data folder."""

    def __init__(self, folder: Path, *options: str, host: str = "127.0.0.1"):
        self.port = free_port(host)
        arguments = [sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--host", host,
                     "--data-dir", str(folder), "--port", str(self.port), "--ui-port", str(free_port(host)), *options]
        self.process = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.printed = ""
        for line in self.process.stdout:
            self.printed += line
            if " data " in line:
                break
        assert self.process.poll() is None and " data " in self.printed, self.printed
        self.url = f"http://{f'[{host}]' if ':' in host else host}:{self.port}"
        listening(host, self.port)  # serve prints its addresses just before uvicorn listens

    def stop(self) -> None:
        self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(30)
        except subprocess.TimeoutExpired:
            self.process.kill()


def join_attempts_refused_by_rate(serve: Serve, attempts: int) -> int:
    """Wrong-code join attempts, each from a new X-Forwarded-For address: how many the rate limit refused."""
    refused = 0
    with httpx.Client(base_url=serve.url, timeout=60) as client:
        for i in range(attempts):
            response = client.post("/api/class/join", json={"code": "WRONG9", "name": f"guess{i}"},
                                   headers={"X-Forwarded-For": f"198.51.100.{i + 1}"})
            refused += response.status_code == 429
    return refused


def test_forwarded_for_does_not_make_a_new_visitor_per_request(tmp_path):
    serve = Serve(tmp_path, "--class", "--join-code", CODE, "--address", "127.0.0.1")
    try:
        # a wrong code costs ten of a burst of sixty: the seventh from one address waits
        assert join_attempts_refused_by_rate(serve, 12) >= 5
    finally:
        serve.stop()


def test_forwarded_for_is_believed_from_the_trusted_proxy_only(tmp_path):
    serve = Serve(tmp_path, "--class", "--join-code", CODE, "--address", "127.0.0.1", "--trusted-proxy", "127.0.0.1")
    try:
        assert join_attempts_refused_by_rate(serve, 12) == 0  # each address its own visitor, as the proxy says
    finally:
        serve.stop()


def test_trusted_proxy_must_be_an_address(tmp_path):
    result = subprocess.run([sys.executable, "-c", "from soccer_lab.app.cli import main; main()", "serve", "--trusted-proxy",
                             "proxy.example", "--data-dir", str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert result.returncode != 0 and "--trusted-proxy proxy.example" in result.stderr + result.stdout
    assert "Traceback" not in result.stderr


@pytest.mark.skipif(not ipv6_loopback(), reason="this machine has no IPv6 loopback")
def test_serve_on_the_ipv6_loopback(tmp_path):
    serve = Serve(tmp_path, host="::1")
    try:
        assert serve.url in serve.printed  # http://[::1]:PORT
        with httpx.Client(base_url=serve.url, timeout=60) as client:
            assert client.get("/api/server").status_code == 200  # Host: [::1]:PORT
            ui = client.get("/ui/", follow_redirects=False)
            assert ui.status_code == 307 and f"ws://[::1]:" in unquote(ui.headers["location"])
            assert client.get("/api/server", headers={"Host": f"evil@[::1]:{serve.port}"}).status_code == 400
    finally:
        serve.stop()


HOSTILE_NEXTS = ["/%09/evil.example/", "/\t/evil.example/", "//evil.example/", "/\\evil.example/",
                 "\\\\evil.example/", "https:evil.example", "https://evil.example/", "javascript:alert(1)",
                 "/%5Cevil.example/", "/\n/evil.example/", "%2F%2Fevil.example/", " //evil.example/",
                 # dot segments: the path left once they are resolved is "//evil.example/" (the join page followed
                 # the path alone, to another site)
                 "/.//evil.example/", "/..//evil.example/", "/%2e//evil.example/", "/a/..//evil.example/",
                 "/./\\evil.example/"]


@pytest.mark.browser
def test_next_after_joining_stays_on_the_apps_own_site(tmp_path):
    if not Path(CHROMIUM).exists():
        pytest.skip(f"Chromium not installed at {CHROMIUM}")
    from playwright.sync_api import sync_playwright

    serve = Serve(tmp_path, "--class", "--join-code", CODE, "--address", "127.0.0.1")
    try:
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            page = browser.new_context().new_page()
            page.set_default_timeout(120_000)
            page.route(lambda url: urlsplit(url).hostname == "evil.example", lambda route: route.abort())
            # one browser, joining again for each `next`: it keeps one place (renamed), so the rate is its own
            for i, hostile in enumerate([*HOSTILE_NEXTS, "/ui/?pitch=abc"]):
                page.goto(f"{serve.url}/join.html?next={quote(hostile, safe='%')}")
                page.fill("#code", CODE)
                page.fill("#name", f"Pupil {i}")
                page.click("#join button")
                page.wait_for_function("!location.pathname.startsWith('/join.html') "
                                       "|| document.getElementById('join-refusal').textContent")
                landed = page.url
                assert "/join.html" not in landed, (hostile, page.text_content("#join-refusal"))
                assert landed.startswith(f"{serve.url}/"), (hostile, landed)
                if hostile == "/ui/?pitch=abc":
                    assert landed.startswith(f"{serve.url}/ui/"), landed  # a page of the app's own comes back
                else:
                    assert "evil" not in landed, (hostile, landed)
                page.wait_for_timeout(2_500)  # a join and two pages cost about 20 requests of the rate
            browser.close()
    finally:
        serve.stop()
