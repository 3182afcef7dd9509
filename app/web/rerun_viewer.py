"""rerun's web viewer, served by the app itself at /viewer/ (one address, behind the app's checks, offline).

The viewer is three static files (a page, a script and a WebAssembly module) that the rerun CLI of the
installed rerun-sdk embeds and serves with `--serve-web`. Run as a server of its own, it was one more port
to guard, a child process to stop, and its page fetched a font from the internet (a failing request on a
school network). So `viewer_files` runs that CLI once per rerun version, on a loopback port of the system's
choosing, copies the files into the data folder and stops it; the page is kept without its font links (its
own CSS falls back to the system's fonts). The app then serves the folder at VIEWER_PATH, and a recording
opens with `recording_link`, from the same address: no cross-origin request either.

The viewer's welcome screen links to rerun's online examples, which a machine without internet cannot load;
its own query parameter `hide_welcome_screen` turns that screen off. The viewer also posts usage telemetry and
asks for rerun's latest release, with no option to stop either from the page: the kept page starts with a
script that refuses every fetch to another site before it leaves the browser (OFFLINE_SCRIPT).
"""

from __future__ import annotations

import os
import re
import shutil
import socket
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path
from urllib.parse import quote

from soccer_lab.soccer.rcss.servers import die_with_parent

CLI_PATH_VARIABLE = "RERUN_CLI_PATH"  # as rerun itself honours
VIEWER_PATH = "/viewer/"
FILES = ("index.html", "re_viewer.js", "re_viewer_bg.wasm", "favicon.ico", "apple-touch-icon.png")
START_TIMEOUT_SECONDS = 30.0
POLL_SECONDS = 0.05
WITHOUT_WELCOME_SCREEN = "hide_welcome_screen"  # the web viewer's own query parameter
# The page's links to a font service (a preconnect, the stylesheet itself): dropped, so nothing is fetched.
FONT_LINKS = re.compile(r"<link\b[^>]*\bhref=\"https?://fonts\.(?:googleapis|gstatic)\.com[^>]*>\s*", re.S)
# Put first in the page's <head>: fetches to the app's own address go on, all others fail at once (as offline).
OFFLINE_SCRIPT = """<script>
(() => {
  const fetchHere = window.fetch.bind(window);
  window.fetch = (resource, options) => {
    const url = new URL(resource instanceof Request ? resource.url : String(resource), location.href);
    return url.origin === location.origin ? fetchHere(resource, options)
      : Promise.reject(new TypeError("soccer-lab serves rerun's viewer offline: " + url.origin + " is not asked"));
  };
})();
</script>
"""
PAGE_EDITS = 2  # bumped whenever the edits above change, so that pages kept by an older soccer-lab are made again


class RerunViewerError(RuntimeError):
    """The viewer's files cannot be had: one line for the user."""


def rerun_cli_path() -> Path:
    explicit = os.environ.get(CLI_PATH_VARIABLE)
    if explicit:
        return Path(explicit)
    import rerun_cli

    return Path(rerun_cli.__file__).parent / "rerun"


def rerun_version() -> str:
    from importlib.metadata import version

    return version("rerun-sdk")


def viewer_home(api_url: str) -> str:
    """Where to open the viewer: its page without the welcome screen and its example links."""
    return f"{api_url.rstrip('/')}{VIEWER_PATH}?{WITHOUT_WELCOME_SCREEN}"


def recording_link(api_url: str, recording_url: str) -> str:
    """The viewer opening one recording (an address the API serves)."""
    return f"{viewer_home(api_url)}&url={quote(recording_url, safe=':/')}"


def viewer_files(cache: Path) -> Path:
    """The folder of the installed rerun's web viewer files (made under `cache` on first use, for each rerun
    version). RerunViewerError when the rerun CLI is missing or does not serve them."""
    folder = cache / f"{rerun_version()}-page{PAGE_EDITS}"
    if all((folder / name).is_file() for name in FILES):
        return folder
    try:
        cache.mkdir(parents=True, exist_ok=True)
        fetched = Path(tempfile.mkdtemp(prefix="fetching-", dir=cache))
    except OSError as exc:
        raise RerunViewerError(f"cannot write rerun's viewer files into {cache}: {exc.strerror or exc}") from None
    try:
        _fetch(fetched)
        shutil.rmtree(folder, ignore_errors=True)
        fetched.rename(folder)
    except OSError as exc:  # another serve made the folder meanwhile: use theirs
        if not all((folder / name).is_file() for name in FILES):
            raise RerunViewerError(f"cannot write rerun's viewer files into {cache}: {exc.strerror or exc}") from None
    finally:
        shutil.rmtree(fetched, ignore_errors=True)
    return folder


def offline_page(page: str) -> str:
    """rerun's viewer page that asks nothing of the internet: no font links, other sites' fetches refused."""
    page = FONT_LINKS.sub("", page)
    head = re.search(r"<head[^>]*>", page)
    if head is None:
        raise RerunViewerError("rerun's viewer page has no <head>: this rerun-sdk is not one soccer-lab knows")
    return page[:head.end()] + "\n" + OFFLINE_SCRIPT + page[head.end():]


def _fetch(into: Path) -> None:
    cli = rerun_cli_path()
    if not cli.is_file():
        raise RerunViewerError(f"rerun's viewer program is missing at {cli} (reinstall rerun-sdk)")
    port = _free_port()
    command = [str(cli), "--serve-web", "--bind", "127.0.0.1", "--web-viewer-port", str(port), "--port", "0"]
    with open(into / "rerun-cli.log", "wb") as log:
        process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=log, stderr=log,
                                   preexec_fn=die_with_parent(os.getpid()))
    try:
        _wait_until_served(process, port)
        for name in FILES:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/{name}", timeout=START_TIMEOUT_SECONDS) as answer:
                content = answer.read()
            if name == "index.html":
                content = offline_page(content.decode("utf-8")).encode("utf-8")
            (into / name).write_bytes(content)
    except OSError as exc:
        raise RerunViewerError(f"rerun's viewer did not give its files: {exc}") from None
    finally:
        process.terminate()
        try:
            process.wait(5)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
        (into / "rerun-cli.log").unlink(missing_ok=True)


def _wait_until_served(process: subprocess.Popen, port: int) -> None:
    deadline = time.monotonic() + START_TIMEOUT_SECONDS
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RerunViewerError(f"rerun's viewer program ended at start (exit status {process.returncode})")
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=POLL_SECONDS):
                return
        except OSError:
            time.sleep(POLL_SECONDS)
    raise RerunViewerError(f"rerun's viewer program did not answer within {START_TIMEOUT_SECONDS:.0f} s")


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]
